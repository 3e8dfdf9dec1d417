"""Receptance tables of one track at one speed."""

import sys

from rail import datasets, io, moving, params


def main(config, speed, offsets, out_path):
    track = params.track(config)
    num = config["numerics"]["track"]
    tab = moving.receptance_table(track, speed, int(num["harmonics"]), offsets, float(num["rtol"]))
    ds = io.finalize(datasets.receptance_table(tab, track), config, title=f"Moving-load receptance, V = {speed} m/s", source="rail.moving.receptance_table")
    io.write_netcdf(ds, out_path)


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    main(snakemake.params.cfg, float(snakemake.wildcards.speed), snakemake.params.offsets, snakemake.output[0])  # noqa: F821
