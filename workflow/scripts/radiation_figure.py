"""Figs 5-6: select the figure's variables from the radiation dataset, write and draw them."""

import sys

from rail.plotting import report
from rail.setup import io
from rail.studies import datasets


def main(nn, config, in_path, data_path, figure_path):
    with io.open_intermediate(in_path) as rad:
        ds = getattr(datasets, f"fig{nn}")(rad.load())
    ds = io.finalize(ds, config, title=f"Figure {int(nn)}", source=f"rail.studies.datasets.fig{nn}")
    io.write_netcdf(ds, data_path)
    getattr(report, f"fig{nn}")(ds).savefig(figure_path, dpi=150)


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    main(snakemake.wildcards.nn, snakemake.params.cfg, snakemake.input[0], snakemake.output.data, snakemake.output.figure)  # noqa: F821
