"""The wavenumber method against independent methods written without rail/:
a time-domain finite-element model (tests/independent/fe_track.py) and a direct superposition
method for stationary loads and statics (tests/independent/stationary_direct.py)."""

import numpy as np
import pytest

from independent import fe_track as fe
from rail import moving
from rail import track as T


@pytest.fixture(scope="module")
def fe_params():
    return fe.default_params()


@pytest.fixture(scope="module")
def viscous_track(fe_params):
    """The FE model's track (Table 1 with viscous dashpots) in rail's dataclasses."""
    P = fe_params
    return T.Track(
        T.Rail(P["E"], P["G"], P["rho"], P["A"], P["I"], P["kappa"], 0.0, P["tau_rail"]),
        T.Pad(P["k_pad"], 0.0, P["c_pad"]),
        T.Sleeper(P["m_sleeper"], P["L"]),
        T.Ballast(P["k_ballast"], 0.0, P["c_ballast"]),
        "viscous",
    )


def _fe_run(P, V, f):
    # 100 bays, 10 elements per bay, Newmark dt = 2.5e-5 s; the load runs over bays 45-50 and is
    # compared over bays 47-50, after the start-up transient has decayed below 1e-4 (fe_track).
    L = P["L"]
    r = fe.moving_load(P, V, f, 100, 10, 2.5e-5, 45 * L, 50 * L)
    sel = r["x"] > 47 * L
    return r["t"][sel], r["w_local"][sel], r["x"][sel]


@pytest.mark.parametrize("V", [20.0, 40.0])
def test_moving_constant_load_matches_time_domain_finite_elements(fe_params, viscous_track, V):
    # Tolerance: 1 % of the fluctuation of the displacement over the bay. The FE model's own
    # error (elements, time step) is about 0.4 % of it (rms difference at K = 128), and the
    # truncated Fourier series adds its 1/n^2 tail at the sleeper (the kink of the deflection).
    t, w_fe, x = _fe_run(fe_params, V, 0.0)
    tab = moving.receptance_table(viscous_track, V, 64)
    Om0 = viscous_track.beta0 * V
    w = np.real(sum(tab.a(n, 0) * np.exp(1j * n * Om0 * t) for n in range(-64, 65)))
    fluctuation = w.max() - w.min()
    assert fluctuation > 0.02 * w.mean()  # the parametric variation is really there (3.8 %)
    assert np.abs(w_fe - w).max() < 0.01 * fluctuation
    # and the truncation error at the sleeper shrinks as harmonics are added
    errs = []
    for K in (16, 64):
        wk = np.real(sum(tab.a(n, 0) * np.exp(1j * n * Om0 * t) for n in range(-K, K + 1)))
        errs.append(np.abs(w_fe - wk).max())
    assert errs[1] < 0.6 * errs[0]


def test_moving_harmonic_load_matches_time_domain_finite_elements(fe_params, viscous_track):
    # A 300 Hz load at 40 m/s: displacement Re[e^{i Omega t} sum_n a_n(Omega) e^{i n Omega_0 t}].
    V, f = 40.0, 300.0
    t, w_fe, _ = _fe_run(fe_params, V, f)
    ns, a, _ = moving.moving_coefficients(viscous_track, V, 2 * np.pi * f, 32)
    Om0 = viscous_track.beta0 * V
    w = np.real(np.exp(2j * np.pi * f * t) * sum(ai * np.exp(1j * n * Om0 * t) for n, ai in zip(ns, a)))
    # FE time-step error for a 300 Hz load at dt = 2.5e-5 is 4e-4 of the amplitude (fe_track)
    assert np.abs(w_fe - w).max() < 3e-3 * np.abs(w).max()
