"""Moving-load receptance table of one track at one speed (shared by the scenarios on that track)."""

import sys

from rail import chain
from rail.setup import build, io
from rail.studies import datasets


def main(config, speed, offsets, out_path):
    track, numerics = build.track(config)
    tab = chain.track_table(track, numerics, speed, offsets)
    ds = io.finalize(datasets.receptance_table(tab, track), config, title=f"Moving-load receptance, V = {speed} m/s", source="rail.moving.receptance_table")
    io.write_netcdf(ds, out_path)


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    main(snakemake.params.cfg, float(snakemake.wildcards.speed), snakemake.params.offsets, snakemake.output[0])  # noqa: F821
