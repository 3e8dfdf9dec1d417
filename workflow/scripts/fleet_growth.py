"""Roughness growth under a scenario's fleet (rail.chain.grow_fleet), resumable from its checkpoint."""

import sys
from pathlib import Path

from rail import chain
from rail.setup import build, io
from rail.setup.progress import Tee
from rail.studies import datasets
from rail.studies import fleet as fleet_study


def read_tables(paths, speeds):
    """{speed: table} of the job's table files, each checked to be at its class speed."""
    tabs = []
    for path in paths:
        with io.open_intermediate(path) as t:
            tabs.append(datasets.read_receptance_table(t.load()))
    return fleet_study.tables_by_speed(tabs, speeds)


def main(config, name, table_paths, speeds, checkpoint, out_path, log):
    scn = build.scenario(config, name)
    fl = build.fleet(config)
    classes = build.fleet_classes(config, scn)
    tables = read_tables(table_paths, speeds)
    Path(checkpoint).parent.mkdir(parents=True, exist_ok=True)
    history = chain.grow_fleet(classes, tables, checkpoint=checkpoint, identity={"config": config}, progress=log,
                               on_mismatch="restart")
    ds = fleet_study.fleet_growth_dataset(classes, tables, history, fl)
    io.write_netcdf(io.finalize(ds, config, title="Roughness growth under the fleet", source="rail.chain.grow_fleet",
                                scenario=name), out_path)


if __name__ == "__main__":
    log = open(snakemake.log[0], "w")  # noqa: F821
    sys.stderr = log
    w = snakemake.wildcards  # noqa: F821
    progress = Tee(log, f"fleet growth {w.scenario}")  # the log, and the terminal if it is one
    main(snakemake.params.cfg, w.scenario, list(snakemake.input.tables), snakemake.params.speeds,  # noqa: F821
         snakemake.params.checkpoint, snakemake.output[0], progress)  # noqa: F821
