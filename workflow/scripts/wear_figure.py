"""Figs 9-19 from a wear case."""

import sys

from rail.plotting import report
from rail.setup import io
from rail.studies import datasets


def main(nn, config, case_path, data_path, figure_path):
    n = int(nn)
    with io.open_intermediate(case_path) as c:
        case = c.load()
    if n == 9:
        ds, draw = datasets.fig09(case), report.fig09
    elif n in (10, 11):
        ds = datasets.fig10_11(case, "traction" if n == 10 else "slip_velocity")
        draw = report.fig10 if n == 10 else report.fig11
    elif n % 2 == 0:
        ds, draw = datasets.fig_wear(case), report.fig_wear
    else:
        ds = datasets.fig_wear_spectrum(case, float(config["figures"]["wear"]["spectrum_max_wavenumber"]))
        draw = report.fig_wear_spectrum
    ds = io.finalize(ds, config, title=f"Figure {n}", source=f"rail.studies.datasets (from {case_path})")
    io.write_netcdf(ds, data_path)
    draw(ds).savefig(figure_path, dpi=150)


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    main(snakemake.wildcards.nn, snakemake.params.cfg, snakemake.input[0], snakemake.output.data, snakemake.output.figure)  # noqa: F821
