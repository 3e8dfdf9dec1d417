"""Moving-load receptance at the contact point of one track, per speed, beside the stationary
bay-averaged point receptance."""

import sys

from rail.setup import build, io
from rail.studies import characterisation
from rail.plotting import track as plots


def main(config, name, speeds, data_path, figure_path):
    scn = build.scenario(config, name)
    ds = characterisation.moving_receptance(scn.track, speeds, name, points=400, rtol=scn.track_numerics.rtol)
    ds = io.finalize(ds, config, title=f"Moving-load receptance at the contact point, track '{name}'",
                     source="rail.studies.characterisation.moving_receptance")
    io.write_netcdf(ds, data_path)
    plots.moving_receptance(ds).savefig(figure_path, dpi=150)


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    main(snakemake.params.cfg, snakemake.params.name, snakemake.params.speeds, snakemake.output.data, snakemake.output.figure)  # noqa: F821
