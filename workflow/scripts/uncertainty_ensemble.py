"""The uncertainty ensemble's band spectrum: median and stated interval per band (rail.studies.ensemble)."""

import sys

from rail.plotting import ensemble as plots
from rail.setup import io
from rail.studies import ensemble


def main(paths, draws, interval, data_path, figure_path):
    members = [io.open_intermediate(p).load() for p in paths]
    ds = ensemble.ensemble_dataset(members, draws, tuple(interval))
    io.write_netcdf(ds, data_path)
    plots.band_interval_figure(ds).savefig(figure_path, dpi=150)


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    main(list(snakemake.input), snakemake.params.draws, snakemake.params.interval, snakemake.output.data,  # noqa: F821
         snakemake.output.figure)  # noqa: F821
