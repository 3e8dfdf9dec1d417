"""Figs 8 and 22: wheel/rail forces from the receptance tables."""

import sys

from rail import chain, interaction
from rail.plotting import report
from rail.setup import build, io
from rail.studies import datasets
from rail.studies.validity import NOT_USED, model_attributes


def _table(path):
    with io.open_intermediate(path) as ds:
        return datasets.read_receptance_table(ds.load())


def main(rule, config, table_paths, data_path, figure_path):
    scn = build.passage_scenario(config)
    track = scn.track
    if rule == "fig08":
        s = config["figures"]["fig08"]
        tab = _table(table_paths[0])
        rough = interaction.Roughness.harmonic(s["amplitude"], s["speed"] / s["frequency"], track.L, tab.harmonics)
        res = chain.solve_forces(scn, tab, rough)
        ds = datasets.fig08(res, track, rough, s)
    else:
        results = {}
        for path in table_paths:
            tab = _table(path)
            results[tab.speed] = chain.solve_forces(scn, tab, interaction.Roughness.smooth(tab.harmonics))
        ds = datasets.fig22(results, track)
    ds = ds.assign_attrs(model_attributes(NOT_USED, scn.contact_numerics.normal))  # forces only: no wear
    ds = io.finalize(ds, config, title=f"Figure {int(rule[3:])}", source=f"rail.interaction.solve_forces, rail.studies.datasets.{rule}")
    io.write_netcdf(ds, data_path)
    getattr(report, rule)(ds).savefig(figure_path, dpi=150)


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    main(snakemake.rule, snakemake.params.cfg, list(snakemake.input), snakemake.output.data, snakemake.output.figure)  # noqa: F821
