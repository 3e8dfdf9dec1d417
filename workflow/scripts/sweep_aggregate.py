"""Aggregate the growth runs of a sweep study into one dataset and a map figure."""

import sys

from rail.plotting import report
from rail.setup import io
from rail.studies import datasets


def main(config, study, keys, values, indices, units, run_paths, data_path, figure_path):
    runs = []
    for path in run_paths:
        with io.open_intermediate(path) as ds:
            runs.append(ds.load())
    ds = datasets.sweep(runs, keys, values, indices, units)
    ds = io.finalize(ds, config, title=f"Sweep study {study}", source="rail.studies.datasets.sweep", scenario=f"sweep study {study}")
    io.write_netcdf(ds, data_path)
    report.sweep_map(ds).savefig(figure_path, dpi=150)


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    main(snakemake.params.cfg, snakemake.wildcards.study, snakemake.params.swept, snakemake.params.grid, snakemake.params.indices,  # noqa: F821
         snakemake.params.units, list(snakemake.input), snakemake.output.data, snakemake.output.figure)  # noqa: F821
