"""Figs 2-4: compute the figure's dataset with rail, write it and draw it."""

import sys

from rail.plotting import report
from rail.setup import build, io
from rail.studies import datasets


def main(nn, config, data_path, figure_path):
    material = build.elastic(config)
    fig_settings = build.halfspace_figures(config)
    numerics = build.halfspace_numerics(config)
    builders = {
        "02": lambda: datasets.fig02(material, fig_settings),
        "03": lambda: datasets.fig03(material, fig_settings),
        "04": lambda: datasets.fig04(material, fig_settings, numerics),
    }
    ds = io.finalize(builders[nn](), config, title=f"Figure {int(nn)}", source=f"rail.studies.datasets.fig{nn}")
    io.write_netcdf(ds, data_path)
    getattr(report, f"fig{nn}")(ds).savefig(figure_path, dpi=150)


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    main(snakemake.wildcards.nn, snakemake.params.cfg, snakemake.output.data, snakemake.output.figure)  # noqa: F821
