"""Self-checks of the brute-force rolling simulation over a wavy rail (tests/independent/rolling_wavy.py).

Each compares with something the simulator does not contain: rail's own brute-force normal solver, the
Hertz and Carter closed forms, the exact single-zone identities of a small cosine (the patch shift
c = R_w r' J0(beta a), the pressure centroid R_w r' (J0 + J2), the half-length filter 2 J1 / (beta a)),
the steady rolling on a rail of constant curvature (an exact quasi-steady state in which the patch moves at
V (1 + dc/dx)), and the production model (patch-fixed march) for the centred patch. Numbers measured on
the default wheel (config/config.yaml: R_w = 0.575 m, b = 8 mm, mu = 0.3, creepage -0.001), P = 100 kN.
"""

import math

import numpy as np
import pytest
from scipy.special import j0

from independent import rolling_wavy as rw
from rail.contact import normal as N
from rail.contact import ContactMaterial, carter, compliance, hertz_half_length, hertz_pressure

MAT = ContactMaterial(2.1e11, 0.3, 0.008, 0.575, 0.3, 0.3, -0.001)
P = 1.0e5
V = 40.0
A0 = rw.hertz_a(MAT, P)
P0 = P / (math.pi * A0 * MAT.half_width)
_, _, Q_C, C_C = carter(np.zeros(1), P, MAT, V, MAT.wheel_radius)
W_C = abs(MAT.creepage) * Q_C / (2 * MAT.half_width)  # Carter's work per unit area of a rail point


def _steady(per_a, K=24, **kw):
    """Smooth rail, dithered (advance (K + 1) / K), after 10 transits: mean work over whole dither periods."""
    h = A0 / per_a
    adv = (K + 1) / K
    r = rw.simulate(MAT, P, V, rw.Smooth(), h, int(14 * A0 / h / adv), advance=adv, profile="parabola",
                    warmup=int(10 * A0 / h / adv), record_last=True, **kw)
    w = r.work[r.passed]
    w = w[: (w.size // (K + 1)) * (K + 1)]
    return r, w


def test_hertz_half_length_is_rails():
    assert rw.hertz_a(MAT, P) == pytest.approx(float(hertz_half_length(P, MAT.wheel_radius, MAT)), rel=1e-13)


@pytest.mark.parametrize("amplitude", [2e-7, 1e-5])
def test_normal_solver_equals_rails_brute_force(amplitude):
    # one zone (small cosine) and three zones (10 um at lambda = a: the wheel bridges troughs), the same
    # grid and gap: the own active set with cached Toeplitz inverses against rail.normal.solve_normal
    h = A0 / 40
    x = np.arange(-70, 71) * h
    beta = 2 * math.pi / A0
    gap = x**2 / (2 * MAT.wheel_radius) - amplitude * np.cos(beta * x + 0.3)
    Pw = P / (2 * MAT.half_width)
    ref = N.solve_normal(x, gap, Pw, MAT)
    row = rw.log_toeplitz(x.size + 2, h)
    i = np.arange(x.size)
    A = row[np.abs(i[:, None] - i[None, :])]
    p, _, active = rw.normal_contact(gap, Pw, compliance(MAT), h, A, rw._ToeplitzInverse(row), gap < gap.min() + 1e-6,
                                     1e-20)
    assert ref.zones == (1 if amplitude < 1e-6 else 3)
    np.testing.assert_allclose(p, ref.p, rtol=0, atol=1e-9 * ref.p.max())


def test_smooth_rail_every_particle_does_the_same_work_and_the_work_is_the_power():
    # wheel one cell per step: every particle sees the same discrete history (no grid-tied noise at all);
    # the work (trapezoidal traction x the step's mean slip, exit step included) equals |gamma| Q / (2b),
    # the frictional power over the sweep speed (measured 2e-5 at 25 cells per a). The start-up transient
    # from zero traction: 4e-7 of the work after 5 transits 2a, 1e-12 after 10
    h = A0 / 25
    r = rw.simulate(MAT, P, V, rw.Smooth(), h, int(24 * A0 / h), phi=0.3, warmup=int(20 * A0 / h))
    w = r.work[r.passed]
    assert w.std() < 1e-8 * w.mean()
    assert w.mean() == pytest.approx(abs(MAT.creepage) * r.force[-1] / (2 * MAT.half_width), rel=1e-4)


def test_smooth_rail_matches_carter_at_first_order():
    # Grid study (dither K = 24, the parabola; mean work over whole dither periods against Carter's
    # |gamma| Q / (2b)): -8.0e-3, -4.8e-3, -2.6e-3, -1.37e-3 at 25, 50, 100, 200 cells per a (observed order
    # 0.73, 0.88, 0.94 -> 1), i.e. -(0.20 ... 0.27) / (a / h); the traction's rms error over the patch
    # 6.5e-3, 4.6e-3, 3.2e-3, 2.2e-3 mu p0 (order 0.5: the square-root edges in piecewise-constant
    # elements), 0.0317-0.0327 / sqrt(a / h). Tolerances: 0.3 / (a / h) and 0.036 / sqrt(a / h).
    errs = []
    for per_a in (25, 50):
        r, w = _steady(per_a)
        err = w.mean() / W_C - 1
        errs.append(err)
        assert -0.3 / per_a < err < 0
        L = r.last
        qc = carter(L["x_rel"], P, MAT, V, MAT.wheel_radius)[0]
        inside = np.abs(L["x_rel"]) < A0
        rms = np.sqrt(np.mean((L["q"] - qc)[inside] ** 2)) / (MAT.friction_dynamic * P0)
        assert rms < 0.036 / math.sqrt(per_a)
        pc = hertz_pressure(L["x_rel"], P, A0, MAT)
        assert np.sqrt(np.mean((L["p"] - pc)[inside] ** 2)) / P0 < 0.045 / per_a  # 1.5e-3, 7.5e-4: order 1
    order = math.log2(errs[0] / errs[1])
    assert 0.6 < order < 1.2


@pytest.mark.slow
def test_smooth_rail_carter_convergence_study():
    errs = []
    for per_a in (50, 100, 200):
        _, w = _steady(per_a)
        errs.append(w.mean() / W_C - 1)
    orders = [math.log2(errs[i] / errs[i + 1]) for i in range(2)]
    assert all(0.8 < o < 1.1 for o in orders)
    assert abs(errs[-1]) < 1.5e-3


@pytest.mark.parametrize("lam_over_2a", [2.0, 5.0, 20.0])
def test_patch_centre_follows_the_slope_through_J0(lam_over_2a):
    # small cosine (R_w Delta beta^2 = 1e-3), 50 cells per a, dither K + 1 <= 25, the harmonic over the wheel
    # positions. The zone midpoint (edges extrapolated from p^2 linear over the 2nd and 3rd elements inside)
    # averaged over the dither phases against c = R_w r' J0(beta a): measured 1.004, 0.994, 1.000 (2, 5, 20;
    # 1.002, 1.000, 1.000 at 100 cells per a). Without the phase average a single position gives 0.77 at
    # any grid (tests nothing but the estimator's gain at one sub-cell offset: the reason for the dither).
    # The pressure centroid against the exact single-zone centroid R_w r' (J0 + J2) (the shift plus the
    # first moment of the shape, Chebyshev U_1): within 1e-4. The zone half-length against the curvature
    # filter: 1.011, 1.003, 0.997.
    mid, cen, ahm, _ = rw.normal_response(MAT, P, lam_over_2a)
    assert abs(mid - 1) < 0.01
    assert abs(cen - 1) < 0.002
    assert abs(ahm - 1) < 0.015  # the half-length filter 2 J1(beta a) / (beta a)


@pytest.mark.parametrize("lam_over_2a", [0.7, 1.0, 1.5])
def test_patch_centre_short_waves(lam_over_2a):
    # J0 < 0 at 0.7 and 1: the patch moves against the slope. The centroid identity holds to 2.3e-3 (50 cells
    # per a); the midpoint estimator is biased by the pressure ripple near the edges (0.967, 0.948, 1.068;
    # 0.965, 0.969, 0.999 at 100 cells per a), so only its sign and size are checked here
    mid, cen, _, _ = rw.normal_response(MAT, P, lam_over_2a)
    assert abs(cen - 1) < 0.005
    assert abs(mid - 1) < 0.08


def test_patch_centre_matches_rails_patch_contact_shift():
    # the same wheel positions through rail.normal.patch_contact (exact single zone, Chebyshev): its shift
    # against the brute force's dither-averaged zone midpoint, as harmonics
    lo = 3.0
    mid, _, _, r = rw.normal_response(MAT, P, lo)
    beta = math.pi / (lo * A0)
    delta = 1e-3 / (MAT.wheel_radius * beta**2)
    pc = N.patch_contact(np.full(r.x_wheel.size, P), r.x_wheel, rw.Cosine(delta, beta).slope, MAT, np.zeros(1))
    ks = np.flatnonzero(r.x_wheel - r.x_wheel[0] < 2 * math.pi / beta * max(1, math.ceil(4 * A0 / (2 * lo * A0))))
    ref = rw.fit_harmonic(pc.shift[ks], r.x_wheel[ks], beta)
    got = rw.fit_harmonic(r.centre[ks], r.x_wheel[ks], beta)
    assert abs(got / ref - 1) < 0.01


def test_centred_mode_keeps_the_patch_under_the_wheel():
    mid, _, ahm, _ = rw.normal_response(MAT, P, 5.0, mode="centred")
    assert abs(mid) < 0.01  # the tilt removed: no shift left (1 = the full shift)
    assert abs(ahm - 1) < 0.03  # the half-length still follows the curvature


def test_constant_curvature_gives_the_quasi_steady_sweep_exactly():
    # r = kappa x^2 / 2: the patch centre moves at dc/dx = R_w kappa / (1 - R_w kappa) (tangent point), a steady
    # state. Its work per rail point against the centred patch's is the power Q(gamma_eff) |gamma| V over the
    # sweep speed V (1 + c'), with Carter's Q at the effective creepage gamma / (1 + c') (the transport of the
    # rail through the patch): -1.82 R_w kappa, against -1 R_w kappa of the closed form (-w-bar dc/dx).
    # Measured at R_w kappa = +-1e-3, 2e-3 and 50 / 100 cells per a: 0.99 - 1.016 of this.
    eps = 1e-3
    kap = eps / MAT.wheel_radius
    per_a, K = 50, 24
    h = A0 / per_a
    adv = (K + 1) / K
    steps = int(30 * A0 / h / adv)
    W = {}
    for mode in ("exact", "centred"):
        r = rw.simulate(MAT, P, V, rw.Parabola(kap), h, steps, advance=adv, mode=mode, warmup=int(10 * A0 / h / adv))
        w = r.work[r.passed]
        W[mode] = w[: (w.size // (K + 1)) * (K + 1)].mean()
        if mode == "exact":
            n = r.x_wheel.size // 2
            assert np.polyfit(r.x_wheel[n:], r.centre[n:], 1)[0] == pytest.approx(eps / (1 - eps), rel=2e-3)
    cp = eps / (1 - eps)
    a = math.sqrt(2 * compliance(MAT) * P / (2 * MAT.half_width) / (1 / MAT.wheel_radius - kap))
    f = abs(MAT.creepage) / (math.pi * compliance(MAT) * MAT.friction_dynamic * P / (math.pi * a * MAT.half_width))
    fe = f / (1 + cp)
    pred = fe * (2 - fe) / (f * (2 - f)) / (1 + cp) - 1
    assert (W["exact"] / W["centred"] - 1) / pred == pytest.approx(1.0, abs=0.03)
    assert pred / eps == pytest.approx(-1.82, abs=0.01)


def test_centred_mode_reproduces_the_production_model():
    # the production model (rail.normal.patch_contact + rail.contact.solve_tangential, patch-fixed grid,
    # closure l = (a/2) e^{2/pi} with the solver's a) against the simulator with the patch held under the
    # wheel and the same closure on its zone half-length: the work harmonic in units of W-bar R_w beta^2.
    # Measured over lambda / 2a = 0.7-20 (production 161 nodes): within 0.003-0.032 at 50 cells per a and one
    # offset, within 0.0016-0.0036 at 100 cells per a and four offsets.
    lo = 5.0
    r = rw.measure(MAT, P, lo, per_a=25, mode="centred", closure="zone")
    H, _, _ = rw.production_centred(MAT, P, lo, nodes=81, grids=2)
    assert abs(r.H - H) < 0.04


def test_centre_move_effect_does_not_depend_on_the_closure():
    # the absolute harmonic does (the 2D kernel's rigid term: fixed L against l(a(t))), the difference of the
    # exact and the centred patch does not (measured 1e-4 at lambda / 2a = 0.7, 5, 20)
    # (measured at 50 cells per a: 1.5e-3, against 0.45 of the centred harmonic)
    lo = 5.0
    d = {}
    for cl in ("zone", "fixed"):
        e = rw.measure(MAT, P, lo, per_a=50, mode="exact", closure=cl)
        c = rw.measure(MAT, P, lo, per_a=50, mode="centred", closure=cl)
        d[cl] = (e.H - c.H, c.H)
    assert abs(d["zone"][0] - d["fixed"][0]) < 0.01
    assert abs(d["zone"][1] - d["fixed"][1]) > 0.2  # the closure itself matters for the absolute harmonic


@pytest.mark.slow
@pytest.mark.parametrize("lam_over_2a", [1.0, 5.0, 20.0])
def test_centre_move_effect_converges_in_grid_and_amplitude(lam_over_2a):
    # exact - centred at 50 and 100 cells per a, and at 100 with Delta halved: within 0.035 of the yardstick
    # W-bar R_w beta^2 (measured: up to 0.032, the grid-phase residue of the dither average)
    out = []
    for per_a, rk in ((50, 1e-3), (100, 1e-3), (100, 5e-4)):
        e = rw.measure(MAT, P, lam_over_2a, per_a=per_a, rwkb2=rk, mode="exact")
        c = rw.measure(MAT, P, lam_over_2a, per_a=per_a, rwkb2=rk, mode="centred")
        out.append(e.H - c.H)
    assert max(abs(out[i] - out[j]) for i in range(3) for j in range(i)) < 0.035


def _offset_mean(lo, per_a=50, offsets=2, **kw):
    """Work harmonic averaged over interleaved wheel offsets phi = j / (offsets K) (finer grid-phase average)."""
    K = rw.lattice(lo * 2 * A0, A0, per_a)[2]
    return sum(rw.measure(MAT, P, lo, per_a=per_a, phi=j / (offsets * K), **kw).H for j in range(offsets)) / offsets


@pytest.mark.parametrize("lam_over_2a", [1.0, pytest.param(3.0, marks=pytest.mark.slow),
                                         pytest.param(10.0, marks=pytest.mark.slow)])
def test_the_centre_move_acts_as_an_effective_creepage(lam_over_2a):
    # The patch moving at V (1 + dc/dx) over the rail with the rigid slip gamma V is, in time rescaled by the
    # sweep speed, the centred patch with the creepage gamma / (1 + dc/dx) (eq 26's transport term): the
    # sweep and the transport speed are one mechanism. The centred patch with that creepage (dc/dx from the
    # closed form R_w r'' J0(beta a)) against the exact rolling, exact - centred in units of W-bar R_w beta^2:
    # measured 0.001-0.018 apart over lambda / 2a = 0.7-20 (50 cells per a, two offsets), where the
    # difference itself is 0.07-1.8 (one offset leaves up to 0.04 of grid-phase residue).
    e = _offset_mean(lam_over_2a, mode="exact")
    c = _offset_mean(lam_over_2a, mode="centred")
    cc = _offset_mean(lam_over_2a, mode="centred", creepage_modulation=True)
    assert abs((e - c) - (cc - c)) < 0.025


@pytest.mark.slow
def test_the_closed_form_misses_the_creepage_and_the_transient():
    # lambda / 2a = 20: exact - centred = 1.82 J0 (the closed form -w-bar dc/dx gives J0: the frictional power
    # is not constant, Q follows the effective creepage, d ln Q / d ln gamma = 0.82); lambda / 2a = 0.7: the
    # closed form -0.32, the rolling +0.10 - 0.08i (the transient tangential response to the creepage
    # modulation), 50 cells per a
    out = {}
    for lo in (0.7, 20.0):
        e = rw.measure(MAT, P, lo, per_a=50, mode="exact")
        c = rw.measure(MAT, P, lo, per_a=50, mode="centred")
        out[lo] = (e.H - c.H) / j0(math.pi / lo)
    assert abs(out[20.0] - 1.82) < 0.04
    assert out[0.7].real < -0.2  # opposite sign to the closed form's J0 < 0 harmonic
