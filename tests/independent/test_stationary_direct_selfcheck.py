"""Fast self-checks of the independent reference model ``stationary_direct`` (no use of the ``rail`` package).

Every check compares against something computed by a different route (quadrature, a different solver, a
textbook closed form, a limit) or against an exact symmetry, so each one fails if the model is wrong.
"""

import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest
import scipy.integrate

try:
    from . import stationary_direct as sd
except ImportError:  # imported outside a package (e.g. --import-mode=importlib)
    _spec = importlib.util.spec_from_file_location(
        "stationary_direct", Path(__file__).with_name("stationary_direct.py"))
    sd = importlib.util.module_from_spec(_spec)
    _spec.loader.exec_module(sd)

TWO_PI = 2.0 * math.pi


@pytest.fixture
def p():
    return sd.table1_params()


def scaled_params(L, **extra):
    """Table 1 with sleeper spacing L and pad/ballast stiffness and sleeper mass scaled by L/0.6 (same K_s/L)."""
    s = L / 0.6
    t = sd.TABLE1
    return sd.table1_params(L=L, k_pad=t["k_pad"] * s, k_ballast=t["k_ballast"] * s,
                            m_sleeper=t["m_sleeper"] * s, **extra)


# ------------------------------------------------------------------------------------------------------------------
# 1. free-beam Green's function: residues vs direct numerical integration of (1/2pi) int H exp(-i beta x) d beta
# ------------------------------------------------------------------------------------------------------------------
def _H(beta, omega, params):
    EI, kGA, rhoA, rhoI, _, _ = sd._complex_properties(omega, params)
    N = EI * beta**2 + kGA - rhoI * omega**2
    D = kGA * beta**2 * (EI * beta**2 - rhoI * omega**2) - rhoA * omega**2 * N
    return N / D


def _green_by_quadrature(x, omega, params):
    """(1/2pi) int_R H exp(-i beta x) d beta = (1/pi) int_0^inf H cos(beta x) d beta (H even), real axis only."""
    scale = 1.0 / abs(sd.free_beam_green(0.0, omega, params))  # O(1) integrand for quad's absolute tolerances
    # break points around the (damped) real-axis poles so quad resolves the narrow peaks; the pole positions
    # only guide the subdivision, the integral itself is on the real axis
    betas, _ = sd._residue_terms(omega, params)
    bmax = 30.0 * float(np.max(np.abs(betas.real)))
    pts = sorted({abs(b.real) + k * abs(b.imag) for b in betas for k in (-30, -10, -3, -1, 0, 1, 3, 10, 30)})
    pts = [v for v in pts if 0.0 < v < bmax]

    def h(b):
        return scale * _H(b, omega, params)

    total = 0.0
    for part, unit in ((np.real, 1.0), (np.imag, 1j)):
        if x == 0.0:
            i1 = scipy.integrate.quad(lambda b: part(h(b)), 0.0, bmax, points=pts, limit=2000,
                                      epsabs=1e-13, epsrel=1e-12)[0]
            i2 = scipy.integrate.quad(lambda b: part(h(b)), bmax, np.inf, limit=2000, epsabs=1e-13, epsrel=1e-12)[0]
        else:
            i1 = scipy.integrate.quad(lambda b: part(h(b)) * np.cos(b * x), 0.0, bmax, points=pts, limit=2000,
                                      epsabs=1e-13, epsrel=1e-12)[0]
            i2 = scipy.integrate.quad(lambda b: part(h(b)), bmax, np.inf, weight="cos", wvar=abs(x), limit=2000,
                                      epsabs=1e-13)[0]
        total = total + unit * (i1 + i2)
    return total / math.pi / scale


@pytest.mark.parametrize("f", [100.0, 1000.0, 3000.0, -500.0])
@pytest.mark.parametrize("x", [0.0, 0.3, -0.7, 2.0])
def test_free_beam_green_matches_quadrature(p, f, x):
    om = TWO_PI * f
    closed = sd.free_beam_green(x, om, p)
    numeric = _green_by_quadrature(x, om, p)
    assert abs(closed - numeric) <= 1e-9 * abs(closed)  # observed ~1e-14


def test_free_beam_green_viscous_and_branch_choice():
    pv = sd.table1_params(damping="viscous", c_pad=5e4, c_ballast=8e4, tau_rail=2e-6)
    om = TWO_PI * 1500.0
    assert abs(sd.free_beam_green(0.45, om, pv) - _green_by_quadrature(0.45, om, pv)) \
        <= 1e-9 * abs(sd.free_beam_green(0.45, om, pv))
    betas, _ = sd._residue_terms(om, pv)
    assert np.all(betas.imag < 0)  # decaying / outgoing for x > 0
    x = np.linspace(-3, 3, 13)
    np.testing.assert_allclose(sd.free_beam_green(x, om, pv), sd.free_beam_green(-x, om, pv), rtol=1e-14)


# ------------------------------------------------------------------------------------------------------------------
# 2. discretely supported rail: convergence in J, solver, reciprocity, periodicity, symmetries, limits
# ------------------------------------------------------------------------------------------------------------------
def test_stationary_converges_in_J(p):
    """Truncation error decays geometrically in J (near the pinned-pinned frequency, the slowest case)."""
    om = TWO_PI * 1000.0
    xo, x0 = np.array([0.0, 0.3, 0.3]), np.array([0.0, 0.3, 0.0])
    ref = sd.stationary_receptance(xo, x0, om, p, n_supports=1024)
    errs = [np.max(np.abs(sd.stationary_receptance(xo, x0, om, p, n_supports=J) - ref) / np.abs(ref))
            for J in (16, 32, 64, 128, 256)]
    assert errs[0] > 1e-2  # truncation is visible for small J ...
    assert all(e2 < 0.5 * e1 for e1, e2 in zip(errs, errs[1:]))  # ... and decreases geometrically
    assert errs[-1] < 1e-4
    adaptive, info = sd.stationary_receptance(xo, x0, om, p, return_info=True)
    np.testing.assert_allclose(adaptive, ref, rtol=1e-9)
    assert all(c < 1e-7 for c in info["rel_change"])


def test_levinson_equals_dense_lu(p, monkeypatch):
    om = TWO_PI * 700.0
    xo = np.array([0.0, 0.1, 0.3, 1.9])
    lev = sd.stationary_receptance(xo, 0.2, om, p, n_supports=300)
    monkeypatch.setattr(sd, "_DENSE_MAX", 10**6)
    dense = sd.stationary_receptance(xo, 0.2, om, p, n_supports=300)
    np.testing.assert_allclose(lev, dense, rtol=1e-10)


@pytest.mark.parametrize("f", [300.0, 1000.0, 2500.0])
def test_reciprocity(p, f):
    om = TWO_PI * f
    x1 = np.array([0.13, 0.0, 0.3, -1.07])
    x2 = np.array([0.97, 0.41, 2.55, 0.52])
    a12 = sd.stationary_receptance(x1, x2, om, p)
    a21 = sd.stationary_receptance(x2, x1, om, p)
    np.testing.assert_allclose(a12, a21, rtol=1e-9)


@pytest.mark.parametrize("f", [300.0, 1000.0])
def test_periodicity_and_mirror_symmetry(p, f):
    om = TWO_PI * f
    L = p["L"]
    x = np.array([0.0, 0.1, 0.3, 0.77, -0.4])
    x0 = np.array([0.0, 0.25, 0.3, 0.1, 0.05])
    a = sd.stationary_receptance(x, x0, om, p)
    np.testing.assert_allclose(sd.stationary_receptance(x + L, x0 + L, om, p), a, rtol=1e-9)
    np.testing.assert_allclose(sd.stationary_receptance(x - 7 * L, x0 - 7 * L, om, p), a, rtol=1e-9)
    # mirror about a sleeper (different truncation window, so this also tests convergence)
    np.testing.assert_allclose(sd.stationary_receptance(-x, -x0, om, p), a, rtol=1e-7)


def test_negative_frequency_is_conjugate(p):
    x = np.array([0.0, 0.3, 1.2])
    om = TWO_PI * 800.0
    np.testing.assert_allclose(sd.stationary_receptance(x, 0.1, -om, p),
                               np.conj(sd.stationary_receptance(x, 0.1, om, p)), rtol=1e-9)


def test_soft_supports_give_free_beam(p):
    q = dict(p, k_pad=1e-2, k_ballast=1e-2, m_sleeper=0.0)
    om = TWO_PI * 600.0
    x = np.array([0.0, 0.2, 1.5])
    np.testing.assert_allclose(sd.stationary_receptance(x, 0.1, om, q), sd.free_beam_green(x - 0.1, om, q),
                               rtol=1e-6)


def test_discrete_close_to_continuous_at_low_frequency(p):
    """At 100 Hz (wavelength >> L) sleeper spacing hardly matters even for L = 0.6 m."""
    om = TWO_PI * 100.0
    c = sd.continuous_support_receptance(om, p)
    a = sd.stationary_receptance([0.0, 0.3], [0.0, 0.3], om, p)
    np.testing.assert_allclose(np.abs(a), abs(c), rtol=0.01)  # magnitudes: observed 0.6 %
    np.testing.assert_allclose(a, c, rtol=0.05)  # complex values: observed 2.5 %


# ------------------------------------------------------------------------------------------------------------------
# 3. continuous support: small-L limit of the discrete model; Euler-Bernoulli vs Timoshenko
# ------------------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("f", [100.0, 300.0, 1000.0])
def test_continuous_equals_discrete_for_small_L(f):
    """L = 0.05 m, K_s/L unchanged: |discrete - continuous| / |continuous| < 0.5 % (observed <= 0.21 %),
    both above a sleeper and at mid-span."""
    ps = scaled_params(0.05)
    om = TWO_PI * f
    c = sd.continuous_support_receptance(om, ps)
    a = sd.stationary_receptance([0.0, 0.025], [0.0, 0.025], om, ps)
    assert np.all(np.abs(a - c) < 5e-3 * abs(c))


def test_discreteness_error_is_second_order_in_L():
    om = TWO_PI * 300.0
    errs = []
    for L in (0.1, 0.05):
        ps = scaled_params(L)
        c = sd.continuous_support_receptance(om, ps)
        errs.append(abs(sd.stationary_receptance(0.0, 0.0, om, ps) - c) / abs(c))
    assert 3.0 < errs[0] / errs[1] < 5.0


@pytest.mark.parametrize("f", [0.0, 100.0, 1000.0, 3000.0, -700.0])
def test_euler_continuous_matches_textbook_formula(p, f):
    """EB beam on a (complex) Winkler foundation: alpha = 1 / (8 EI mu^3), mu^4 = (k - rhoA w^2) / (4 EI)."""
    om = TWO_PI * f
    EI = p["E"] * p["I"] * (1 + 1j * p["eta_rail"] * np.sign(om))
    k = sd.support_stiffness(om, p) / p["L"]
    mu = ((k - p["rho"] * p["A"] * om**2) / (4 * EI)) ** 0.25
    assert abs(sd.continuous_support_receptance(om, p, beam="euler") * 8 * EI * mu**3 - 1) < 1e-12


def test_euler_vs_timoshenko(p):
    lo, hi = TWO_PI * 100.0, TWO_PI * 3000.0
    e_lo, t_lo = (sd.continuous_support_receptance(lo, p, beam=b) for b in ("euler", "timoshenko"))
    e_hi, t_hi = (sd.continuous_support_receptance(hi, p, beam=b) for b in ("euler", "timoshenko"))
    # 100 Hz: agree to within the (static) shear flexibility, 7 % for kappa = 0.4; 3 kHz: differ by ~100 %
    assert abs(e_lo - t_lo) < 0.10 * abs(t_lo)
    assert abs(e_hi - t_hi) > 0.5 * abs(t_hi)
    # with shear made rigid the Timoshenko result tends to EB at 100 Hz (rotary inertia negligible there)
    t_rigid = sd.continuous_support_receptance(lo, dict(p, G=p["G"] * 1e7))
    assert abs(t_rigid - e_lo) < 2e-3 * abs(e_lo)


# ------------------------------------------------------------------------------------------------------------------
# 4. statics on discrete springs
# ------------------------------------------------------------------------------------------------------------------
def test_static_tends_to_winkler_closed_form():
    """EB beam (G = inf) on springs every L with k/L fixed -> F / (8 EI lam^3); relative error (sleeper and
    mid-span load) must decrease with L and be < 1e-5 at L = 0.05 m (observed 2.5e-7, ~L^4)."""
    errs = []
    for L in (0.6, 0.3, 0.1, 0.05):
        pl = scaled_params(L, G=np.inf)
        EI = pl["E"] * pl["I"]
        k = pl["k_pad"] * pl["k_ballast"] / (pl["k_pad"] + pl["k_ballast"]) / L
        lam = (k / (4 * EI)) ** 0.25
        w = sd.static_deflection_discrete([0.0, L / 2], [0.0, L / 2], pl)
        errs.append(np.max(np.abs(w * 8 * EI * lam**3 - 1)))
    assert errs[0] > 1e-3
    assert all(e2 < e1 for e1, e2 in zip(errs, errs[1:]))
    assert errs[-1] < 1e-5


def test_static_timoshenko_tends_to_continuous_timoshenko():
    """Timoshenko statics (shear included): discrete L = 0.05 vs continuous closed form at omega = 0, < 2e-4."""
    pl = scaled_params(0.05)
    c = sd.continuous_support_receptance(0.0, pl)
    assert abs(c.imag) == 0.0
    w = sd.static_deflection_discrete([0.0, 0.025], [0.0, 0.025], pl)
    assert np.max(np.abs(w / c.real - 1)) < 2e-4


def test_static_equilibrium_and_reciprocity(p):
    xs, F = sd.static_support_forces(0.13, p)
    assert abs(F.sum() - 1.0) < 1e-10  # vertical equilibrium
    assert abs((F * xs).sum() - 0.13) < 1e-10  # moment equilibrium
    a = sd.static_deflection_discrete([0.05, 1.31], [1.31, 0.05], p)
    assert abs(a[0] - a[1]) < 1e-10 * abs(a[0])
    # mid-span load deflects more than a load over a sleeper
    w_s, w_m = sd.static_deflection_discrete([0.0, 0.3], [0.0, 0.3], p)
    assert w_m > w_s > 0


def test_viscous_low_frequency_tends_to_static():
    """Two unrelated methods: harmonic direct superposition (viscous damping, 0.01 Hz) vs FE statics."""
    pv = sd.table1_params(damping="viscous", c_pad=5e4, c_ballast=8e4, tau_rail=1e-5)
    x = np.array([0.0, 0.17, 0.3, 0.9, 2.5])
    for x0 in (0.0, 0.3):
        ws = sd.static_deflection_discrete(x, x0, pv)
        a = sd.stationary_receptance(x, x0, TWO_PI * 0.01, pv)
        assert np.max(np.abs(a - ws)) < 2e-4 * np.max(np.abs(ws))  # O(omega c / k) = 1e-4 damping term


# ------------------------------------------------------------------------------------------------------------------
# 5. pinned-pinned frequency and the sleeper / mid-span contrast
# ------------------------------------------------------------------------------------------------------------------
def test_pinned_pinned_rayleigh_limit(p):
    q = dict(p, G=1e25)  # shear rigid -> Rayleigh beam: w^2 = EI b^4 / (rhoA + rhoI b^2)
    b = math.pi / p["L"]
    f_r = math.sqrt(p["E"] * p["I"] * b**4 / (p["rho"] * p["A"] + p["rho"] * p["I"] * b**2)) / TWO_PI
    assert abs(sd.pinned_pinned_frequency(q) / f_r - 1) < 1e-9
    assert sd.pinned_pinned_frequency(p) < f_r  # shear lowers it


def test_pinned_pinned_peak_and_max_difference(p):
    """The mid-span point receptance peaks at the pinned-pinned frequency (sleepers at nodes of sin(pi x/L)),
    and the sleeper / mid-span contrast is largest just above it."""
    fpp = sd.pinned_pinned_frequency(p)
    assert 1000.0 < fpp < 1150.0
    f = np.arange(1000.0, 1160.0, 2.0)
    a_s = sd.stationary_receptance(0.0, 0.0, TWO_PI * f, p)
    a_m = sd.stationary_receptance(0.3, 0.3, TWO_PI * f, p)
    assert abs(f[np.argmax(np.abs(a_m))] - fpp) <= 3.0
    d = 20 * np.log10(np.abs(a_m) / np.abs(a_s))
    assert d.max() > 20.0
    assert fpp < f[np.argmax(d)] < 1.1 * fpp
