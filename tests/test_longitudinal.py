"""The rail head's longitudinal flexibility (rail.creepage.rail_flexibility): the moving-load receptances against
closed forms on a smeared foundation, a direct stationary solution written without the module
(tests/independent/rail_head_direct.py), reciprocity, their convergence in the harmonics, and the
coupled march against the closed loop of its own transfers."""

import dataclasses
import sys
from pathlib import Path

import numpy as np
import pytest

from rail.creepage import coupling
from rail import contact as C
from rail.creepage import rail_flexibility as lg
from rail.contact.passage import MarchInputs
from rail.track import Ballast, Pad, Rail, Sleeper, Track

sys.path.insert(0, str(Path(__file__).parent / "independent"))
import rail_head_direct as direct  # noqa: E402

RAIL = Rail(2.1e11, 8.1e10, 7850.0, 7.69e-3, 3.055e-5, 0.4, 0.01, 1.6e-6)  # config/config.yaml


def _track(L=0.6, damping="hysteretic"):
    """The default track (config/config.yaml) with its supports scaled to the spacing L (the same per metre)."""
    s = L / 0.6
    return Track(RAIL, Pad(3.5e8 * s, 0.25, 2.8e4 * s), Sleeper(162.0 * s, L), Ballast(5e7 * s, 1.0, 8e4 * s), damping)


TRACK = _track()


def test_the_rod_under_a_moving_load_on_a_smeared_foundation_is_the_closed_form():
    # Viscous supports: the smeared integrand is a quadratic in beta (residues, lg.smeared_rod_receptance).
    # The rod's decay length sqrt(EA L / k_x) = 9.8 m is far beyond L, so even L = 0.6 m is smeared:
    # measured 3.0e-5 (L = 0.6), 1.3e-5 (0.15); the floor is E A's damping taken at Omega in the closed form
    for L in (0.6, 0.15):
        head = lg.RailHead(_track(L, "viscous"), longitudinal_stiffness=1e7 * L / 0.6, longitudinal_viscous_damping=800 * L / 0.6)
        om = 2 * np.pi * 230.0
        a = lg.moving_head_matrix(head, 30.0, om, [0], kinds=("rod",), rtol=1e-7)["rod"][0, 0]
        assert abs(a / lg.smeared_rod_receptance(head, om, 30.0) - 1) < 1e-4


@pytest.mark.parametrize("f", [pytest.param(300.0, marks=pytest.mark.slow), 1000.0])
def test_the_rotation_tends_to_the_smeared_closed_form_as_the_supports_close_up(f):
    # psi per unit moment at the load (V -> 0) against the Timoshenko rail on a continuous foundation
    # K_s / L: measured 0.063, 0.0088, 0.0020 at 300 Hz and 0.117, 0.0016, 0.00039 at 1 kHz for
    # L = 0.6, 0.3, 0.15 m (order about 2 in L)
    om = 2 * np.pi * f
    err = []
    for L in (0.6, 0.3, 0.15):
        tr = _track(L)
        a = lg.moving_head_matrix(lg.RailHead(tr), 0.02, om, [0], kinds=("psiM",), rtol=1e-6)["psiM"][0, 0]
        err.append(abs(a / lg.smeared_rotation_receptance(tr, om) - 1))
    assert err[-1] < 3e-3, err
    assert np.log2(err[0] / err[2]) / 2 > 1.5, err  # observed order in L
    assert err[0] > 0.03  # the discrete supports do matter at L = 0.6 m


@pytest.fixture(scope="module", params=[pytest.param(300.0, marks=pytest.mark.slow), 1000.0])
def slow_load(request):
    """Moving receptances at V = 0.02 m/s against the direct stationary solution's Fourier coefficients
    over the load's position in the bay, a_n = (1 / L) int alpha(x0, x0) exp(-i n beta0 x0) dx0."""
    out = {}
    xs = (np.arange(64) + 0.5) / 64 * TRACK.L  # the midpoint rule: alpha(x0, x0) has a kink at the support (1/n^2 terms)
    head = lg.RailHead(TRACK, longitudinal_loss_factor=1.0)  # the rod's waves die out within the direct row
    for f in (request.param,):
        om = 2 * np.pi * f
        m = lg.moving_head_matrix(head, 0.02, om, np.arange(-3, 4), kinds=("rod", "psiM", "psiF", "wM", "dpsiF"), rtol=1e-7)
        beam = np.array([direct.stationary_beam(x, om, TRACK, n=150) for x in xs])
        rod = np.array([direct.stationary_rod(x, om, TRACK, head.longitudinal_stiffness, 1.0, n=300) for x in xs])
        ref = {"psiF": beam[:, 0], "psiM": beam[:, 1], "wM": beam[:, 2], "dpsiF": beam[:, 3], "rod": rod}
        out[f] = {k: (m[k][3:6, 3], np.array([np.mean(v * np.exp(-1j * n * TRACK.beta0 * xs)) for n in range(3)]))
                  for k, v in ref.items()}
    return out


def test_moving_receptances_tend_to_the_direct_stationary_solution_as_the_speed_vanishes(slow_load):
    # Measured: the beam's harmonics n = 1, 2 within 3e-4 of themselves, the means within 1e-6 of the
    # n = 0 term's scale; the rod's mean within 1e-3. psi/F is odd in x0 about a support: its mean
    # vanishes at rest (the moving table's is O(V)).
    (f,) = slow_load
    for kind in ("psiM", "psiF", "dpsiF", "rod"):
        mov, ref = slow_load[f][kind]
        scale = abs(ref[0]) if kind != "psiF" else abs(ref[1])
        assert abs(mov[0] - ref[0]) < 2e-3 * scale, (kind, mov[0], ref[0])
        if kind != "rod":  # the rod's n >= 1 are 1e-4 of its mean: the direct row's ends reach them
            for n in (1, 2):
                assert abs(mov[n] - ref[n]) < 2e-3 * abs(ref[n]), (kind, n, mov[n], ref[n])


def test_the_stationary_cross_receptance_is_reciprocal(slow_load):
    # psi at the load from a vertical force = w at the load from a moment (Maxwell-Betti), harmonic by
    # harmonic; and in the direct solution as well (an independent check of its Green's functions)
    for f in slow_load:
        mF, rF = slow_load[f]["psiF"]
        mM, rM = slow_load[f]["wM"]
        for n in (1, 2):
            assert abs(mF[n] - mM[n]) < 1e-3 * abs(mF[n])
            assert abs(rF[n] - rM[n]) < 1e-9 * abs(rF[n])


def test_the_parametric_response_converges_in_the_harmonics_with_the_observed_order():
    # The head's motion under a constant load passing the supports: |A[p, 0]| falls like p^-3 for the
    # vertical force (psi is C^1: the support reaction is a jump in shear) and like p^-2 for the tangential
    # force at high p (the rod's u_n has a kink at each spring). Measured at 40 m/s over p = 8..64: 3.0 and 2.2.
    K = 64
    tab = lg.head_table(lg.RailHead(TRACK), 40.0, K, 0.0)
    p = np.array([8, 16, 32, 64])
    aP, aQ = np.abs(tab.A_P[K + p, K]), np.abs(tab.A_Q[K + p, K])
    order_P = -np.polyfit(np.log(p), np.log(aP), 1)[0]
    order_Q = -np.polyfit(np.log(p[1:]), np.log(aQ[1:]), 1)[0]
    assert order_P > 2.6 and order_Q > 1.8, (order_P, order_Q)
    # the truncation at K: the tail beyond 32 harmonics is below 1e-3 of the first harmonic (beyond 16 it is
    # 2.3e-3: the pinned-pinned resonance sits at p = 16 at 40 m/s)
    assert np.sum(np.abs(tab.A_P[K + 33:, K])) < 1e-3 * abs(tab.A_P[K + 1, K])


def test_the_table_is_a_real_operator():
    # a real load gives a real response: A[-p, -k] = conj(A[p, k]) on the class nu = 0 (and nu = 1/2 maps onto itself)
    K = 6
    for nu in (0.0, 0.5):
        tab = lg.head_table(lg.RailHead(TRACK), 40.0, K, nu)
        A = tab.A_Q
        flip = A[::-1, ::-1]
        assert np.allclose(flip, A.conj(), rtol=0, atol=1e-6 * np.abs(A).max())


M0 = C.ContactMaterial(2.1e11, 0.3, 0.008, 0.46, 0.3, 0.3, -0.001)
V, P0, R = 40.0, 1e5, 0.46
A0 = float(C.hertz_half_length(P0, R, M0))


def _inputs(nodes=21):
    """March inputs of one 0.6 m bay under the constant load P0."""
    delta, Nx, Mm = C.rolling_grid(1.05 * A0, 0.6, nodes)
    spin = min(Nx, int(np.ceil(20 * 2 * 1.05 * A0 / delta)))
    steps = spin + Nx + 2 * Mm + 1
    P = np.full(steps, P0)
    return MarchInputs(P=P, a=C.hertz_half_length(P, R, M0), shape=None, delta=delta, Nx=Nx, M=Mm, spin=spin, min_shape=1.0, shift=0.0)


def test_the_coupled_march_closes_the_loop_of_its_own_transfers():
    # A constant load passing the supports: the rail's parametric u_bar (A_P P0, the head's strain E_P P0 and
    # A_Q Q0) modulates the creepage. Closed form from the march's own open-loop transfer of a given u_bar harmonic to Q (G_k,
    # steady base state: diagonal in the harmonics): (I - A_Q G) U = A_Q Q_open - A_P P + V E_P P / (i omega), Q = Q_open + G U.
    K = 8
    head = lg.RailHead(TRACK)
    mi = _inputs()
    num = C.ContactNumerics(21, "default", 1.0, "report", "wheel")
    mat = dataclasses.replace(M0, rail_flexibility=head)
    sol, info = coupling.march_with_creepage(mi, mat, V, num, tol=1e-9, harmonics=K)
    period = slice(mi.spin, mi.spin + mi.Nx)
    n = mi.Nx
    Qc = np.fft.fft(sol.Q[period]) / n
    base = C.solve_tangential(mi.P, mi.a, M0, V, mi.delta, mi.M)
    Qo = np.fft.fft(base.Q[period]) / n
    t = (np.arange(mi.P.size) - mi.spin) * mi.delta / V
    T = n * mi.delta / V
    G = np.zeros(2 * K + 1, dtype=complex)
    du = 1e-9
    for k in range(1, K + 1):
        s = C.solve_tangential(mi.P, mi.a, M0, V, mi.delta, mi.M, ubar=du * np.cos(2 * np.pi * k * t / T))
        G[K + k] = 2 * (np.fft.fft(s.Q[period]) / n)[k] / du - 0  # response at +k per unit cos amplitude
        G[K + k] -= 2 * Qo[k] / du
        G[K - k] = np.conj(G[K + k])
    op = lg.head_operator(head, V, K, 1)
    tab = op.tables[0]
    q = np.arange(-K, K + 1)
    Ph = np.fft.fft(mi.P[period]) / n
    lhs = np.eye(2 * K + 1) - tab.A_Q * G[None, :]
    wq = 2 * np.pi * q * V / 0.6
    strain = np.where(q != 0, V * (tab.E_P @ Ph[q % n]) / (1j * np.where(q != 0, wq, 1.0)), 0.0)  # V int eps dt
    U = np.linalg.solve(lhs, tab.A_Q @ Qo[q % n] - tab.A_P @ Ph[q % n] + strain)
    Qp = Qo[q % n] + G * U
    err = [abs(Qc[k] / Qp[K + k] - 1) for k in range(1, 5)]
    print("closed loop, harmonics 1-4:", err)
    assert max(err) < 1e-5, err  # measured 7e-11 to 1e-8: the Newton state is the closed loop
    # the rail's u_bar makes the force vary over the bay at all (the open loop's is constant)
    assert abs(Qc[1]) > 1e3 * abs(Qo[1])
    assert info["iterations"] <= 8


def test_without_the_rail_the_march_and_the_material_are_unchanged():
    mi = _inputs()
    num = C.ContactNumerics(21, "default", 1.0, "report", "wheel")
    a, info = coupling.march_with_creepage(mi, M0, V, num)
    b = C.solve_tangential(mi.P, mi.a, M0, V, mi.delta, mi.M)
    assert info is None and np.array_equal(a.work, b.work)
    assert "rail_flexibility" not in repr(M0)
    assert "rail_flexibility" in repr(dataclasses.replace(M0, rail_flexibility=lg.RailHead(TRACK)))


def test_the_march_needs_the_harmonics_with_the_rail():
    mat = dataclasses.replace(M0, rail_flexibility=lg.RailHead(TRACK))
    with pytest.raises(ValueError, match="needs harmonics"):
        coupling.march_with_creepage(_inputs(), mat, V, C.ContactNumerics(21, "default", 1.0, "report", "wheel"))


@pytest.mark.parametrize("key,value,match", [
    ("longitudinal_stiffness", -1.0, r"track.pad.longitudinal_stiffness = -1.0 N/m is not allowed"),
    ("longitudinal_stiffness", float("nan"), r"track.pad.longitudinal_stiffness = nan N/m is not allowed"),
    ("longitudinal_loss_factor", float("inf"), r"track.pad.longitudinal_loss_factor = inf is not allowed"),
    ("longitudinal_viscous_damping", -2.0, r"longitudinal_viscous_damping = -2.0 is not allowed"),
    ("head_height", 0.5, r"track.rail.head_height = 0.5 m is not allowed: it must be a finite number in \[0, 0.3\]"),
])
def test_bad_parameters_are_refused_naming_key_value_and_range(key, value, match):
    with pytest.raises(ValueError, match=match):
        lg.RailHead(TRACK, **{key: value})


def test_the_config_switch_builds_the_rail_and_the_results_say_so():
    from rail.app import api
    from rail.studies.validity import creepage_model_text
    on = api.load("dyn_rail").scenario.material
    assert isinstance(on.rail_flexibility, lg.RailHead) and on.rail_flexibility.bending
    assert on.rail_flexibility.head_height == 0.0911 and on.rail_flexibility.longitudinal_stiffness == 1e7
    assert "rail's longitudinal flexibility" in creepage_model_text(on)
    both = api.load("dyn_rail_trailer").scenario.material
    text = creepage_model_text(both)
    assert "torsional wheelset" in text and "rail's longitudinal flexibility (rod" in text and "not modelled" not in text
    off = api.load("default").scenario.material
    assert off.rail_flexibility is None and creepage_model_text(off) == ""
    rod = api.load("dyn_rail", changes={"rail_flexibility": {"model": "rod"}}).scenario.material
    assert not rod.rail_flexibility.bending


@pytest.mark.parametrize("damping", ["hysteretic", "viscous"])
def test_the_free_beam_matrix_displacement_term_is_the_tracks_free_receptance(damping):
    """H_ww of the (F, M) -> (W, Psi) matrix and rail.track.free_receptance are one quantity written twice
    (the bending and shear of the same Timoshenko rail): equal to rounding over wavenumber and frequency,
    below, near and above the rail's shear cut-on."""
    from rail.track import free_receptance

    tr = _track(damping=damping)
    beta = np.linspace(-60.0, 60.0, 241)[:, None]
    omega = 2 * np.pi * np.array([5.0, 300.0, 1069.0, 5000.0, 2.0e4])[None, :]
    H_ww = lg.free_beam_matrix(beta, omega, tr)[0]
    H = free_receptance(beta, omega, tr)
    np.testing.assert_allclose(H_ww, H, rtol=1e-11, atol=0.0)
