"""Figs 5-6: select each figure's variables from the radiation dataset, write and draw them (one job for both)."""

import sys

import matplotlib.pyplot as plt

from rail.plotting import report
from rail.setup import io
from rail.studies import datasets
from rail.studies.validity import NOT_USED, model_attributes


def main(figures, config, in_path, data_paths, figure_paths):
    with io.open_intermediate(in_path) as rad:
        radiation = rad.load()
    for nn, data_path, figure_path in zip(figures, data_paths, figure_paths, strict=True):
        ds = getattr(datasets, f"fig{nn}")(radiation)
        ds = ds.assign_attrs(model_attributes(NOT_USED, NOT_USED))  # the half-space alone: no wear, no wheel/rail contact
        ds = io.finalize(ds, config, title=f"Figure {int(nn)}", source=f"rail.studies.datasets.fig{nn}")
        io.write_netcdf(ds, data_path)
        fig = getattr(report, f"fig{nn}")(ds)
        fig.savefig(figure_path, dpi=150)
        plt.close(fig)


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    main(snakemake.params.figures, snakemake.params.cfg, snakemake.input[0], snakemake.output.data, snakemake.output.figure)  # noqa: F821
