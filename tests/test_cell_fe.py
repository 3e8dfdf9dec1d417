"""The force of one wheel over the smooth rail on an irregular track (rail.cell, issue 34) against the
independent time-domain FE of tests/independent/fe_track.py (Timoshenko elements, Newmark, every support
its own properties and position). Viscous damping (the FE's). Compared by harmonics of the cell, as the
FE's docstring advises (its time record carries a ~12 kHz ripple of 0.25 % and spurious lines at the
element-passing harmonic): the force reconstructed from harmonics 0..24 of the cell must agree within
0.5 % of its fluctuation (issue 34). Slow: python -m pytest -m slow tests/test_cell_fe.py"""

import numpy as np
import pytest
from independent import fe_track as fe

from rail import interaction as I
from rail import moving
from rail import track as T
from rail.cell import make_cell

P = fe.default_params()
L = P["L"]
WHEEL, LOAD, KH = 1350.0, 1e5, 1.4e9
CASES = {  # (bays, spacing, factor on the pad, factor on the ballast)
    "voided": (4, [L] * 4, [1, 1, 1, 1], [1, 1e-3, 1, 1]),
    "uneven": (4, [0.55, 0.65, 0.60, 0.60], [1, 1, 1, 1], [1, 1, 1, 1]),
    "stiff_pad": (8, [L] * 8, [1, 1, 1, 4, 1, 1, 1, 1], [1] * 8),
}
KC = 24  # harmonics of the cell compared (well below the FE's element-passing lines)


def _model_track():
    return T.Track(T.Rail(P["E"], P["G"], P["rho"], P["A"], P["I"], P["kappa"], 0.0, P["tau_rail"]),
                   T.Pad(P["k_pad"], 0.0, P["c_pad"]), T.Sleeper(P["m_sleeper"], P["L"]),
                   T.Ballast(P["k_ballast"], 0.0, P["c_ballast"]), "viscous")


def _fe_cell(bays, spacing, pad, ballast):
    pos = np.concatenate([[0.0], np.cumsum(spacing)[:-1]])
    sup = [dict(k_pad=P["k_pad"] * p, c_pad=P["c_pad"] * p, k_ballast=P["k_ballast"] * b, c_ballast=P["c_ballast"] * b)
           for p, b in zip(pad, ballast)]
    return fe.make_cell(P, pos, float(np.sum(spacing)), sup)


def _model_harmonics(name, V):
    bays, spacing, pad, ballast = CASES[name]
    cell = make_cell(_model_track(), bays, spacing, pad, ballast)
    tab = moving.cell_receptance_table(cell, V, 24, rtol=1e-5)
    J = tab.harmonics
    F = I.solve_forces(tab, I.Wheels(WHEEL, 0.46, LOAD, (0.0,)), I.ContactSpring(KH),
                       I.Roughness(np.zeros(2 * J + 1, complex), bays), cell.mean_spacing)
    return F.P[0, J : J + KC + 1], cell.period


def _fe_harmonics(name, V, dt=5e-5, elements=8):
    # dt = 5e-5 s and 8 elements per bay: 1.6e-4 and 4e-5 of the largest harmonic (fe_track.wheel_force_smooth_rail),
    # far below the 0.5 % compared; four cells of run-in (the start-up falls about 12 times per cell)
    bays, spacing, pad, ballast = CASES[name]
    c = _fe_cell(bays, spacing, pad, ballast)
    Pc = c["period"]
    n_cells = 14
    r = fe.wheel_force_smooth_rail(P, c, V, n_cells, elements, dt, 5 * Pc, 10 * Pc, wheel_mass=WHEEL, static_load=LOAD,
                                   hertz_stiffness=KH)
    steps = int(round(Pc / (V * dt)))
    x, f = r["x"][-steps - 1 : -1], r["P"][-steps - 1 : -1]  # the last cell, after 4 cells of run-in
    k = np.arange(KC + 1)
    return np.exp(-2j * np.pi * np.outer(k, x / Pc)) @ f / steps


def _history(c, x, Pc):
    k = np.arange(1, len(c))
    return c[0].real + 2 * np.real(np.exp(2j * np.pi * np.outer(x / Pc, k)) @ c[1:])


@pytest.mark.slow
@pytest.mark.parametrize("V", [20.0, 40.0])
@pytest.mark.parametrize("name", list(CASES))
def test_cell_force_over_the_smooth_rail_agrees_with_the_time_domain_fe(name, V):
    cm, Pc = _model_harmonics(name, V)
    cf = _fe_harmonics(name, V)
    x = np.linspace(0, Pc, 2000, endpoint=False)
    hm, hf = _history(cm, x, Pc), _history(cf, x, Pc)
    err = np.abs(hm - hf).max() / np.ptp(hm)
    print(f"{name} {V:g} m/s: fluctuation {np.ptp(hm):.0f} N, largest difference {err:.2e} of it")
    assert err < 0.005
    # the check can fail: the uniform track's force (one bay, the same harmonics of the cell) differs from
    # the cell's by far more than the tolerance
    tab = moving.receptance_table(_model_track(), V, 24, rtol=1e-5)
    Fu = I.solve_forces(tab, I.Wheels(WHEEL, 0.46, LOAD, (0.0,)), I.ContactSpring(KH), I.Roughness(np.zeros(49, complex)), L)
    N = CASES[name][0]
    cu = np.zeros(KC + 1, complex)
    cu[::N] = Fu.P[0, 24 : 24 + KC // N + 1]  # bay harmonic k is harmonic N k of the cell
    assert np.abs(_history(cu, x, Pc) - hm).max() / np.ptp(hm) > 20 * err
