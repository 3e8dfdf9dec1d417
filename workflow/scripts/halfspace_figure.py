"""Figs 2-4: compute each figure's dataset with rail, write it and draw it (one job for the three)."""

import sys

import matplotlib.pyplot as plt

from rail.plotting import report
from rail.setup import build, io
from rail.studies import datasets
from rail.studies.validity import NOT_USED, model_attributes


def main(figures, config, data_paths, figure_paths):
    material = build.elastic(config)
    fig_settings = build.halfspace_figures(config)
    numerics = build.halfspace_numerics(config)
    builders = {
        "02": lambda: datasets.fig02(material, fig_settings),
        "03": lambda: datasets.fig03(material, fig_settings),
        "04": lambda: datasets.fig04(material, fig_settings, numerics),
    }
    for nn, data_path, figure_path in zip(figures, data_paths, figure_paths, strict=True):
        ds = builders[nn]().assign_attrs(model_attributes(NOT_USED, NOT_USED))  # the half-space alone: no wear, no wheel/rail contact
        ds = io.finalize(ds, config, title=f"Figure {int(nn)}", source=f"rail.studies.datasets.fig{nn}")
        io.write_netcdf(ds, data_path)
        fig = getattr(report, f"fig{nn}")(ds)
        fig.savefig(figure_path, dpi=150)
        plt.close(fig)


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    main(snakemake.params.figures, snakemake.params.cfg, snakemake.output.data, snakemake.output.figure)  # noqa: F821
