"""One point of the convergence study: a figure quantity at one value of one numerical setting."""

import sys

import numpy as np
import xarray as xr

from rail.setup import build, io
from rail.studies import convergence, datasets


def main(config, study, setting, value, table_path, out_path):
    s = study["settings"][setting]
    V = float(study["speed"])
    scn = convergence.with_setting(build.scenario(config), setting, value)
    attrs = {"setting": setting, "value": value, "quantity": s["quantity"], "speed_m_per_s": V}
    cpu = {"units": "s", "long_name": "CPU time of the computation (one core)"}
    if s["quantity"] == "force":
        P, t = convergence.force_quantity(scn, V)
        x = np.linspace(0.0, scn.L, len(P), endpoint=False)
        ds = xr.Dataset({"force": ("position", P, {"units": "N", "long_name": "normal force on a smooth rail"}), "cpu_time": ((), t, cpu)},
                        coords={"position": ("position", x, {"units": "m", "long_name": "wheel position in the bay, 0 above a sleeper"})})
    else:
        with io.open_intermediate(table_path) as t:
            tab = datasets.read_receptance_table(t.load())
        hk = {"units": "1", "long_name": "harmonic index k of the bay"}
        if s["quantity"] == "wear":
            F = [float(f) for f in study["wear_frequencies"]]
            out = [convergence.wear_quantity(scn, tab, f, float(config["figures"]["wear"]["amplitude"])) for f in F]
            Z = np.array([o[0] for o in out])
            ds = xr.Dataset(
                {
                    "wear_real": (("frequency", "harmonic_all"), Z.real, {"units": "m", "long_name": "real part of the wear coefficients Delta Z_k"}),
                    "wear_imag": (("frequency", "harmonic_all"), Z.imag, {"units": "m", "long_name": "imaginary part of Delta Z_k"}),
                    "mean_wear": ("frequency", np.array([o[1] for o in out]), {"units": "m", "long_name": "mean wear depth of one passage"}),
                    "cpu_time": ((), sum(o[2] for o in out), cpu),
                },
                coords={"frequency": ("frequency", F, {"units": "Hz", "long_name": "excitation frequency of the harmonic roughness"}),
                        "harmonic_all": ("harmonic_all", np.arange(-tab.harmonics, tab.harmonics + 1), hk)},
            )
        else:
            Z, t = convergence.growth_quantity(scn, tab)
            ds = xr.Dataset(
                {"Z_real": ("harmonic_all", Z.real, {"units": "m", "long_name": "real part of the roughness Z_k after the run"}),
                 "Z_imag": ("harmonic_all", Z.imag, {"units": "m", "long_name": "imaginary part of Z_k"}), "cpu_time": ((), t, cpu)},
                coords={"harmonic_all": ("harmonic_all", np.arange(-tab.harmonics, tab.harmonics + 1), hk)},
            )
    ds.attrs.update(attrs)
    io.write_netcdf(io.finalize(ds, config, title=f"Convergence study: {setting} = {value:g}", source="rail.studies.convergence"), out_path)


if __name__ == "__main__":
    sys.stderr = open(snakemake.log[0], "w")  # noqa: F821
    main(snakemake.params.cfg, snakemake.params.study, snakemake.wildcards.setting, float(snakemake.params.value),  # noqa: F821
         snakemake.input.get("table"), snakemake.output[0])  # noqa: F821
