"""Figs 8 and 22: wheel/rail forces from the receptance tables."""

import sys

import xarray as xr

from rail import datasets, figures, interaction, io, params


def _table(path):
    with xr.open_dataset(path) as ds:
        return datasets.read_receptance_table(ds.load())


def main(rule, config, table_paths, data_path, figure_path):
    track, wheels, contact = params.track(config), params.wheels(config), params.contact_spring(config)
    one_wheel = interaction.Wheels(wheels.mass, wheels.radius, wheels.static_load, (0.0,))
    if rule == "fig08":
        s = config["figures"]["fig08"]
        tab = _table(table_paths[0])
        rough = interaction.Roughness.harmonic(s["amplitude"], s["speed"] / s["frequency"], track.L, tab.harmonics)
        res = interaction.solve_forces(tab, one_wheel, contact, rough, track.beta0, track.L)
        ds = datasets.fig08(res, track, rough, s)
    else:
        results = {}
        for path in table_paths:
            tab = _table(path)
            results[tab.speed] = interaction.solve_forces(tab, one_wheel, contact, interaction.Roughness.smooth(tab.harmonics), track.beta0, track.L)
        ds = datasets.fig22(results, track)
    ds = io.finalize(ds, config, title=f"Figure {int(rule[3:])}", source=f"rail.interaction.solve_forces, rail.datasets.{rule}")
    io.write_netcdf(ds, data_path)
    getattr(figures, rule)(ds).savefig(figure_path, dpi=150)


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    main(snakemake.rule, snakemake.config, list(snakemake.input), snakemake.output.data, snakemake.output.figure)  # noqa: F821
