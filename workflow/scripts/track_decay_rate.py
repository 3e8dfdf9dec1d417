"""Vertical track decay rate of one track in one-third-octave bands (EN 15461), with a measured
decay rate (config/measured/<track>_decay_rate.csv) on the same axes if there is one."""

import sys

from rail import decay
from rail.setup import build, io
from rail.studies import characterisation
from rail.plotting import track as plots


def main(config, name, measured_path, data_path, figure_path):
    track = build.scenario(config, name).track
    ds = characterisation.track_decay_rate(track, name)
    measured = None
    if measured_path is not None:
        measured = characterisation.measured_decay_rate(decay.read_measured_decay_rate(measured_path))
        ds = ds.merge(measured, combine_attrs="override")
    ds = io.finalize(ds, config, title=f"Vertical track decay rate of track '{name}'", source="rail.studies.characterisation.track_decay_rate")
    io.write_netcdf(ds, data_path)
    plots.track_decay_rate(ds, measured).savefig(figure_path, dpi=150)


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    measured = snakemake.input[0] if len(snakemake.input) else None  # noqa: F821
    main(snakemake.params.cfg, snakemake.params.name, measured, snakemake.output.data, snakemake.output.figure)  # noqa: F821
