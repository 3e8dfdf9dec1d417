"""Figs 9-19 from the wear cases (one job for the eleven)."""

import sys

import matplotlib.pyplot as plt

from rail.plotting import report
from rail.setup import build, io
from rail.studies import datasets
from rail.studies.validity import model_attributes


def figure(nn, config, case, case_path):
    """The dataset of Fig. nn from its wear case, and the function that draws it."""
    n = int(nn)
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
    nums = build.passage_scenario(config).contact_numerics  # the wear case's contact (its configuration)
    ds = ds.assign_attrs(model_attributes(nums.path, nums.normal))
    return io.finalize(ds, config, title=f"Figure {n}", source=f"rail.studies.datasets (from {case_path})"), draw


def main(cases, configs, data_paths, figure_paths):
    """cases, configs: {nn: wear case file}, {nn: the configuration Fig. nn reads}; the output paths
    in the order of cases."""
    loaded = {}
    for nn, data_path, figure_path in zip(cases, data_paths, figure_paths, strict=True):
        path = cases[nn]
        if path not in loaded:
            with io.open_intermediate(path) as c:
                loaded[path] = c.load()
        ds, draw = figure(nn, configs[nn], loaded[path], path)
        io.write_netcdf(ds, data_path)
        fig = draw(ds)
        fig.savefig(figure_path, dpi=150)
        plt.close(fig)


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    main(snakemake.params.cases, snakemake.params.cfg, snakemake.output.data, snakemake.output.figure)  # noqa: F821
