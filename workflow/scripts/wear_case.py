"""Wheel passages over a harmonic roughness, one per frequency: forces, contact and wear along the bay."""

import sys

from rail import chain, interaction
from rail.setup import build, io
from rail.studies import datasets


def main(config, table_path, frequencies, out_paths):
    scn = build.passage_scenario(config)
    s = config["figures"]["wear"]
    with io.open_intermediate(table_path) as t:
        tab = datasets.read_receptance_table(t.load())
    for frequency, out_path in zip(frequencies, out_paths, strict=True):
        rough = interaction.Roughness.harmonic(s["amplitude"], s["speed"] / frequency, scn.L, tab.harmonics)
        forces = chain.solve_forces(scn, tab, rough)
        result = chain.passage_wear(scn, forces, rough)
        ds = datasets.wear_case(result, forces, rough, scn.track, s, frequency)
        io.write_netcdf(io.finalize(ds, config, title=f"Wear of one passage, {frequency:.0f} Hz", source="rail.chain.passage_wear"), out_path)


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    main(snakemake.params.cfg, snakemake.input.table, snakemake.params.frequencies, list(snakemake.output))  # noqa: F821
