"""Periodically supported Timoshenko rail: closed forms, limits and the moving-load method."""

import numpy as np
import pytest
from scipy import special

from rail import moving
from rail.cell import TrackCell
from rail import track as T


def table1(damping="hysteretic", L=0.6, pad=3.5e8, scale=1.0, G=0.81e11):
    """Table 1 track; ``scale`` multiplies the support stiffnesses and sleeper mass (for small L)."""
    return T.Track(
        T.Rail(2.1e11, G, 7850.0, 7.69e-3, 30.55e-6, 0.4, loss_factor=0.01, damping_time=1.6e-6),
        T.Pad(pad * scale, 0.25, 2.8e4 * scale),
        T.Sleeper(162.0 * scale, L),
        T.Ballast(50e6 * scale, 1.0, 8.0e4 * scale),
        damping,
    )


@pytest.fixture(scope="module")
def track():
    return table1()


def brute_periodic_sum(beta, omega, track, x=0.0, M=4000):
    """sum_m H(beta + m beta0) e^{i (beta + m beta0) x}: explicit terms |m| <= M, and for x = 0 the
    tail of the quasi-static H_0 by polygamma (the dynamic part of the tail is < 1e-12 relative)."""
    b0 = track.beta0
    m = np.arange(-M, M + 1)
    out = np.sum(T.free_receptance(beta + m * b0, omega, track) * np.exp(1j * (beta + m * b0) * x))
    if x == 0.0:
        EI, kGA = T.rail_stiffnesses(track, omega)
        a = beta / b0
        out += (special.polygamma(1, M + 1 + a) + special.polygamma(1, M + 1 - a)) / (b0**2 * kGA)
        out += (special.polygamma(3, M + 1 + a) + special.polygamma(3, M + 1 - a)) / (6 * b0**4 * EI)
    return out


@pytest.mark.parametrize("f", [30.0, 700.0, 2500.0])
def test_periodic_sum_closed_form_matches_explicit_sum(track, f):
    om = 2 * np.pi * f
    kap = np.array([-3.0, 0.7, 2.5, 5.0])
    closed = T.periodic_sum(kap, om, track)
    brute = np.array([brute_periodic_sum(k, om, track) for k in kap])
    np.testing.assert_allclose(closed, brute, rtol=1e-9)


@pytest.mark.parametrize("x", [0.13, 0.5999, -0.25, 1.45])
def test_phased_periodic_sum_matches_explicit_sum(track, x):
    # away from x = 0 mod L the explicit sum converges fast enough without a tail
    om = 2 * np.pi * 700.0
    kap = np.array([-3.0, 0.7, 2.5])
    closed = T.phased_periodic_sum(kap, x, om, track)
    brute = np.array([brute_periodic_sum(k, om, track, x=x, M=20000) for k in kap])
    np.testing.assert_allclose(closed, brute, rtol=2e-5)


def test_free_green_matches_direct_wavenumber_integral(track):
    om = 2 * np.pi * 700.0
    A = 3000.0
    beta = np.linspace(-A, A, 3_000_001)
    H = T.free_receptance(beta, om, track)
    c, p = T.free_receptance_poles(om, track)
    for x in (0.0, 0.3, 1.2):
        direct = np.trapezoid(H * np.exp(-1j * beta * x), beta) / (2 * np.pi)
        # the truncated tails |beta| > A add about -2 / (kGA A) / 2pi ~ 4e-13 (x = 0), well inside:
        assert abs(T.free_green(x, om, track) - direct) < 2e-3 * abs(direct) + 1e-12


def euler_bernoulli_winkler_receptance(omega, EI, rhoA, kf):
    """Point receptance of an EB beam on a Winkler foundation kf (N/m^2, complex):
    alpha = (i - 1) / (4 EI q^3), q^4 = (rho A omega^2 - kf) / EI, q in the first quadrant."""
    q4 = (rhoA * omega**2 - kf) / EI
    q = q4 ** 0.25
    for r in q * np.array([1, 1j, -1, -1j]):
        if r.real > 0 and r.imag >= 0:
            q = r
    return (1j - 1) / (4 * EI * q**3)


@pytest.mark.parametrize("f", [50.0, 150.0])
def test_continuous_support_tends_to_euler_bernoulli_winkler_for_stiff_shear(f):
    # shear rigidity -> infinity leaves EB plus rotary inertia, whose relative size I q^2 / A is
    # 0.3 % at 50 Hz and 1 % at 150 Hz in the dispersion relation (2 % at 300 Hz, where the
    # receptances differ by 0.25 %); the tolerance 2e-3 holds where it is below that.
    tr = table1(G=0.81e17)
    om = 2 * np.pi * f
    EI, _ = T.rail_stiffnesses(tr, om)
    kf = T.support_stiffness(tr, om) / tr.L
    eb = euler_bernoulli_winkler_receptance(om, EI, 7850 * 7.69e-3, kf)
    assert T.continuous_support_receptance(om, tr) == pytest.approx(eb, rel=2e-3)


@pytest.mark.parametrize("f", [100.0, 500.0, 1500.0])
def test_discrete_supports_tend_to_continuous_support_as_spacing_shrinks(f):
    # the same stiffness and mass per metre on supports 5 cm apart: the bay-averaged receptance
    # approaches the continuous foundation; the residual falls with L (checked at two spacings)
    om = 2 * np.pi * f
    errs = []
    for L in (0.1, 0.05):
        tr = table1(L=L, scale=L / 0.6)
        x = np.linspace(0, L, 8, endpoint=False)
        mean_alpha = np.mean(T.stationary_receptance(x, x, om, tr))
        cont = T.continuous_support_receptance(om, tr)
        errs.append(abs(mean_alpha / cont - 1))
    assert errs[1] < 0.01
    assert errs[1] < errs[0]


def test_stationary_receptance_is_reciprocal_and_periodic(track):
    om = 2 * np.pi * 800.0
    a12 = T.stationary_receptance(0.1, 0.45, om, track)
    a21 = T.stationary_receptance(0.45, 0.1, om, track)
    assert a12 == pytest.approx(a21, rel=1e-7)
    shifted = T.stationary_receptance(0.1 + track.L, 0.45 + track.L, om, track)
    assert shifted == pytest.approx(a12, rel=1e-7)


def test_stationary_receptance_quadrature_converges(track):
    om = 2 * np.pi * 1000.0
    x = np.array([0.0, 0.3])
    coarse, err = T.stationary_receptance(x, x, om, track, rtol=1e-5, return_error=True)
    fine = T.stationary_receptance(x, x, om, track, rtol=1e-11)
    assert np.all(np.abs(coarse - fine) <= 10 * err + 1e-16)
    assert np.all(np.abs(coarse - fine) / np.abs(fine) < 1e-5)


@pytest.mark.slow
def test_pinned_pinned_closed_form_is_recovered_from_the_receptance(track):
    # Timoshenko simply supported span L (closed form) against the mid-span receptance peak
    fc = T.characteristic_frequencies(track)
    assert fc["pinned_pinned"] == pytest.approx(T.pinned_pinned_frequency(track), rel=0.02)
    assert 50 < fc["track_on_ballast"] < fc["out_of_phase"] < fc["pinned_pinned"]


@pytest.mark.parametrize("f", [300.0, 1000.0])
@pytest.mark.slow
def test_moving_load_tends_to_stationary_fourier_coefficients_as_speed_vanishes(track, f):
    # a_n(Omega) -> (1/L) int_0^L alpha(x0, x0; Omega) e^{-i n beta0 x0} dx0 as V -> 0 (Omega != 0,
    # valid for hysteretic damping too); the difference falls in proportion to V.
    Om = 2 * np.pi * f
    x0 = np.linspace(0, track.L, 64, endpoint=False)
    alpha = T.stationary_receptance(x0, x0, Om, track)
    n = np.arange(-4, 5)
    four = np.array([np.mean(alpha * np.exp(-1j * k * track.beta0 * x0)) for k in n])
    errs = []
    for V in (2.0, 0.5):
        _, a, _ = moving.moving_coefficients(track, V, Om, 4)
        errs.append(np.max(np.abs(a - four)) / abs(four[4]))
    assert errs[1] < 1e-3
    assert errs[1] < 0.5 * errs[0]


def test_receptance_table_columns_equal_single_frequency_coefficients(track):
    V, K = 40.0, 6
    tab = moving.receptance_table(track, V, K, offsets=(0.0, 3.3))
    Om0 = track.beta0 * V
    for k in (0, 2, -3):
        for i, d in enumerate((0.0, 3.3)):
            _, a, _ = moving.moving_coefficients(track, V, k * Om0, 3, offset=d)
            table = np.array([tab.a(n, k, i) if abs(k + n) <= K else np.nan for n in range(-3, 4)])
            ok = ~np.isnan(table)
            np.testing.assert_allclose(table[ok], a[ok], rtol=1e-6, atol=1e-6 * abs(tab.a(0, k, i)))


@pytest.mark.slow
def test_receptance_table_converges_in_quadrature_tolerance(track):
    coarse = moving.receptance_table(track, 40.0, 8, rtol=1e-4)
    fine = moving.receptance_table(track, 40.0, 8, rtol=1e-8)
    scale = np.abs(fine.A).max()
    assert np.abs(coarse.A - fine.A).max() / scale < 1e-4
    assert np.abs(coarse.A - fine.A).max() <= 10 * coarse.error.max() + 1e-6 * scale


def test_moving_static_load_varies_with_the_bay_and_is_symmetric(track):
    # Constant load (k = 0): displacement under the load is real-periodic over the bay, largest
    # at mid-span for this track, and symmetric about mid-span: a_{-n} = conj(a_n) only holds
    # for V -> 0; here check the variation's sign and size against the stationary static limit.
    tab = moving.receptance_table(table1("viscous"), 2.0, 8)
    t = np.linspace(0, 1, 41)
    w = np.real(sum(tab.a(n, 0) * np.exp(2j * np.pi * n * t) for n in range(-8, 9)))
    assert w[20] > w[0]  # mid-span softer than above a sleeper
    assert 0.005 < (w.max() - w.min()) / w.mean() < 0.1


def test_bad_arguments_are_rejected(track):
    with pytest.raises(ValueError, match=r"speed = 0\.0 m/s is not allowed: it must be a finite number > 0"):
        moving.receptance_table(track, 0.0, 4)
    with pytest.raises(ValueError, match=r"track\.pad\.stiffness = -1\.0 is not allowed: it must be > 0"):
        T.Pad(-1.0)
    with pytest.raises(ValueError, match=r"track\.damping = 'coulomb' is not allowed"):
        T.Track(track.rail, track.pad, track.sleeper, track.ballast, "coulomb")


@pytest.mark.slow
def test_transfer_receptance_converges_in_the_wavenumber_window(track):
    # d != 0: the oscillating integrand is windowed from the cut to twice the cut. At a tight
    # quadrature tolerance (so the window is what is measured) doubling the default cut changes
    # the transfer receptances by < 1e-7 (measured 2e-10 at 3.3 m, 9e-9 at 10 m); halving it
    # changes them by ~1e-7, so the test can fail if the window were too narrow.
    K = 8
    cut = (K + 12) * track.beta0
    base = moving.receptance_table(track, 40.0, K, offsets=(3.3, 10.0), rtol=1e-7)
    wide = moving.receptance_table(track, 40.0, K, offsets=(3.3, 10.0), rtol=1e-7, transfer_cut=2 * cut)
    narrow = moving.receptance_table(track, 40.0, K, offsets=(3.3, 10.0), rtol=1e-7, transfer_cut=0.5 * cut)
    for i in range(2):
        scale = np.abs(wide.A[i]).max()
        assert np.abs(base.A[i] - wide.A[i]).max() < 1e-7 * scale
        assert np.abs(narrow.A[i] - wide.A[i]).max() > np.abs(base.A[i] - wide.A[i]).max()


@pytest.mark.parametrize("V", [pytest.param(20.0, marks=pytest.mark.slow), 40.0])
def test_far_offset_table_matches_direct_oscillatory_quadrature_within_its_stated_error(track, V):
    # The transfer receptances of offsets up to 13.3 m (the four-wheel vehicle) integrate the
    # smooth factors against exp(-i beta d) with Filon weights on the d = 0 rule. Reference: the
    # oscillating integrands resolved node by node by the adaptive Gauss rule to 1e-7 of each
    # column's scale (tests/reference/moving_direct.py). The diagonal and two columns of every
    # offset must lie within the table's stated error, which is set on the scale of the column
    # (the diagonal at d = 0).
    from tests.reference.moving_direct import transfer_entries

    K, offsets, columns = 6, (0.0, 3.3, -6.7, 13.3), [0, 4]
    tab = moving.receptance_table(track, V, K, offsets)
    column = np.abs(np.diag(tab.A[0]))
    for i, d in enumerate(offsets[1:], start=1):
        diag, cols = transfer_entries(track, V, K, d, columns)
        got = np.concatenate([np.diag(tab.A[i]), tab.A[i][:, np.array(columns) + K].ravel()])
        ref = np.concatenate([diag, cols.ravel()])
        bound = np.concatenate([np.diag(tab.error[i]), tab.error[i][:, np.array(columns) + K].ravel()])
        scale = np.concatenate([column, np.tile(column[np.array(columns) + K], 2 * K + 1)])
        err = np.abs(got - ref)
        assert np.all(err <= bound), (d, np.max(err / bound))
        assert np.max(err / scale) < 2e-5


@pytest.mark.slow
def test_filon_weights_remove_the_aliasing_of_far_offsets_on_the_d0_rule(track):
    # Mechanism check: on the nodes of the d = 0 rule, Gauss weights times exp(-i beta d) alias the
    # oscillation of a 13.3 m offset (measured: 0.16 of the column's scale at K = 24); the Filon
    # weights on the same nodes are within the stated error (measured 3e-6).
    from tests.reference.moving_direct import transfer_entries

    K, V, d = 24, 40.0, 13.3
    js = np.arange(-K, K + 1)
    cut = (K + 12) * track.beta0
    diag, _ = transfer_entries(track, V, K, d, [], rtol=1e-6)
    column = np.abs(np.diag(moving.receptance_table(track, V, K).A[0]))
    errs = {}
    for filon in (False, True):
        A, _, _ = moving._integrate(TrackCell.uniform(track), V, 0.0, js, [d], 0, 1e-4, cut, filon=filon)
        errs[filon] = np.max(np.abs(np.diag(A[0]) - diag) / column)
    assert errs[False] > 1e-2
    assert errs[True] < 2e-5


@pytest.mark.parametrize("damping", ["hysteretic", "viscous"])
@pytest.mark.parametrize("fraction", [0.0, 0.3])
def test_compiled_uniform_columns_are_as_accurate_as_numpys(track, damping, fraction):
    """The uniform track's node tables from the compiled loop (rail.moving._uniform_columns) against
    numpy's formulas (``compiled=False``) and both against the same formulas in extended precision
    (numpy's longdouble, from the same double inputs): h_j, the reactions and the diagonal integrand
    h - h Y / P (a difference: its error on the scale of h) are no less accurate compiled than
    numpy's own (the two differ at rounding: the formula's own conditioning, up to a few 1e-14 of h
    near its free waves). The static point's nodes and row are numpy's code in both. The adaptive
    rule's proxy is the compiled columns' numbers exactly."""
    tr = track if damping == "hysteretic" else table1("viscous")
    cell = TrackCell.uniform(tr)
    V, js = 40.0, np.arange(-64, 65)
    Omega = fraction * tr.beta0 * V
    static = 0 if fraction == 0 else None
    beta = np.concatenate([np.random.default_rng(3).uniform(-400, 400, 700), np.linspace(-0.4, 0.4, 8) * tr.beta0])
    num = moving._node_tables(beta, Omega, V, js, cell, static, compiled=False)
    com = moving._node_tables(beta, Omega, V, js, cell, static, compiled=True)
    near = com[5]
    assert np.array_equal(near, num[5]) and near.any() == (fraction == 0)
    far = ~near
    omega = Omega + beta * V
    x = moving._free_scalars(beta, omega, js, cell) + (
        moving._support_coef(beta, omega, moving.point_stiffness(cell, omega), far, cell), cell.period)
    # extended precision from the same double inputs
    ld = np.clongdouble
    b = x[0].astype(np.longdouble)[:, None] - js.astype(np.longdouble)[None, :] * np.longdouble(x[2])
    EI, kGA, ine, ra, c = (x[3].astype(ld)[:, None], x[4].astype(ld)[:, None], x[5].astype(np.longdouble)[:, None],
                           x[6].astype(np.longdouble)[:, None], x[7].astype(ld)[:, None])
    b2 = b * b
    nu = EI * b2 + kGA - ine
    G = nu / (kGA * b2 * (EI * b2 - ine) - ra * nu)
    Yx = c * G
    D = G - G * Yx / np.longdouble(x[8])
    eps = np.finfo(float).eps

    def err(a, ref, scale):
        return float(np.max(np.abs(a[far] - ref[far]) / np.maximum(np.abs(scale[far]), 1e-300)))

    for a_c, a_n, ref, scale in [(com[0], num[0], G, G), (com[3][:, 0], num[3][:, 0], Yx, Yx), (com[1], num[1], D, G)]:
        e_c, e_n = err(a_c, ref, scale), err(a_n, ref, scale)
        assert e_c <= 2 * e_n + 8 * eps, (e_c, e_n)
    if fraction == 0:  # the static point's nodes: numpy's code on inputs equal to rounding
        assert np.allclose(com[4][near], num[4][near], rtol=1e-12, atol=0)
        assert np.allclose(com[1][near], num[1][near], rtol=1e-12, atol=0)
    # the proxy: diag and the central column's reactions, times the Jacobian, away from the static point
    bf, of = beta[far], omega[far]
    xf = moving._free_scalars(bf, of, js, cell) + (
        moving._support_coef(bf, of, moving.point_stiffness(cell, of), np.ones(far.sum(), dtype=bool), cell), cell.period)
    jac = np.linspace(0.5, 2.0, far.sum())
    proxy = moving._uniform_proxy(*xf, jac, 64)
    assert np.array_equal(proxy, np.concatenate([com[1][far], com[3][far][:, 0, 64][:, None]], axis=1) * jac[:, None])
