"""Moving-load receptance table of one track at one speed (shared by the scenarios on that track);
for a roughness periodic over N bays, the tables of its Bloch fractions; for a track periodic over a
cell of N bays (track.cell), the one table over the cell's harmonics."""

import sys

from rail import chain
from rail.setup import build, io
from rail.setup.progress import Tee, progress_lines
from rail.studies import datasets


def main(config, speed, offsets, bays, out_path, progress=None):
    track, numerics = build.track(config)
    cell = build.track_cell(config)
    tab = chain.track_table(track if cell is None else cell.track, numerics, speed, offsets, bays, cell, progress=progress)
    track = track if cell is None else cell.track
    ds = datasets.bloch_tables(tab, track) if isinstance(tab, tuple) else datasets.receptance_table(tab, track)
    title = f"Moving-load receptance, V = {speed} m/s" + ("" if bays == 1 else f", roughness period {bays} bays") + \
        ("" if cell is None else f", track cell of {cell.bays} bays")
    io.write_netcdf(io.finalize(ds, config, title=title, source="rail.moving.receptance_table"), out_path)


if __name__ == "__main__":
    log = open(snakemake.log[0], "w")  # noqa: F821
    sys.stderr = log
    w = snakemake.wildcards  # noqa: F821
    label = f"receptance {w.track} V{w.speed}" + (f" N{w.bays}" if "bays" in w.keys() else "")
    tee = Tee(log, label)  # progress lines into the log, and a bar on the terminal if there is one
    print(f"{label}: {len(snakemake.params.offsets)} offsets, harmonics K = {snakemake.params.cfg['numerics']['track']['harmonics']}",  # noqa: F821
          file=tee, flush=True)
    main(snakemake.params.cfg, snakemake.params.speed, snakemake.params.offsets, snakemake.params.bays, snakemake.output[0],  # noqa: F821
         progress_lines(tee))
    tee.close()
