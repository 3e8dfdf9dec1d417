"""The dynamic-creepage study over speed (issue 43, named target dynamic_creepage_speeds): which
wavelengths grow, at which frequency, and whether the growing band keeps its frequency or its
wavelength as the speed changes, for each mechanism of ū(t) alone and together, on each track.

Each case is one scenario's growth-rate spectrum at several speeds (rail.growth_spectrum, one
dataset per speed as the workflow writes it). What a case holds is read from the configuration
the dataset records (its ``config`` attribute), not from its name: the wheelset (a trailer has no
motor inertia), the rail's longitudinal flexibility, friction falling with slip, and the pad.

The verdict per case compares, over the speeds at which some line grows, the spread of the fastest
growing line's frequency with that of its wavelength (both as ln(max / min)): a band that keeps its
frequency ("constant frequency", as roaring rail near the pinned-pinned frequency does) has the
smaller frequency spread by more than a factor of 2, one that keeps its wavelength ("constant
wavelength") the smaller wavelength spread; a peak on the edge of the computed range of wavelengths
is said to be there, because the band may continue beyond it.

One band, as the speed rises from V_1 to V_2, moves between those two limits: its wavelength
grows by no more than the speed (ln(lambda_2 / lambda_1) in [0, ln(V_2 / V_1)], to one line's
spacing). A fastest line whose wavelength shortens as the speed rises, or grows faster than the
speed, has moved to another band (two mechanisms, e.g. the wheelset's torsion at low speed and the
rail's band above pinned-pinned at high speed): the verdict then says "two bands" and where the
fastest line changes band, and does not call the pair constant in either.
"""

from __future__ import annotations

import numpy as np
import xarray as xr
import yaml

from ..contact import friction_law
from ..creepage.choices import rail_flexibility, wheelset_model
from ..setup.config import setting
from ..setup.io import data_var

__all__ = ["mechanism_label", "track_label", "study_dataset", "verdict", "summary_table"]

def mechanism_label(cfg: dict) -> str:
    """The mechanisms of ū(t) a resolved scenario configuration switches on, in words, each asked of its
    model choice (rail.creepage.choices, rail.contact.FrictionLaw), a key left out at the schema's default.

    Parameters
    ----------
    cfg : dict
        The resolved configuration (a spectrum dataset's ``config`` attribute, parsed).

    Returns
    -------
    str
        "fixed creepage" (the report's rigid wheel), or the parts joined by " + ": "trailer wheelset"
        or "motored wheelset" (the torsional wheelset without or with motor inertia), "rigid wheelset",
        "rail flexibility" (rail_flexibility.model other than none), "falling friction"
        (contact.friction_decay > 0 with friction_dynamic below friction_static).
    """
    wheelset = wheelset_model(setting(cfg, "wheelset.model"))
    parts = [wheelset.mechanism(driven=float(setting(cfg, "wheelset.motor_inertia")) > 0)]
    if rail_flexibility(setting(cfg, "rail_flexibility.model")).modelled:
        parts.append("rail flexibility")
    c = cfg.get("contact") or {}
    if "friction_dynamic" in c and friction_law(setting(cfg, "contact.friction_decay"), c.get("friction_static", c["friction_dynamic"]),
                                                c["friction_dynamic"]).falling:
        parts.append("falling friction")
    parts = [p for p in parts if p]
    return " + ".join(parts) if parts else "fixed creepage"


def track_label(cfg: dict) -> str:
    """The track in words: its pad's vertical stiffness ("pad 1e+09 N/m").

    Parameters
    ----------
    cfg : dict
        A case's resolved configuration.

    Returns
    -------
    str
    """
    k = float(cfg["track"]["pad"]["stiffness"])
    return f"pad {k:.3g} N/m"


def study_dataset(cases: dict, pinned_pinned: dict) -> xr.Dataset:
    """One dataset over the cases, the speeds and the lines.

    Parameters
    ----------
    cases : dict
        Scenario name -> list of growth-rate spectrum datasets (one per speed; rail.studies.rate_spectrum),
        all on the same lines (wavelengths).
    pinned_pinned : dict
        Scenario name -> the pinned-pinned frequency of its track [Hz] (rail.track.pinned_pinned_frequency).

    Returns
    -------
    xarray.Dataset
        growth_dB_per_1e5_axles (case, speed, wavelength), frequency (speed, wavelength), the mechanism and
        track of each case, and per case and speed the fastest line, the line nearest the pinned-pinned
        frequency and how many lines grow; per case the verdict (keeps frequency or wavelength).
    """
    names = list(cases)
    if not names:
        raise ValueError("cases must hold at least one scenario's spectra")
    speeds = sorted({float(s) for n in names for d in cases[n] for s in np.atleast_1d(d["speed"].values)})
    lam = np.asarray(cases[names[0]][0]["wavelength"].values, dtype=float)
    rate = np.full((len(names), len(speeds), lam.size), np.nan)
    mech, track = [], []
    for i, n in enumerate(names):
        cfg = yaml.safe_load(cases[n][0].attrs["config"])
        mech.append(mechanism_label(cfg))
        track.append(track_label(cfg))
        for d in cases[n]:
            if not np.allclose(np.asarray(d["wavelength"].values, dtype=float), lam, rtol=1e-12, atol=0.0):
                raise ValueError(f"the spectra of {n} are not on the lines of {names[0]}: every case must share its lines")
            for s in np.atleast_1d(d["speed"].values):
                rate[i, speeds.index(float(s))] = d["growth_dB_per_1e5_axles"].sel(speed=s).values
    V = np.array(speeds)
    f = V[:, None] / lam[None, :]
    fpp = np.array([float(pinned_pinned[n]) for n in names])
    ds = xr.Dataset(
        {"growth_dB_per_1e5_axles": data_var(("case", "speed", "wavelength"), rate, "dB per 100000 axle passages",
                                             "growth rate of the roughness level at the line (negative: decay)")},
        coords={"case": data_var("case", np.array(names), "1", "scenario"),
                "speed": data_var("speed", V, "m/s", "train speed"),
                "wavelength": data_var("wavelength", lam, "m", "roughness wavelength of the line"),
                "frequency": data_var(("speed", "wavelength"), f, "Hz", "passing frequency V / wavelength"),
                "mechanism": data_var("case", np.array(mech), "1", "the mechanisms of the dynamic creepage switched on"),
                "track": data_var("case", np.array(track), "1", "the track (its pad's vertical stiffness)"),
                "pinned_pinned_Hz": data_var("case", fpp, "Hz", "pinned-pinned frequency of the case's track (simply supported Timoshenko span)")},
    )
    fast = np.nanargmax(np.where(np.isnan(rate), -np.inf, rate), axis=2)
    near = np.argmin(np.abs(np.log(f[None, :, :] / fpp[:, None, None])), axis=2)
    pick = lambda idx: np.take_along_axis(rate, idx[..., None], axis=2)[..., 0]  # noqa: E731
    ds["fastest_wavelength"] = data_var(("case", "speed"), lam[fast], "m", "wavelength of the fastest line (growing or least decaying)")
    ds["fastest_frequency"] = data_var(("case", "speed"), V[None, :] / lam[fast], "Hz", "its frequency")
    ds["fastest_dB_per_1e5_axles"] = data_var(("case", "speed"), pick(fast), "dB per 100000 axle passages", "its growth rate")
    ds["pinned_pinned_wavelength"] = data_var(("case", "speed"), lam[near], "m", "the line nearest the pinned-pinned frequency")
    ds["pinned_pinned_dB_per_1e5_axles"] = data_var(("case", "speed"), pick(near), "dB per 100000 axle passages",
                                                    "growth rate at the line nearest the pinned-pinned frequency")
    ds["growing_lines"] = data_var(("case", "speed"), np.sum(rate > 0, axis=2), "1", "lines with a positive growth rate")
    ds["verdict"] = data_var("case", np.array([verdict(ds.isel(case=i)) for i in range(len(names))]), "1",
                             "whether the fastest growing line keeps its frequency or its wavelength over speed")
    ds.attrs["verdict_rule"] = ("over the speeds at which a line grows, the spread ln(max/min) of the fastest growing line's frequency "
                                "against that of its wavelength: the smaller by more than a factor 2 is what the band keeps; "
                                "'two bands' where, between two such speeds, its wavelength shortens as the speed rises or grows "
                                "faster than the speed (beyond one line's spacing), which one band cannot do")
    return ds


def verdict(case: xr.Dataset) -> str:
    """Whether one case's growing band keeps its frequency or its wavelength over speed (module docstring).

    Parameters
    ----------
    case : xarray.Dataset
        One case of study_dataset (``ds.isel(case=i)``) with fastest_wavelength, fastest_frequency and
        growing_lines per speed.

    Returns
    -------
    str
    """
    lam_all = np.asarray(case["wavelength"].values, dtype=float)
    grows = np.asarray(case["growing_lines"].values) > 0
    if not grows.any():
        return "nothing grows"
    lam = np.asarray(case["fastest_wavelength"].values, dtype=float)[grows]
    f = np.asarray(case["fastest_frequency"].values, dtype=float)[grows]
    V = np.asarray(case["speed"].values, dtype=float)[grows]
    where = ", ".join(f"{v:g} m/s: {1e3 * l:.3g} mm ({ff:.0f} Hz)" for v, l, ff in zip(V, lam, f))
    edge = [l for l in lam if l in (lam_all.min(), lam_all.max())]
    note = " (at the edge of the computed wavelengths: the band may continue beyond)" if edge else ""
    if grows.sum() == 1:
        return f"grows at one speed only ({where}){note}"
    # one band moves between constant frequency and constant wavelength: 0 <= d ln(lambda) <= d ln(V),
    # to one line's spacing; outside that the fastest line is in another band
    lnl = np.sort(np.log(lam_all[np.isfinite(lam_all) & (lam_all > 0)]))
    tol = float(np.max(np.diff(lnl))) if lnl.size > 1 else 0.0
    order = np.argsort(V)
    dV, dl = np.diff(np.log(V[order])), np.diff(np.log(lam[order]))
    jumps = [(V[order][i], V[order][i + 1]) for i in range(dV.size) if not (-tol <= dl[i] <= dV[i] + tol)]
    if jumps:
        between = ", ".join(f"{a:g} and {b:g} m/s" for a, b in jumps)
        return f"two bands: the fastest line changes band between {between} ({where}){note}"
    sf, sl = np.log(f.max() / f.min()), np.log(lam.max() / lam.min())
    if sf < sl / 2:
        kind = "constant frequency"
    elif sl < sf / 2:
        kind = "constant wavelength"
    else:
        kind = "neither frequency nor wavelength"
    return f"{kind} ({where}){note}"


def summary_table(ds: xr.Dataset) -> str:
    """A markdown table of study_dataset: per case and speed the fastest line, the pinned-pinned line
    and the number of growing lines, and per case the verdict.

    Parameters
    ----------
    ds : xr.Dataset
        The study's dataset (study_dataset).

    Returns
    -------
    str
        Markdown text.
    """
    out = ["| mechanism | track | speed (m/s) | fastest line | its rate (dB per 1e5 axles) | near pinned-pinned | its rate | growing lines |",
           "|---|---|---|---|---|---|---|---|"]
    for i in range(ds.sizes["case"]):
        c = ds.isel(case=i)
        for k, V in enumerate(c["speed"].values):
            r = float(c["fastest_dB_per_1e5_axles"].values[k])
            if np.isnan(r):
                continue
            lf, ff = 1e3 * float(c["fastest_wavelength"].values[k]), float(c["fastest_frequency"].values[k])
            lp = float(c["pinned_pinned_wavelength"].values[k])
            out.append(f"| {c['mechanism'].item()} | {c['track'].item()} | {V:g} | {lf:.3g} mm ({ff:.0f} Hz) | {r:+.2f} | "
                       f"{1e3 * lp:.3g} mm ({V / lp:.0f} Hz) | {float(c['pinned_pinned_dB_per_1e5_axles'].values[k]):+.2f} | "
                       f"{int(c['growing_lines'].values[k])} |")
    out += ["", "| mechanism | track | over speed |", "|---|---|---|"]
    for i in range(ds.sizes["case"]):
        c = ds.isel(case=i)
        out.append(f"| {c['mechanism'].item()} | {c['track'].item()} | {c['verdict'].item()} |")
    return "\n".join(out) + "\n"
