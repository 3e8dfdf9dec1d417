"""Roughness growth of one scenario at one speed, resumable from its checkpoint."""

import sys
from pathlib import Path

from rail import chain
from rail.setup import build, io
from rail.setup.progress import Tee
from rail.studies import datasets, runs


def main(config, name, table_path, speed, checkpoint, out_path, log):
    scn = build.scenario(config, name)
    with io.open_intermediate(table_path) as t:
        tab = datasets.read_receptance_table(t.load())
    Path(checkpoint).parent.mkdir(parents=True, exist_ok=True)
    history = chain.grow(scn, tab, checkpoint=checkpoint, identity={"config": config}, progress=log, on_mismatch="restart")
    ds = runs.growth_dataset(scn, tab, history, speed, warn=log)
    io.write_netcdf(io.finalize(ds, config, title=f"Roughness growth at {speed:g} m/s", source="rail.chain.grow", scenario=name), out_path)


if __name__ == "__main__":
    log = open(snakemake.log[0], "w")  # noqa: F821
    sys.stderr = log
    w = snakemake.wildcards  # noqa: F821
    progress = Tee(log, f"growth {w.scenario} V{w.speed}")  # the log, and the terminal if it is one
    main(snakemake.params.cfg, w.scenario, snakemake.input.table, snakemake.params.speed, snakemake.params.checkpoint, snakemake.output[0], progress)  # noqa: F821
