"""One wheel passage over a harmonic roughness: forces, contact and wear along the bay."""

import sys

import xarray as xr

from rail import datasets, interaction, io, params, wear


def main(config, table_path, frequency, out_path):
    track, wheels = params.track(config), params.wheels(config)
    s = config["figures"]["wear"]
    with xr.open_dataset(table_path) as t:
        tab = datasets.read_receptance_table(t.load())
    one = interaction.Wheels(wheels.mass, wheels.radius, wheels.static_load, (0.0,))
    rough = interaction.Roughness.harmonic(s["amplitude"], s["speed"] / frequency, track.L, tab.harmonics)
    forces = interaction.solve_forces(tab, one, params.contact_spring(config), rough, track.beta0, track.L)
    c = config["contact"]
    result = wear.bay_wear(
        forces, 0, rough, params.contact_material(config), float(config["material"]["density"]),
        float(config["wear"]["coefficient"]), track.beta0, track.L, nodes=int(config["numerics"]["contact"]["nodes"]),
        closure=c["closure"], closure_scale=float(c["closure_scale"]),
    )
    ds = datasets.wear_case(result, forces, rough, track, s, frequency)
    io.write_netcdf(io.finalize(ds, config, title=f"Wear of one passage, {frequency:.0f} Hz", source="rail.wear.bay_wear"), out_path)


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    cfg = getattr(snakemake.params, "cfg", None) or snakemake.config  # noqa: F821
    main(cfg, snakemake.input.table, snakemake.params.frequency, snakemake.output[0])  # noqa: F821
