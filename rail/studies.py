"""Datasets, figures and tables of the numerical studies (named targets, README).

* closure sensitivity study (contact.closure_scale): ``closure_study``, ``closure_spectra``,
  ``closure_wear_spectra``;
* stability suite: ``stability_dataset``, ``stability_rows``;
* convergence study: ``convergence_dataset``, ``convergence_figure``.

Kept apart from rail.datasets and rail.figures so that changing a study's presentation does not
rerun the growth jobs (each rule's params hold a hash of the modules it uses).
"""

from __future__ import annotations

import matplotlib
import matplotlib.ticker

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

from .datasets import _var  # noqa: E402


def closure_study(runs: dict, soft: dict, four: dict, wear_cases: dict, wellposed: xr.Dataset, L: float,
                  pinned_pinned_Hz: float, k_max_rad_per_m: float = 525.0) -> xr.Dataset:
    """The closure sensitivity study (contact.closure_scale s) in one dataset.

    runs : {(s, speed): growth dataset} single wheel, default track;
    soft, four : {s: growth dataset} softer railpad and four wheels at the higher speed;
    wear_cases : {(s, frequency_Hz): wear-case dataset} one passage over a harmonic roughness;
    wellposed : growth_per_transit(closure_scale, nodes) from rail.contact.perturbation_growth.
    A closure value whose perturbations grow (growth per transit >= 1 on any grid) is marked
    well_posed = 0 and its conclusions are not decided (conclusion_holds = -1).
    """
    from .conclusions import CONCLUSIONS, evaluate, overall_level_dB, short_wavelength_ratio

    S = sorted({s for s, _ in runs})
    V = sorted({v for _, v in runs})
    F = sorted({f for _, f in wear_cases})
    first = runs[(S[0], V[0])]
    Kh = first.sizes["harmonic"]
    passages = first["passage"].values

    def Z(ds, i=-1):
        return ds["Z_real"].values[i] + 1j * ds["Z_imag"].values[i]

    level = np.array([[runs[(s, v)]["level"].values for v in V] for s in S])
    overall = np.array([[overall_level_dB(Z(runs[(s, v)])) for v in V] for s in S])
    ratio = np.array([[short_wavelength_ratio(Z(runs[(s, v)]), L) for v in V] for s in S])
    o_soft = np.array([overall_level_dB(Z(soft[s])) for s in S])
    o_four = np.array([overall_level_dB(Z(four[s])) for s in S])
    wear_spec = np.array([[wear_cases[(s, f)]["wear_spectrum"].values for f in F] for s in S])
    amp = np.zeros((len(S), len(F)))
    rate = np.zeros((len(S), len(F)))
    for i, s in enumerate(S):
        for j, f in enumerate(F):
            c = wear_cases[(s, f)]
            m = int(round(L / c.attrs["roughness_wavelength_m"]))
            dz = c["wear_spectrum_real"].values[m - 1] + 1j * c["wear_spectrum_imag"].values[m - 1]
            z = c.attrs["roughness_amplitude_m"] / 2  # Z_m of A cos(2 pi x / lambda)
            amp[i, j] = 2 * abs(dz) / c.attrs["mean_wear_m"]
            rate[i, j] = -np.real(dz / z)
    gpt = wellposed["growth_per_transit"].sel(closure_scale=S).values
    ok = np.all(gpt < 1.0, axis=1)
    keys = list(CONCLUSIONS)
    holds = np.full((len(S), len(keys)), -1, dtype=int)
    evidence = np.empty((len(S), len(keys)), dtype=object)
    slow, fast = 0, len(V) - 1
    for i, s in enumerate(S):
        res = evaluate(
            levels_first=float(level[i, fast, 1, 0]),
            levels_final=float(level[i, fast, -1, 0]), argmax_harmonic=int(np.argmax(level[i, fast, -1])) + 1,
            wear_amplitude=dict(zip(F, amp[i])), wear_rate=dict(zip(F, rate[i])),
            ratio_slow=float(ratio[i, slow]), ratio_fast=float(ratio[i, fast]),
            overall_default=float(overall[i, fast]), overall_soft=float(o_soft[i]),
            overall_single=float(overall[i, fast]), overall_four=float(o_four[i]), pinned_pinned_Hz=pinned_pinned_Hz,
        )
        for j, key in enumerate(keys):
            evidence[i, j] = res[key][1]
            if ok[i]:
                holds[i, j] = int(res[key][0])
    return xr.Dataset(
        {
            "level": _var(("closure_scale", "speed", "passage", "harmonic"), level, "dB re 1 um", "rms roughness level of each harmonic, single wheel, smooth initial rail"),
            "overall_level": _var(("closure_scale", "speed"), overall, "dB re 1 um", "overall rms roughness level at the end, single wheel"),
            "overall_level_soft_pad": _var("closure_scale", o_soft, "dB re 1 um", f"overall level at the end, softer railpad, {V[fast]:g} m/s"),
            "overall_level_four_wheels": _var("closure_scale", o_four, "dB re 1 um", f"overall level at the end, four wheels, {V[fast]:g} m/s"),
            "short_wavelength_ratio": _var(("closure_scale", "speed"), ratio, "1", "rms of wavelengths <= L/5 after the sleepers over that at mid-span"),
            "wear_spectrum": _var(("closure_scale", "frequency", "harmonic"), wear_spec, "m", "amplitude 2|Delta Z_k| of the wear of one passage over a harmonic roughness"),
            "wear_amplitude": _var(("closure_scale", "frequency"), amp, "1", "wear at the roughness wavelength over the mean wear, one passage"),
            "wear_rate": _var(("closure_scale", "frequency"), rate, "1", "in-phase growth per passage -Re(Delta Z_m / Z_m) (> 0: the roughness grows)"),
            "growth_per_transit": _var(("closure_scale", "nodes"), gpt, "1", "growth factor per patch transit of a perturbation of steady rolling (< 1: well-posed)"),
            "well_posed": _var("closure_scale", ok.astype(int), "1", "1 when perturbations decay on every grid tested, else 0"),
            "conclusion_holds": _var(("closure_scale", "conclusion"), holds, "1", "1 holds, 0 does not, -1 not decided (closure not well-posed)"),
            "conclusion_evidence": _var(("closure_scale", "conclusion"), evidence.astype(str), "1", "the numbers that decide each conclusion"),
        },
        coords={
            "closure_scale": _var("closure_scale", np.array(S), "1", "closure scale s: l = (a/2) exp(2 s / pi)"),
            "speed": _var("speed", np.array(V), "m/s", "train speed"),
            "passage": _var("passage", passages, "1", "wheel passages"),
            "harmonic": _var("harmonic", first["harmonic"].values, "1", "harmonic k of the sleeper bay"),
            "wavenumber": _var("harmonic", first["wavenumber"].values, "rad/m", "wavenumber k beta0"),
            "frequency": _var("frequency", np.array(F), "Hz", "excitation frequency of the harmonic roughness (wear cases)"),
            "nodes": wellposed["nodes"],
            "conclusion": _var("conclusion", np.array([str(k) for k in keys]), "1", "conclusion of section 7 of the report"),
            "conclusion_text": _var("conclusion", np.array([CONCLUSIONS[k] for k in keys]), "1", "statement of the conclusion"),
        },
        attrs={"pinned_pinned_Hz": pinned_pinned_Hz, "spectrum_max_wavenumber_rad_per_m": k_max_rad_per_m, "harmonics": int(Kh),
               "wear_speed_m_per_s": float(next(iter(wear_cases.values())).attrs["speed_m_per_s"])},
    )


def _closure_lines(ds):
    """Line style and grey level per closure value (dark: small s, light: large s); the default
    s = 1 is solid black."""
    S = ds["closure_scale"].values
    styles = ["--", "-.", ":", (0, (5, 1, 1, 1, 1, 1)), (0, (1, 3)), (0, (8, 2))]
    out = []
    for i, s in enumerate(S):
        if np.isclose(s, 1.0):
            out.append(("-", "k", 1.4))
        else:
            out.append((styles[i % len(styles)], plt.cm.viridis(i / max(len(S) - 1, 1)), 1.0))
    return out


def closure_spectra(ds: xr.Dataset):
    """Closure study: roughness level spectra after the last passage per closure value (as Fig. 23),
    one panel per speed. Closure values that are not well-posed are marked in the legend."""
    V = ds["speed"].values
    fig, axes = plt.subplots(1, len(V), figsize=(6.0 * len(V), 4.2), layout="constrained", squeeze=False)
    sel = ds["wavenumber"].values <= ds.attrs["spectrum_max_wavenumber_rad_per_m"]
    for ax, v in zip(axes[0], V):
        for (style, color, lw), s, ok in zip(_closure_lines(ds), ds["closure_scale"].values, ds["well_posed"].values):
            y = ds["level"].sel(speed=v).sel(closure_scale=s).isel(passage=-1).values[sel]
            ax.plot(ds["wavenumber"].values[sel], y, linestyle=style, color=color, lw=lw, label=f"s = {s:g}" + ("" if ok else " (ill-posed)"))
        ax.set_xlabel("wavenumber (rad/m)")
        ax.set_ylabel("roughness level (dB re 1 µm)")
        ax.set_title(f"V = {v:g} m/s, {int(ds['passage'].values[-1])} passages, single wheel", fontsize=9)
    axes[0][0].legend(fontsize=7, title="closure scale", title_fontsize=7)
    return fig


def closure_wear_spectra(ds: xr.Dataset):
    """Closure study: wear spectra of one passage over a harmonic roughness (Figs 13, 15, 17, 19)
    per closure value, one panel per excitation frequency."""
    F = ds["frequency"].values
    fig, axes = plt.subplots(2, (len(F) + 1) // 2, figsize=(11.0, 7.0), layout="constrained", squeeze=False)
    sel = ds["wavenumber"].values <= ds.attrs["spectrum_max_wavenumber_rad_per_m"]
    for ax, f in zip(axes.ravel(), F):
        for (style, color, lw), s in zip(_closure_lines(ds), ds["closure_scale"].values):
            y = ds["wear_spectrum"].sel(frequency=f, closure_scale=s).values[sel] * 1e12
            ax.plot(ds["wavenumber"].values[sel], y, linestyle=style, color=color, lw=lw, marker="o", ms=2, label=f"s = {s:g}")
        ax.set_xlabel("wavenumber (rad/m)")
        ax.set_ylabel("wear amplitude after one passage (pm)")
        ax.set_title(f"{f:.0f} Hz roughness, V = {ds.attrs['wear_speed_m_per_s']:g} m/s", fontsize=9)
    axes.ravel()[0].legend(fontsize=7, title="closure scale", title_fontsize=7)
    return fig


def stability_dataset(records: list[dict], expect: dict, critical_speed: float) -> xr.Dataset:
    """Outcomes of the stability suite, one entry per case (rail.stability.run_case records).

    expect : {case: 'ok' or {'error': regex}} from config/stability.yaml; as_expected is 1 when
    the outcome is the expected one. critical_speed : m/s, of the default track.
    """
    from .stability import outcome_matches

    names = [r["case"] for r in records]

    def col(key):
        return np.array([str(r[key]) for r in records])

    checks = np.array(["; ".join(f"{c['name']} {c['value']:.3g} (limit {c['limit']:.3g}) {'pass' if c['passed'] else 'FAIL'}" for c in r["checks"]) for r in records])
    expected = np.array(["ok" if expect[n] == "ok" else f"error: {expect[n]['error']}" for n in names])
    matches = np.array([int(outcome_matches(r, expect[r["case"]])) for r in records])
    return xr.Dataset(
        {
            "description": _var("case", col("description"), "1", "what the case tests"),
            "status": _var("case", col("status"), "1", "ok (checks passed), error (clear error naming the cause) or failed"),
            "error_type": _var("case", col("error_type"), "1", "type of the error that stopped the case"),
            "message": _var("case", col("message"), "1", "error message, or a note (full slip)"),
            "stage": _var("case", col("stage"), "1", "computation stage reached"),
            "checks": _var("case", checks, "1", "checks of a completed case: value, limit, outcome"),
            "expected": _var("case", expected, "1", "expected outcome (config/stability.yaml)"),
            "as_expected": _var("case", matches, "1", "1 when the outcome is the expected one"),
            "full_slip": _var("case", np.array([float(r["full_slip"]) for r in records]), "1", "fraction of the bay without a stick zone (one passage)"),
            "cpu_time": _var("case", np.array([float(r["cpu_s"]) for r in records]), "s", "CPU time of the case"),
        },
        coords={"case": _var("case", np.array(names), "1", "stability case")},
        attrs={"critical_speed_m_per_s": critical_speed},
    )


def stability_rows(ds: xr.Dataset) -> list[list[str]]:
    """Rows (header first) of the stability outcome table."""
    rows = [["case", "what", "outcome", "as expected", "evidence (checks or error message)", "CPU (s)"]]
    for i, c in enumerate(ds["case"].values):
        ev = str(ds["checks"].values[i]) if str(ds["status"].values[i]) == "ok" else f"{ds['error_type'].values[i]}: {ds['message'].values[i]}"
        if str(ds["status"].values[i]) == "ok" and str(ds["message"].values[i]):
            ev = f"{ds['message'].values[i]}; {ev}"
        ev = " ".join(ev.replace("|", "/").split())  # one line per table cell
        rows.append([str(c), str(ds["description"].values[i]), str(ds["status"].values[i]),
                     "yes" if ds["as_expected"].values[i] else "NO", ev, f"{float(ds['cpu_time'].values[i]):.1f}"])
    return rows


def _cz(ds, re_name, im_name):
    return ds[re_name].values + 1j * ds[im_name].values


def convergence_dataset(points: dict, study: dict, defaults: dict) -> xr.Dataset:
    """Errors of the convergence study against each setting's reference (rail.convergence).

    points : {(setting, value): point dataset}; study : config/convergence.yaml;
    defaults : {setting: default value}. One entry per non-reference point, dimension 'point'.
    For wear and growth points, error is the largest error of a harmonic against itself
    (rail.convergence.harmonic_error, harmonics within 40 dB of the largest; for wear points the
    largest over the wear frequencies) and, for growth, error_dB the level error within 40 dB.
    """
    from .convergence import WITHIN_DB, force_error, harmonic_error, level_error_dB, pareto_front

    rows = []
    for name, s in study["settings"].items():
        ref = points[(name, float(s["reference"]))]
        ref_time = float(ref["cpu_time"])
        for v in s["values"]:
            p = points[(name, float(v))]
            q = s["quantity"]
            e_db = np.nan
            if q == "force":
                e = force_error(p["force"].values, ref["force"].values)
            elif q == "wear":
                Zr, Zp = _cz(ref, "wear_real", "wear_imag"), _cz(p, "wear_real", "wear_imag")
                e = max(harmonic_error(Zp[i], Zr[i], k_max=50) for i in range(Zr.shape[0]))
            else:
                Zr, Zp = _cz(ref, "Z_real", "Z_imag"), _cz(p, "Z_real", "Z_imag")
                e = harmonic_error(Zp, Zr, k_max=50)
                e_db = level_error_dB(Zp, Zr, k_max=50)
            rows.append((name, q, float(v), float(p["cpu_time"]), e, e_db, float(v) == float(defaults[name]), float(s["reference"]), ref_time))
    settings = np.array([r[0] for r in rows])
    times = np.array([r[3] for r in rows])
    errors = np.array([r[4] for r in rows])
    front = np.zeros(len(rows), dtype=bool)
    for name in study["settings"]:
        sel = settings == name
        front[sel] = pareto_front(times[sel], errors[sel])
    return xr.Dataset(
        {
            "cpu_time": _var("point", times, "s", "CPU time of the computation (one core)"),
            "error": _var("point", errors, "1", f"error against the reference: force / fluctuation; wear and roughness: largest |Z_k / Z_k,ref - 1| over the harmonics within {WITHIN_DB:g} dB of the largest"),
            "error_dB": _var("point", np.array([r[5] for r in rows]), "dB", f"largest roughness level error within {WITHIN_DB:g} dB of the highest level (growth points)"),
            "is_default": _var("point", np.array([int(r[6]) for r in rows]), "1", "1 for the default value of the setting"),
            "on_pareto_front": _var("point", front.astype(int), "1", "1 when no value of the same setting is both faster and more accurate"),
            "reference_value": _var("point", np.array([r[7] for r in rows]), "1", "value of the setting in the reference"),
            "reference_cpu_time": _var("point", np.array([r[8] for r in rows]), "s", "CPU time of the reference"),
        },
        coords={
            "setting": _var("point", settings, "1", "numerical setting (config/convergence.yaml)"),
            "quantity": _var("point", np.array([r[1] for r in rows]), "1", "figure quantity whose error is measured"),
            "value": _var("point", np.array([r[2] for r in rows]), "1", "value of the setting"),
        },
        attrs={"speed_m_per_s": float(study["speed"])},
    )


_QUANTITY_TEXT = {"force": "normal force along the bay (Fig. 22)", "wear": "wear spectrum of one passage (Figs 13, 19)",
                  "growth": "roughness after 100,000 passages (Fig. 23)"}


def convergence_figure(ds: xr.Dataset):
    """Error against CPU time, log-log, one panel per quantity and a line per setting; the default
    value is a filled marker, the others open; each point is labelled with its value."""
    quantities = list(dict.fromkeys(ds["quantity"].values))
    fig, axes = plt.subplots(1, len(quantities), figsize=(5.0 * len(quantities), 4.2), layout="constrained", squeeze=False)
    markers = ["o", "s", "^", "D", "v"]
    for ax, q in zip(axes[0], quantities):
        names = list(dict.fromkeys(ds["setting"].values[ds["quantity"].values == q]))
        for m, name in zip(markers, names):
            sel = ds["setting"].values == name
            t, e = ds["cpu_time"].values[sel], np.maximum(ds["error"].values[sel], 1e-12)
            order = np.argsort(t)
            ax.loglog(t[order], e[order], "-", color="k", lw=0.8, marker=m, mfc="none", label=name)
            d = ds["is_default"].values[sel].astype(bool)
            ax.loglog(t[d], e[d], m, color="k")
            for ti, ei, v in zip(t, e, ds["value"].values[sel]):
                ax.annotate(f"{v:g}", (ti, ei), fontsize=6, xytext=(3, 3), textcoords="offset points")
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.yaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.set_xlabel("CPU time (s, one core)")
        ax.set_ylabel("relative error")
        ax.set_title(_QUANTITY_TEXT.get(q, q), fontsize=9)
        ax.legend(fontsize=7, title="setting (filled: default)", title_fontsize=7)
    return fig


def convergence_rows(ds: xr.Dataset) -> list[list[str]]:
    """Rows (header first) of the convergence summary: each setting's default, its error and time,
    the reference, and whether the default is on the Pareto front."""
    rows = [["setting", "quantity", "default", "error of the default", "CPU time (s)", "reference (CPU s)", "on the Pareto front",
             "all values: value -> error"]]
    for name in dict.fromkeys(ds["setting"].values):
        sel = ds["setting"].values == name
        d = np.where(sel & (ds["is_default"].values == 1))[0]
        allv = ", ".join(f"{v:g} -> {e:.2g}" + (f" ({db:.2f} dB)" if np.isfinite(db) else "")
                         for v, e, db in zip(ds["value"].values[sel], ds["error"].values[sel], ds["error_dB"].values[sel]))
        if len(d):
            i = d[0]
            err = f"{ds['error'].values[i]:.2g}" + (f" ({ds['error_dB'].values[i]:.2f} dB)" if np.isfinite(ds["error_dB"].values[i]) else "")
            rows.append([str(name), str(ds["quantity"].values[i]), f"{ds['value'].values[i]:g}", err, f"{ds['cpu_time'].values[i]:.1f}",
                         f"{ds['reference_value'].values[i]:g} ({ds['reference_cpu_time'].values[i]:.1f})", "yes" if ds["on_pareto_front"].values[i] else "no", allv])
        else:
            rows.append([str(name), "", "(not in the study)", "", "", "", "", allv])
    return rows
