"""Roughness growth of one scenario at one speed, resumable from its checkpoint."""

import sys
from pathlib import Path

import xarray as xr

from rail import datasets, growth, io, params


def main(config, table_path, speed, checkpoint, out_path, log):
    track = params.track(config)
    with xr.open_dataset(table_path) as t:
        tab = datasets.read_receptance_table(t.load())
    K = tab.harmonics
    Path(checkpoint).parent.mkdir(parents=True, exist_ok=True)
    history = growth.run_growth(
        tab, params.wheels(config), params.contact_spring(config), params.contact_material(config),
        float(config["material"]["density"]), float(config["wear"]["coefficient"]),
        params.roughness(config, speed, track.L, K), track.beta0, track.L, params.growth_settings(config),
        checkpoint=checkpoint, identity={"config": config, "speed": speed}, progress=log, on_mismatch="restart",
    )
    ds = datasets.growth(history, track, speed, len(config["wheels"]["positions"]))
    io.write_netcdf(io.finalize(ds, config, title=f"Roughness growth at {speed:g} m/s", source="rail.growth.run_growth"), out_path)


if __name__ == "__main__":
    log = open(snakemake.log[0], "w")  # noqa: F821
    sys.stderr = log
    main(snakemake.params.cfg, snakemake.input.table, float(snakemake.wildcards.speed), snakemake.params.checkpoint, snakemake.output[0], log)  # noqa: F821
