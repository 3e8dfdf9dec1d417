"""The irregular-track study's summary: pinned-pinned band and loudest band after the run (rail.studies.irregular)."""

import sys

import numpy as np
import xarray as xr

from rail.setup import build, io
from rail.studies import irregular


def main(cfgs, case_cfgs, spreads, uniform_cfg, speed, cases, uniform_path, random_paths, out, log):
    from rail.plotting.irregular import summary_figure

    rows = []
    uniform = build.track(uniform_cfg)[0]
    with io.open_intermediate(uniform_path) as g:
        rows.append(("irregular_uniform", "uniform", 0.0, irregular.band_summary(g.load(), speed, uniform)))
    for name, path in cases:
        cell = build.track_cell(case_cfgs[name])
        with io.open_intermediate(path) as g:
            rows.append((name, "case", np.nan, irregular.band_summary(g.load(), speed, cell.track)))
    for name, path in random_paths:
        cell = build.track_cell(cfgs[name])
        spread = float(spreads[name])
        with io.open_intermediate(path) as g:
            rows.append((name, "random", spread, irregular.band_summary(g.load(), speed, cell.track)))
    n = len(rows)
    ds = xr.Dataset(
        {
            "pp_level_dB": io.data_var("case", np.array([r[3]["pp_level_dB"] for r in rows]), "dB re 1 um",
                                "level of the one-third-octave band holding the pinned-pinned wavelength after the run"),
            "loudest_level_dB": io.data_var("case", np.array([r[3]["loudest_level_dB"] for r in rows]), "dB re 1 um",
                                            "level of the loudest band (20 mm - 1 m)"),
            "loudest_band_m": io.data_var("case", np.array([r[3]["loudest_band_m"] for r in rows]), "m", "nominal centre of the loudest band"),
        },
        coords={"case": io.data_var("case", np.array([r[0] for r in rows]), "1", "scenario"),
                "kind": io.data_var("case", np.array([r[1] for r in rows]), "1", "uniform, named case or random track"),
                "spacing_spread": io.data_var("case", np.array([r[2] for r in rows]), "1",
                                              "spread of the sleeper spacing of a random track (uniform draw, +-)")},
        attrs={"speed_m_per_s": speed, "pp_band_m": rows[0][3]["pp_band_m"], "passages": rows[0][3]["passages"],
               "pinned_pinned_wavelength_m": rows[0][3]["pinned_pinned_wavelength_m"]},
    )
    io.write_netcdf(io.finalize(ds, {"cases": case_cfgs, "random": cfgs, "uniform": uniform_cfg}, title="Irregular-track study: pinned-pinned band",
                                source="rail.studies.irregular.band_summary"), out["data"])
    summary_figure(ds).savefig(out["figure"], dpi=110)
    lines = [f"# Irregular track at {speed:g} m/s: the pinned-pinned band ({1e3 * ds.attrs['pp_band_m']:g} mm, "
             f"V / f_pp = {1e3 * ds.attrs['pinned_pinned_wavelength_m']:.1f} mm) after {ds.attrs['passages']} passages", "",
             "| case | kind | spacing spread | pinned-pinned band (dB re 1 µm) | "
             "change from uniform (dB) | loudest band (mm) | its level (dB re 1 µm) |",
             "|---|---|---|---|---|---|---|"]
    u = float(ds["pp_level_dB"].values[0])
    for i in range(n):
        sp = ds["spacing_spread"].values[i]
        lines.append(f"| {ds['case'].values[i]} | {ds['kind'].values[i]} | {'' if np.isnan(sp) else f'±{100 * sp:g} %'} | "
                     f"{ds['pp_level_dB'].values[i]:.1f} | {ds['pp_level_dB'].values[i] - u:+.1f} | {1e3 * ds['loudest_band_m'].values[i]:g} | "
                     f"{ds['loudest_level_dB'].values[i]:.1f} |")
    rnd = ds["kind"].values == "random"
    for s in sorted(set(ds["spacing_spread"].values[rnd].tolist())):
        v = ds["pp_level_dB"].values[rnd & (ds["spacing_spread"].values == s)]
        lines.append(f"\nRandom track, spacing ±{100 * s:g} %: pinned-pinned band median {np.median(v) - u:+.1f} dB from the uniform track "
                     f"(range {v.min() - u:+.1f} to {v.max() - u:+.1f} dB over {v.size} seeds).")
    open(out["table"], "w").write("\n".join(lines) + "\n")
    print("\n".join(lines), file=log, flush=True)


if __name__ == "__main__":
    log = open(snakemake.log[0], "w")  # noqa: F821
    sys.stderr = log
    p = snakemake.params  # noqa: F821
    names = list(p.cfg)
    rnd = list(zip(names, snakemake.input.random))  # noqa: F821
    cases = list(zip(list(p.case_cfg), snakemake.input.cases))  # noqa: F821
    main(p.cfg, p.case_cfg, p.spreads, p.uniform_cfg, p.speed, cases, snakemake.input.uniform, rnd,  # noqa: F821
         {k: snakemake.output[k] for k in ("data", "figure", "table")}, log)  # noqa: F821
