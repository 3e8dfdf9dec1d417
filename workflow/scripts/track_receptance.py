"""Vertical point receptance of one track above a sleeper and at mid-span, with its
characteristic frequencies."""

import sys

from rail.setup import build, io
from rail.studies import characterisation
from rail.plotting import track as plots


def main(config, name, data_path, figure_path):
    track = build.scenario(config, name).track
    ds = characterisation.track_receptance(track, name)
    ds = io.finalize(ds, config, title=f"Vertical point receptance of track '{name}'", source="rail.studies.characterisation.track_receptance")
    io.write_netcdf(ds, data_path)
    plots.track_receptance(ds).savefig(figure_path, dpi=150)


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    main(snakemake.params.cfg, snakemake.params.name, snakemake.output.data, snakemake.output.figure)  # noqa: F821
