"""Moving-load receptance table of one track at one speed (shared by the scenarios on that track);
for a roughness periodic over N bays, the tables of its Bloch fractions; for a track periodic over a
cell of N bays (track.cell), the one table over the cell's harmonics."""

import sys

from rail import chain
from rail.setup import build, io
from rail.studies import datasets


def main(config, speed, offsets, bays, out_path):
    track, numerics = build.track(config)
    cell = build.track_cell(config)
    tab = chain.track_table(track if cell is None else cell.track, numerics, speed, offsets, bays, cell)
    track = track if cell is None else cell.track
    ds = datasets.bloch_tables(tab, track) if isinstance(tab, tuple) else datasets.receptance_table(tab, track)
    title = f"Moving-load receptance, V = {speed} m/s" + ("" if bays == 1 else f", roughness period {bays} bays") + \
        ("" if cell is None else f", track cell of {cell.bays} bays")
    io.write_netcdf(io.finalize(ds, config, title=title, source="rail.moving.receptance_table"), out_path)


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    w = snakemake.wildcards  # noqa: F821
    main(snakemake.params.cfg, float(w.speed), snakemake.params.offsets, int(w.get("bays", 1)), snakemake.output[0])  # noqa: F821
