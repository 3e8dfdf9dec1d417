"""Convergence study: the error of what the figures show against a refined reference, with CPU time.

Three quantities, one per stage of the model:

* ``force``  : the normal force along the bay on a smooth rail (Fig. 22), at ``points`` positions.
  Error: max abs(P - P_ref) over the fluctuation max P_ref - min P_ref.
* ``wear``   : the wear spectrum of one passage over a 10 um harmonic roughness (Figs 13-19),
  Delta Z_k for k <= K. Error: harmonic_error, each harmonic against itself.
* ``growth`` : the roughness coefficients Z_k after the growth run from a smooth rail (Fig. 23).
  Errors: harmonic_error (the plotted one), and the largest level difference in dB over the
  harmonics within 40 dB of the highest level.

Every error of a spectrum is judged per harmonic against that harmonic, never against a larger
total such as the mean wear: an error of 0.3 % of the mean wear can be 30 % of the harmonic that
decides whether roughness grows.

Each ``*_quantity`` function returns (values, cpu_seconds) and measures only its own stage (the
receptance table is timed for the track settings, not for the contact and growth settings).
"""

from __future__ import annotations

import dataclasses
import io
import time

import numpy as np
import xarray as xr

from .. import chain
from ..growth import levels_dB
from ..interaction import Roughness, force_history
from ..scenario import Scenario
from ..setup.io import data_var

__all__ = ["force_quantity", "wear_quantity", "growth_quantity", "force_error", "harmonic_error", "level_error_dB",
           "pareto_front", "with_setting", "default_settings", "convergence_dataset", "convergence_rows"]

WITHIN_DB = 40.0  # harmonics within this many dB of the largest are judged


def force_quantity(scn: Scenario, speed: float, points: int = 601):
    """Force [N] on a smooth rail at ``points`` positions over the bay for one wheel, and the CPU time
    [s] of the receptance table (scn.track_numerics) and the force solution.

    Parameters
    ----------
    scn : Scenario
    speed : float
        Train speed [m/s].
    points : int
        Positions over the bay [-].

    Returns
    -------
    tuple of (ndarray, float)
        The force [N] at the positions, and the CPU time [s].
    """
    t0 = time.process_time()
    one = chain.single_wheel(scn)
    tab = chain.receptance_table(one, speed)
    F = chain.solve_forces(one, tab, Roughness.smooth(one.harmonics))
    x = np.linspace(0.0, scn.L, points, endpoint=False)
    P = force_history(F, x)[0]
    return P, time.process_time() - t0


def wear_quantity(scn: Scenario, table, frequency: float, amplitude: float):
    """Wear spectrum Delta Z_k (k = -K..K) [m] of one passage of one wheel over a harmonic roughness
    of ``amplitude`` [m] at ``frequency`` [Hz], its mean wear depth [m], and the CPU time [s] of the
    forces, contact and wear (scn.contact_numerics).

    Parameters
    ----------
    scn : Scenario
    table : rail.moving.ReceptanceTable
        The track's table at the speed.
    frequency : float
        Excitation frequency [Hz].
    amplitude : float
        Roughness amplitude [m].

    Returns
    -------
    tuple of (ndarray, float, float)
        Delta Z_k [m], the mean wear depth [m] and the CPU time [s].
    """
    t0 = time.process_time()
    one = chain.single_wheel(scn)
    rough = Roughness.harmonic(amplitude, table.speed / frequency, scn.L, table.harmonics)
    w = chain.passage_wear(one, chain.solve_forces(one, table, rough), rough)
    return w.Z, float(w.depth.mean()), time.process_time() - t0


def growth_quantity(scn: Scenario, table):
    """Roughness Z_k [m] after scn.growth.passages from a smooth rail, and the CPU time [s].

    Parameters
    ----------
    scn : Scenario
    table : rail.moving.ReceptanceTable
        The track's table at the speed.

    Returns
    -------
    tuple of (ndarray, float)
        Z_k, k = -K..K [m], and the CPU time [s].
    """
    t0 = time.process_time()
    h = chain.grow(scn, table, Roughness.smooth(table.harmonics), progress=io.StringIO())
    return h.Z[-1], time.process_time() - t0


def with_setting(scn: Scenario, setting: str, value: float) -> Scenario:
    """The scenario with one numerical setting of the convergence study changed: 'harmonics', 'rtol'
    (receptance table), 'nodes', 'nodes_growth' (contact grid) or 'passages_per_update' (the growth
    step, saving only at the end).

    Parameters
    ----------
    scn : Scenario
    setting : str
        One of harmonics, rtol, nodes, nodes_growth, passages_per_update.
    value : float
        Its value [-] (a count, or the relative tolerance).

    Returns
    -------
    Scenario
    """
    if setting in ("harmonics", "rtol"):
        tn = scn.track_numerics
        tn = dataclasses.replace(tn, harmonics=int(value)) if setting == "harmonics" else dataclasses.replace(tn, rtol=float(value))
        return dataclasses.replace(scn, track_numerics=tn)
    if setting in ("nodes", "nodes_growth"):
        return dataclasses.replace(scn, contact_numerics=dataclasses.replace(scn.contact_numerics, nodes=int(value)))
    if setting == "passages_per_update":
        g = dataclasses.replace(scn.growth, passages_per_update=int(value), save_every=scn.growth.passages)
        return dataclasses.replace(scn, growth=g)
    raise ValueError(f"convergence setting {setting!r} is not known: it must be one of harmonics, rtol, nodes, nodes_growth, passages_per_update.")


def default_settings(scn: Scenario) -> dict:
    """The default value of every setting of the convergence study.

    Parameters
    ----------
    scn : Scenario

    Returns
    -------
    dict
        {setting: value [-]}.
    """
    return {"rtol": scn.track_numerics.rtol, "harmonics": scn.track_numerics.harmonics, "nodes": scn.contact_numerics.nodes,
            "nodes_growth": scn.contact_numerics.nodes, "passages_per_update": scn.growth.passages_per_update}


def force_error(P, P_ref) -> float:
    """max abs(P - P_ref) over the fluctuation of P_ref, -.

    Parameters
    ----------
    P, P_ref : array_like
        Forces at the same positions [N].

    Returns
    -------
    float
        The error [-].
    """
    return float(np.max(np.abs(np.asarray(P) - P_ref)) / np.ptp(P_ref))


def harmonic_error(Z, Z_ref, within_dB: float = WITHIN_DB, k_max: int | None = None) -> float:
    """Largest relative error of a harmonic against itself, max_k abs(Z_k / Z_k,ref - 1), over the
    harmonics 1 <= k <= k_max whose reference amplitude is within ``within_dB`` of the largest, -.

    abs(Z / Z_ref - 1) bounds both the relative amplitude error and the phase error (in radians, for
    small errors). Z, Z_ref : coefficients k = -K..K (the spectra may have different K; the common
    harmonics k <= min(K, K_ref) are compared).

    Parameters
    ----------
    Z, Z_ref : array_like of complex
        Coefficients k = -K..K [m] (or wear spectra [m]).
    within_dB : float
        Harmonics compared: within this of the largest reference amplitude [dB].
    k_max : int, optional
        Highest harmonic compared [-].

    Returns
    -------
    float
        The error [-].
    """
    K, Kr = (len(Z) - 1) // 2, (len(Z_ref) - 1) // 2
    n = min(K, Kr) if k_max is None else min(K, Kr, k_max)
    a = np.asarray(Z)[K + 1 : K + 1 + n]
    b = np.asarray(Z_ref)[Kr + 1 : Kr + 1 + n]
    sel = np.abs(b) >= np.abs(b).max() * 10 ** (-within_dB / 20)
    return float(np.max(np.abs(a[sel] / b[sel] - 1)))


def level_error_dB(Z, Z_ref, k_max: int | None = None, within_dB: float = WITHIN_DB) -> float:
    """Largest level difference (dB) over the harmonics k <= k_max whose reference level is within
    ``within_dB`` of the highest reference level.

    Parameters
    ----------
    Z, Z_ref : array_like of complex
        Coefficients k = -K..K [m].
    k_max : int, optional
        Highest harmonic compared [-].
    within_dB : float
        Harmonics compared: within this of the highest reference level [dB].

    Returns
    -------
    float
        The largest difference [dB].
    """
    K = (len(Z_ref) - 1) // 2
    k_max = K if k_max is None else min(k_max, K)
    ref = levels_dB(Z_ref)[:k_max]
    lev = levels_dB(Z)[:k_max]
    sel = ref >= ref.max() - within_dB
    return float(np.max(np.abs(lev[sel] - ref[sel])))


def pareto_front(times, errors) -> np.ndarray:
    """True for each point that no other point beats in both CPU time and error (ties allowed).

    Parameters
    ----------
    times : array_like
        CPU time of each point [s].
    errors : array_like
        Its error [-].

    Returns
    -------
    ndarray of bool
    """
    t, e = np.asarray(times, float), np.asarray(errors, float)
    out = np.ones(len(t), dtype=bool)
    for i in range(len(t)):
        better = (t <= t[i]) & (e <= e[i]) & ((t < t[i]) | (e < e[i]))
        out[i] = not better.any()
    return out


def _cz(ds, re_name, im_name):
    return ds[re_name].values + 1j * ds[im_name].values


def convergence_dataset(points: dict, study: dict, defaults: dict) -> xr.Dataset:
    """Errors of the convergence study against each setting's reference (rail.studies.convergence).

    One entry per non-reference point, dimension 'point'. For wear and growth points, error is the
    largest error of a harmonic against itself (harmonic_error, harmonics within 40 dB of the largest;
    for wear points the largest over the wear frequencies) and, for growth, error_dB the level error
    within 40 dB.

    Parameters
    ----------
    points : dict
        {(setting, value): point dataset}.
    study : dict
        config/convergence.yaml.
    defaults : dict
        {setting: default value}.

    Returns
    -------
    xr.Dataset
        Per point: setting, value, error [-], error_dB [dB], CPU time [s], reference CPU time [s], whether
        it is the default and on the Pareto front.
    """
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
            "cpu_time": data_var("point", times, "s", "CPU time of the computation (one core)"),
            "error": data_var("point", errors, "1",
                              f"error against the reference: force / fluctuation; wear and roughness: "
                              f"largest |Z_k / Z_k,ref - 1| over the harmonics within {WITHIN_DB:g} dB of the largest"),
            "error_dB": data_var("point", np.array([r[5] for r in rows]), "dB",
                                 f"largest roughness level error within {WITHIN_DB:g} dB of the highest level (growth points)"),
            "is_default": data_var("point", np.array([int(r[6]) for r in rows]), "1", "1 for the default value of the setting"),
            "on_pareto_front": data_var("point", front.astype(int), "1", "1 when no value of the same setting is both faster and more accurate"),
            "reference_value": data_var("point", np.array([r[7] for r in rows]), "1", "value of the setting in the reference"),
            "reference_cpu_time": data_var("point", np.array([r[8] for r in rows]), "s", "CPU time of the reference"),
        },
        coords={
            "setting": data_var("point", settings, "1", "numerical setting (config/convergence.yaml)"),
            "quantity": data_var("point", np.array([r[1] for r in rows]), "1", "figure quantity whose error is measured"),
            "value": data_var("point", np.array([r[2] for r in rows]), "1", "value of the setting"),
        },
        attrs={"speed_m_per_s": float(study["speed"])},
    )


def convergence_rows(ds: xr.Dataset) -> list[list[str]]:
    """Rows (header first) of the convergence summary: each setting's default, its error and time,
    the reference, and whether the default is on the Pareto front.

    Parameters
    ----------
    ds : xr.Dataset
        The study's dataset (convergence_dataset).

    Returns
    -------
    list of list of str
        The header first.
    """
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
                         f"{ds['reference_value'].values[i]:g} ({ds['reference_cpu_time'].values[i]:.1f})",
                         "yes" if ds["on_pareto_front"].values[i] else "no", allv])
        else:
            rows.append([str(name), "", "(not in the study)", "", "", "", "", allv])
    return rows
