"""Stability suite (config/stability.yaml): every stiff and extreme case ends in a result that passes
its checks or in a clear error naming the cause; plus the checks the suite relies on."""

import io
from pathlib import Path

import numpy as np
import pytest

from model import scenario

from rail import chain
from rail import contact as C
from rail import interaction as I
from rail import moving
from rail import track as T
from rail import wear as W
from rail.growth import GrowthStepError
from rail.setup.config import load_yaml
from rail.studies import stability

ROOT = Path(__file__).resolve().parents[1]
DEFAULTS = load_yaml(ROOT / "config/config.yaml")
SCHEMA = load_yaml(ROOT / "config/schema/config.schema.yaml")
SUITE = load_yaml(ROOT / "config/stability.yaml")
REDUCED = {"contact": {"nodes": 41}}  # the workflow runs 81 nodes; the harmonics stay at their defaults (the truncation check needs them)


# the cases that take longest (6-18 s each on a shared 2-core machine) run in the slow run
_SLOW_CASES = {"low_speed", "light_damping", "even_nodes", "stiff_pad", "near_critical_speed", "soft_pad", "high_speed",
               "saturated_creepage", "above_critical_speed"}


@pytest.mark.parametrize("name", [pytest.param(n, marks=pytest.mark.slow) if n in _SLOW_CASES else n
                                  for n in SUITE["cases"]])
def test_stability_case_ends_as_expected(name):
    case = {**SUITE["defaults"], **SUITE["cases"][name]}
    rec = stability.run_case(DEFAULTS, SCHEMA, name, case, numerics=REDUCED)
    assert rec["status"] != "failed", rec
    assert stability.outcome_matches(rec, case["expect"]), rec
    if rec["status"] == "ok":
        assert rec["checks"] and all(c["passed"] and np.isfinite(c["value"]) for c in rec["checks"])


def test_suite_covers_the_required_cases():
    cases = SUITE["cases"]
    pads = {c.get("overrides", {}).get("track", {}).get("pad", {}).get("stiffness") for c in cases.values()}
    assert {3.5e9, 1.0e7} <= pads
    speeds = {c.get("speed") for c in cases.values()}
    assert {5.0, 120.0, 240.0, 300.0} <= speeds


def _track(pad=3.5e8, eta_rail=0.01):
    return T.Track(T.Rail(2.1e11, 0.81e11, 7850.0, 7.69e-3, 30.55e-6, 0.4, eta_rail), T.Pad(pad, 0.25), T.Sleeper(162.0, 0.6), T.Ballast(50e6, 1.0))


def test_undamped_rail_is_refused_by_the_moving_load_solver():
    with pytest.raises(ValueError, match=r"track\.rail\.loss_factor = 0\.0 is not allowed: the moving-load wavenumber integrals need rail damping"):
        moving.receptance_table(_track(eta_rail=0.0), 40.0, 8)


def test_critical_speed_against_a_beam_on_an_elastic_foundation():
    # With a very soft pad (1e7 N/m) the sleepers hardly move and the rail is a beam on an elastic
    # foundation of stiffness s = (k_P k_B / (k_P + k_B)) / L per metre: c_cr = (4 s EI / m^2)^(1/4)
    # = 559 m/s (Euler-Bernoulli, continuous, undamped). The discrete, damped Timoshenko track
    # gives 523 m/s (6.5 % lower).
    soft = _track(pad=1e7)
    r = soft.rail
    s = 1e7 * 50e6 / (1e7 + 50e6) / 0.6
    c_beam = (4 * s * r.youngs_modulus * r.second_moment_of_area / (r.density * r.area) ** 2) ** 0.25
    assert moving.critical_speed(soft, v_min=300.0, v_max=800.0) == pytest.approx(c_beam, rel=0.1)
    # the default track: the sleeper mass takes part and lowers it to 268 m/s; the suite's
    # near-critical case (240 m/s) is 0.9 of it and its supercritical case (300 m/s) 1.1 times it
    vc = moving.critical_speed(_track(), v_min=200.0, v_max=400.0)
    assert 240.0 / vc == pytest.approx(0.9, abs=0.03) and 300.0 / vc == pytest.approx(1.1, abs=0.03)


MATERIAL = C.ContactMaterial(2.1e11, 0.3, 0.008, 0.575, 0.3, 0.3, -0.001)


def test_saturated_creepage_gives_full_slip_reported_and_mu_P():
    # creepage three times the saturation value: no stick zone anywhere, Q = mu_d P (Carter's
    # saturated limit) at every position of the bay, and full slip reported
    tr = _track()
    tab = moving.receptance_table(tr, 40.0, 16)
    rough = I.Roughness.smooth(16)
    F = I.solve_forces(tab, I.Wheels(1350.0, 0.575, 1e5, (0.0,)), I.ContactSpring(1.4e9, 0.0), rough, tr.L)
    m = C.ContactMaterial(2.1e11, 0.3, 0.008, 0.575, 0.3, 0.3, -0.01)
    w = W.bay_wear(F, 0, rough, m, W.WearLaw(7850.0, 2.5e-9), C.ContactNumerics(41, "default", 1.0, "report", "wheel"))
    assert w.full_slip == 1.0
    assert np.abs(w.Q / (0.3 * w.P) - 1).max() < 5e-3
    w0 = W.bay_wear(F, 0, rough, MATERIAL, W.WearLaw(7850.0, 2.5e-9), C.ContactNumerics(41, "default", 1.0, "report", "wheel"))
    assert w0.full_slip == 0.0


def _run(step, passages, tol=0.05, K=24):
    tr = _track()
    tab = moving.receptance_table(tr, 40.0, K)
    scn = scenario(tr, MATERIAL, I.ContactSpring(1.4e9, 0.0), K=K, nodes=21, passages=passages, step=step, save_every=passages, tol=tol)
    return chain.grow(scn, tab, I.Roughness.smooth(K), progress=io.StringIO())


def test_update_error_estimate_is_first_order_in_the_step():
    # the estimate (h/2)|W(Z') - W(Z)| / |Z'| of the first update halves when the step halves
    e20 = _run(20000, 40000).step_error
    e10 = _run(10000, 20000).step_error
    assert e20[0] / e10[0] == pytest.approx(2.0, rel=0.1)
    assert len(e20) == 2 and len(e10) == 2  # one per update, the last from the extra evaluation


def test_update_step_too_large_stops_with_a_clear_error():
    with pytest.raises(GrowthStepError, match=r"growth\.passages_per_update = 20000 is too large: .* use at most about \d+ passages per update"):
        _run(20000, 40000, tol=1e-4)
