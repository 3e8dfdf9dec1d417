"""Stability suite: stiff, soft and extreme cases that must end in a checked result or a clear error.

A case is a set of overrides of the default configuration (config/stability.yaml). ``run_case``
computes, in the order of the growth workflow: the configuration (validated), the receptance
table at the case's speed, the normal forces, the wear of one passage and a short growth run.
Any exception is caught and recorded with its type and message; a result that completes is put
through checks that can fail:

* every number finite;
* the wavenumber quadrature converged (its error bound within 10 times numerics.track.rtol);
* the harmonic truncation converged: the force along the bay with K and with K/2 harmonics
  differs by less than 10 % of its fluctuation (smooth rail);
* the contact state periodic over the bay (the second bay repeats the first);
* the mean tangential force against Carter's for the static load (steady theory), within 10 %
  for a dynamic load (it varies along the bay) and 0.5 % when the whole patch slips (mu_d P);
* the growth run's update error below growth.step_tolerance (otherwise GrowthStepError).

The outcome is 'ok' (all checks pass), 'error' (a clear, anticipated error: configuration,
contact loss, multiple contact, update step too large) or 'failed' (anything else: an
unanticipated exception or a failed check). The suite expects no 'failed' outcome.
"""

from __future__ import annotations

import io
import re
import time
import traceback

import numpy as np
import xarray as xr

from .. import chain, contact, growth, interaction, moving
from ..scenario import Scenario
from ..setup.build import scenario as build_scenario
from ..setup.config import ConfigError, deep_merge, resolve
from ..setup.io import data_var

__all__ = ["CLEAR_ERRORS", "run_case", "outcome_matches"]

# Error types that name their cause (the parameter and its range, or the physical assumption
# that stopped holding). Anything else is an unanticipated failure.
CLEAR_ERRORS = (ConfigError, ValueError, contact.ContactError, interaction.ContactLossError, growth.GrowthStepError)


def _truncation(scn: Scenario, tab, forces, rough, points: int = 256):
    """Largest difference of the force along the bay between K and K/2 harmonics (both with the
    1/p^2 tail), over the force fluctuation: the truncation is converged when it is small. None
    when the roughness has harmonics above K/2."""
    K, K2 = tab.harmonics, tab.harmonics // 2
    k = np.arange(-K, K + 1)
    if K2 < 1 or np.any(rough.Z[np.abs(k) > K2] != 0):
        return None
    sl = slice(K - K2, K + K2 + 1)
    half = moving.MovingReceptance(tab.speed, K2, tab.offsets, tab.A[:, sl, sl], tab.error[:, sl, sl], tab.nodes)
    F2 = chain.solve_forces(scn, half, interaction.Roughness(rough.Z[sl]))
    x = np.linspace(0.0, scn.L, points, endpoint=False)
    P = interaction.force_history(forces, x)[0]
    P2 = interaction.force_history(F2, x)[0]
    return float(np.max(np.abs(P - P2)) / max(np.ptp(P), 1e-300))


def _checks(scn: Scenario, tab, forces, rough, w, hist):
    """List of (name, value, limit, passed)."""
    out = []
    # the wavenumber quadrature converged: its error bound (the half-node rule's difference) on
    # the diagonal, relative to the diagonal, at most 10 times the requested tolerance
    d = np.arange(tab.A.shape[1])
    qerr = float(np.max(tab.error[0, d, d] / np.abs(tab.A[0, d, d])))
    rtol = scn.track_numerics.rtol
    out.append(("quadrature error bound over a_0 on the diagonal", qerr, 10 * rtol, qerr <= 10 * rtol))
    finite = bool(np.all(np.isfinite(forces.P)) and np.all(np.isfinite(w.depth)) and np.all(np.isfinite(w.q)) and np.all(np.isfinite(hist.Z)))
    out.append(("all results finite", float(finite), 1.0, finite))
    P0 = scn.wheels.static_load
    material = scn.material
    trunc = _truncation(scn, tab, forces, rough)
    if trunc is not None:
        out.append(("force with K against K/2 harmonics / fluctuation", trunc, 0.1, trunc < 0.1))
    out.append(("contact state periodicity over the bay", float(w.periodicity), 1e-3, w.periodicity < 1e-3))
    R = material.wheel_radius
    if material.creepage != 0:
        Qc = float(contact.carter(np.zeros(1), P0, material, forces.speed, R)[2])
        dev = abs(np.mean(w.Q) / Qc - 1)
        limit = 5e-3 if w.full_slip == 1.0 else 0.1
        out.append(("mean tangential force / Carter's - 1", float(dev), limit, dev < limit))
    else:
        rel = float(np.max(np.abs(w.Q)) / (material.friction_dynamic * P0))
        out.append(("largest tangential force / mu_d P (zero creepage: 0 for identical materials)", rel, 0.05, rel < 0.05))
    err = float(np.nanmax(hist.step_error)) if np.isfinite(hist.step_error).any() else 0.0
    tol = scn.growth.step_tolerance
    out.append(("largest estimated update error", err, tol, err <= tol))
    return out


def run_case(defaults: dict, schema: dict, name: str, case: dict, numerics: dict | None = None) -> dict:
    """Run one stability case; returns a record (JSON-friendly dict).

    Parameters
    ----------
    defaults : dict
        The validated default configuration the case's overrides are merged onto.
    schema : dict
        config/schema/config.schema.yaml.
    name : str
        The case's name.
    case : dict
        {'description', 'overrides' (config keys), 'speed' [m/s], 'passages', 'passages_per_update'}.
    numerics : dict, optional
        Overrides of ``numerics`` (reduced resolution for the test suite).

    Returns
    -------
    dict
        case, description, status ('ok' or 'failed'), stage reached, error_type and message, the checks
        (name, value, limit, passed), full_slip [-] and cpu_s [s].
    """
    rec = {"case": name, "description": case.get("description", ""), "status": "failed", "stage": "config",
           "error_type": "", "message": "", "checks": [], "full_slip": 0.0, "cpu_s": 0.0}
    t0 = time.process_time()
    try:
        speed = float(case.get("speed", 40.0))
        # the case's own overrides win over reduced test numerics; its speed is validated too
        over = deep_merge({"numerics": numerics} if numerics else {}, case.get("overrides", {}))
        g = {"growth": {k: case[k] for k in ("passages", "passages_per_update") if k in case}, "speeds": [speed]}
        if g["growth"]:
            g["growth"]["save_every"] = g["growth"].get("passages_per_update", defaults["growth"]["passages_per_update"])
        source = f"stability case {name}"
        scn = build_scenario(resolve(defaults, schema, deep_merge(over, g), source=source), name, source)
        rec["stage"] = "receptance table"
        tab = chain.receptance_table(scn, speed)
        rec["stage"] = "normal forces"
        rough = chain.initial_roughness(scn, speed)
        forces = chain.solve_forces(scn, tab, rough)
        rec["stage"] = "contact and wear"
        w = chain.passage_wear(scn, forces, rough)
        rec["full_slip"] = float(w.full_slip)
        rec["stage"] = "growth"
        hist = chain.grow(scn, tab, rough, progress=io.StringIO())
        rec["stage"] = "checks"
        checks = _checks(scn, tab, forces, rough, w, hist)
        rec["checks"] = [{"name": n, "value": v, "limit": lim, "passed": bool(p)} for n, v, lim, p in checks]
        rec["status"] = "ok" if all(p for *_, p in checks) else "failed"
        if rec["full_slip"] > 0:
            rec["message"] = f"full slip (no stick zone) over {100 * rec['full_slip']:.0f} % of the bay, reported"
        rec["stage"] = "done"
    except CLEAR_ERRORS as e:
        rec["status"], rec["error_type"], rec["message"] = "error", type(e).__name__, str(e)
    except Exception as e:  # noqa: BLE001 - recorded as an unanticipated failure
        rec["status"], rec["error_type"] = "failed", type(e).__name__
        rec["message"] = f"{e} | {traceback.format_exc(limit=3)}"
    rec["cpu_s"] = time.process_time() - t0
    return rec


def outcome_matches(rec: dict, expect) -> bool:
    """Whether a case's record is what config/stability.yaml expects: 'ok', or {'error': regex}.

    Parameters
    ----------
    rec : dict
        A case's record (run_case).
    expect : str or dict
        'ok', or {'error': regex}.

    Returns
    -------
    bool
    """
    if expect == "ok":
        return rec["status"] == "ok"
    return rec["status"] == "error" and re.search(expect["error"], rec["message"]) is not None


def stability_dataset(records: list[dict], expect: dict, critical_speed: float) -> xr.Dataset:
    """Outcomes of the stability suite, one entry per case (rail.studies.stability.run_case records);
    as_expected is 1 when the outcome is the expected one.

    Parameters
    ----------
    records : list of dict
        run_case's records.
    expect : dict
        {case: 'ok' or {'error': regex}} from config/stability.yaml.
    critical_speed : float
        The default track's critical speed [m/s].

    Returns
    -------
    xr.Dataset
        Per case: description, status, error type, message, stage, checks, the expected outcome,
        as_expected, full slip [-] and CPU time [s].
    """
    names = [r["case"] for r in records]

    def col(key):
        return np.array([str(r[key]) for r in records])

    checks = np.array(["; ".join(f"{c['name']} {c['value']:.3g} (limit {c['limit']:.3g}) {'pass' if c['passed'] else 'FAIL'}"
                                 for c in r["checks"]) for r in records])
    expected = np.array(["ok" if expect[n] == "ok" else f"error: {expect[n]['error']}" for n in names])
    matches = np.array([int(outcome_matches(r, expect[r["case"]])) for r in records])
    return xr.Dataset(
        {
            "description": data_var("case", col("description"), "1", "what the case tests"),
            "status": data_var("case", col("status"), "1", "ok (checks passed), error (clear error naming the cause) or failed"),
            "error_type": data_var("case", col("error_type"), "1", "type of the error that stopped the case"),
            "message": data_var("case", col("message"), "1", "error message, or a note (full slip)"),
            "stage": data_var("case", col("stage"), "1", "computation stage reached"),
            "checks": data_var("case", checks, "1", "checks of a completed case: value, limit, outcome"),
            "expected": data_var("case", expected, "1", "expected outcome (config/stability.yaml)"),
            "as_expected": data_var("case", matches, "1", "1 when the outcome is the expected one"),
            "full_slip": data_var("case", np.array([float(r["full_slip"]) for r in records]), "1",
                                  "fraction of the bay without a stick zone (one passage)"),
            "cpu_time": data_var("case", np.array([float(r["cpu_s"]) for r in records]), "s", "CPU time of the case"),
        },
        coords={"case": data_var("case", np.array(names), "1", "stability case")},
        attrs={"critical_speed_m_per_s": critical_speed},
    )


def stability_rows(ds: xr.Dataset) -> list[list[str]]:
    """Rows (header first) of the stability outcome table.

    Parameters
    ----------
    ds : xr.Dataset
        stability_dataset's.

    Returns
    -------
    list of list of str
        The header first.
    """
    rows = [["case", "what", "outcome", "as expected", "evidence (checks or error message)", "CPU (s)"]]
    for i, c in enumerate(ds["case"].values):
        ev = str(ds["checks"].values[i]) if str(ds["status"].values[i]) == "ok" else f"{ds['error_type'].values[i]}: {ds['message'].values[i]}"
        if str(ds["status"].values[i]) == "ok" and str(ds["message"].values[i]):
            ev = f"{ds['message'].values[i]}; {ev}"
        ev = " ".join(ev.replace("|", "/").split())  # one line per table cell
        rows.append([str(c), str(ds["description"].values[i]), str(ds["status"].values[i]),
                     "yes" if ds["as_expected"].values[i] else "NO", ev, f"{float(ds['cpu_time'].values[i]):.1f}"])
    return rows
