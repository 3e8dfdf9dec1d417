"""Normal contact with the roughness inside the patch (rail.contact.normal, docs/contact.md): the brute-force
influence-coefficient solver against Hertz and Westergaard, the contact filters against it, and the
production single-zone solution against it."""

import functools

import numpy as np
import pytest
from scipy.special import j0

from rail import contact as C
from rail.contact import normal as N

R, P0 = 0.46, 1.0e5


def material():
    return C.ContactMaterial(2.1e11, 0.3, 0.008, R, 0.3, 0.3, -0.001)


M = material()
A0 = float(C.hertz_half_length(P0, R, M))
PW = P0 / (2 * M.half_width)  # load per unit width, N/m
ESTAR = N.composite_modulus(M)


def test_composite_modulus_gives_the_tangential_compliance():
    assert 2 / (np.pi * ESTAR) == pytest.approx(C.compliance(M), rel=1e-14)


def _hertz_error(cells_per_a):
    # grid with the patch edge half-way between element centres (a / h = cells_per_a + 1/2), so that
    # the edge's position against the grid is the same at every refinement
    h = A0 / (cells_per_a + 0.5)
    n = 2 * int(1.3 * A0 / h) + 1
    x = (np.arange(n) - n // 2) * h
    s = N.solve_normal(x, x**2 / (2 * R), PW, M)
    pH = C.hertz_pressure(x, P0, A0, M)
    return np.sqrt(np.sum((s.p - pH) ** 2) * h / (2 * A0)) / pH.max(), s.zones


def test_smooth_rail_pressure_converges_to_hertz():
    # rms error of the pressure over the patch against the Hertz ellipse (eq 22), relative to p0
    errs = []
    for cells in (20, 40, 80, 160):
        e, zones = _hertz_error(cells)
        assert zones == 1
        errs.append(e)
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    # measured: 4.4e-3, 2.2e-3, 1.1e-3, 5.6e-4 of p0 at 20-160 elements per half-length (observed
    # order 1.0: piecewise-constant pressure against the square-root edge)
    assert errs[-1] < 7e-4
    assert np.all(orders > 0.9), orders


@pytest.mark.parametrize("pbar_over_pstar", [1.5, 4.0])
def test_periodic_sinusoid_in_full_contact_is_westergaard(pbar_over_pstar):
    # Johnson, Contact Mechanics, sec. 13.2: z = Delta cos(2 pi x / lambda) pressed fully flat carries
    # p = pbar + p* cos(2 pi x / lambda), p* = pi E* Delta / lambda
    lam, D, n = 0.01, 1e-6, 128
    x = (np.arange(n) + 0.5) * lam / n - lam / 2
    pstar = np.pi * ESTAR * D / lam
    s = N.solve_normal(x, -D * np.cos(2 * np.pi * x / lam), pbar_over_pstar * pstar * lam, M, period=lam)
    assert s.contact.all()
    exact = pbar_over_pstar * pstar + pstar * np.cos(2 * np.pi * x / lam)
    # piecewise-constant elements collocated at their centres: second order, 2.0e-4 p* at 128 per period
    assert np.abs(s.p - exact).max() < 1e-3 * pstar


def test_periodic_sinusoid_in_partial_contact_has_one_zone_per_crest():
    # Westergaard's partial contact (Johnson eq 13.19): contact half-width c with sin^2(pi c / lambda) =
    # pbar / p*; three periods in the domain give three separate zones
    lam, D, n = 0.01, 1e-6, 3 * 400
    period = 3 * lam
    x = (np.arange(n) + 0.5) * period / n - period / 2
    pstar = np.pi * ESTAR * D / lam
    ratio = 0.3
    s = N.solve_normal(x, -D * np.cos(2 * np.pi * x / lam), ratio * pstar * period, M, period=period)
    assert s.zones == 3
    c_exact = lam / np.pi * np.arcsin(np.sqrt(ratio))
    c_grid = s.contact.sum() * (period / n) / 3 / 2
    assert c_grid == pytest.approx(c_exact, abs=period / n)


def test_cylinder_on_a_short_sinusoid_carries_westergaard_ripple_inside_the_patch():
    # lambda << a: in the patch interior the pressure is Hertz plus Westergaard's ripple p* cos(beta x)
    lam, D = A0 / 8, 0.3e-6
    beta = 2 * np.pi / lam
    x = np.linspace(-1.3 * A0, 1.3 * A0, 1601)
    s0 = N.solve_normal(x, x**2 / (2 * R), PW, M)
    s1 = N.solve_normal(x, x**2 / (2 * R) - D * np.cos(beta * x), PW, M)
    pstar = np.pi * ESTAR * D / lam
    inner = np.abs(x) < 0.5 * A0
    ripple = (s1.p - s0.p)[inner]
    fit = np.linalg.lstsq(np.c_[np.cos(beta * x[inner]), np.sin(beta * x[inner]), np.ones(inner.sum())], ripple, rcond=None)[0]
    assert fit[0] == pytest.approx(pstar, rel=0.01)  # measured 0.2 % (grid: 23 elements per wavelength)
    assert abs(fit[1]) < 0.01 * pstar


@functools.cache
def _brute_smooth(n):
    """The smooth-rail solution on the fine grid of _brute_filter (the same for every wavelength: computed once)."""
    x = np.linspace(-1.6 * A0, 1.6 * A0, n)
    return x, N.solve_normal(x, x**2 / (2 * R), PW, M)


@functools.cache
def _brute_filter(lam_over_2a, n=1201, D=1e-8):
    beta = np.pi / (lam_over_2a * A0)
    x, s0 = _brute_smooth(n)
    s1 = N.solve_normal(x, x**2 / (2 * R) - D * np.cos(beta * x), PW, M)
    return -(s1.approach - s0.approach) / D, beta  # the roughness the normal force sees, per unit roughness


@pytest.mark.parametrize("lam_over_2a", [0.5, 0.75, 1.0, 2.0, 3.0, 5.0, 10.0, 20.0])
def test_approach_filter_against_brute_force(lam_over_2a):
    # change of the approach at fixed load per unit roughness amplitude (cosine centred on the patch),
    # the full nonlinear contact on a fine grid at small amplitude, against J0(beta a)
    H, beta = _brute_filter(lam_over_2a)
    # measured within 1.2e-3 (grid of 375 elements across the patch)
    assert H == pytest.approx(float(N.approach_filter(beta, A0)), abs=3e-3)


def test_approach_filter_tends_to_one_for_long_wavelengths_and_changes_sign_below_the_patch():
    assert N.approach_filter(2 * np.pi / (200 * A0), A0) == pytest.approx(1.0, abs=3e-4)
    H, _ = _brute_filter(1.0)  # lambda = 2a: beta a = pi, J0 = -0.304: the force sees an inverted roughness
    assert H < -0.25


def test_patch_contact_on_a_smooth_rail_is_hertz():
    xi = np.linspace(-A0, A0, 41)
    pc = N.patch_contact(np.array([P0, 0.8 * P0]), np.zeros(2), lambda x: np.zeros_like(x), M, xi)
    assert pc.a == pytest.approx(C.hertz_half_length(np.array([P0, 0.8 * P0]), R, M), rel=1e-12)
    assert np.abs(pc.shape[0] - 1).max() < 1e-12
    assert np.all(pc.min_shape > 1 - 1e-12) and np.all(np.abs(pc.shift) < 1e-15 * A0)


@pytest.mark.parametrize("lam_over_2a", [0.5, 1.0, 2.0, 5.0])
def test_patch_contact_pressure_against_brute_force(lam_over_2a):
    # cosine roughness centred on the wheel, large enough to change the pressure by about 10 %:
    # the single-zone solution's half-length and pressure perturbation against the fine-grid solver
    beta = np.pi / (lam_over_2a * A0)
    D = 0.1 * 2 * ESTAR ** -1 * 7e8 / (np.pi * beta)  # p* = 10 % of 700 MPa
    x = np.linspace(-1.4 * A0, 1.4 * A0, 1401)
    s = N.solve_normal(x, x**2 / (2 * R) - D * np.cos(beta * x), PW, M)
    pc = N.patch_contact(np.array([P0]), np.array([0.0]), lambda y: -D * beta * np.sin(beta * y), M, x)
    a = pc.a[0]
    p = P0 / (np.pi * a * M.half_width) * np.sqrt(np.clip(1 - (x / a) ** 2, 0, None)) * pc.shape[0]
    edge = x[s.contact]
    h = x[1] - x[0]
    assert a == pytest.approx(0.5 * (edge[-1] - edge[0] + h), abs=h)
    pH = C.hertz_pressure(x, P0, A0, M)
    dev = np.sqrt(np.mean((s.p - pH) ** 2))  # the roughness's part of the pressure
    # measured 0.5-1.6 % of it (the brute force's grid error at the edges)
    assert np.sqrt(np.mean((p - s.p) ** 2)) < 0.03 * dev


def test_patch_contact_half_length_follows_the_curvature_filter():
    # small cosine: 1/R_eq = 1/R_w + kappa 2 J1(beta a)/(beta a), a ~ R^(1/2); report eq 24 is beta a -> 0
    for lam_over_2a in (0.5, 1.0, 3.0, 20.0):
        beta = np.pi / (lam_over_2a * A0)
        D = 1e-9
        pc = N.patch_contact(np.array([P0]), np.array([0.0]), lambda y: -D * beta * np.sin(beta * y), M, np.zeros(1))
        expected = -0.5 * R * D * beta**2 * N.half_length_filter(beta, A0)
        assert pc.a[0] / A0 - 1 == pytest.approx(expected, rel=1e-3, abs=1e-12)


@pytest.mark.slow
def test_patch_contact_shift_against_brute_force():
    # a sine under the patch moves the single-zone contact forward by about R_w r' J0: the diagnostic
    # against the centre of the fine-grid contact zone
    lam = 6 * A0
    beta = 2 * np.pi / lam
    D = 2e-6
    x = np.linspace(-1.4 * A0, 1.4 * A0, 2801)
    s = N.solve_normal(x, x**2 / (2 * R) - D * np.sin(beta * x), PW, M)
    pc = N.patch_contact(np.array([P0]), np.array([0.0]), lambda y: D * beta * np.cos(beta * y), M, np.zeros(1))
    edge = x[s.contact]
    centre = 0.5 * (edge[0] + edge[-1])
    assert pc.shift[0] == pytest.approx(centre, abs=x[1] - x[0])
    assert pc.shift[0] == pytest.approx(R * D * beta * j0(beta * A0), rel=0.05)


def test_patch_contact_reports_contact_lost_inside_the_patch():
    # a deep short trough under the patch: the single-zone pressure turns negative there
    lam = A0 / 2
    beta = 2 * np.pi / lam
    pstar_needed = 1.2 * P0 / (np.pi * A0 * M.half_width)
    D = pstar_needed * lam / (np.pi * ESTAR)
    pc = N.patch_contact(np.array([P0]), np.array([0.0]), lambda y: -D * beta * np.sin(beta * y), M, np.zeros(1))
    assert pc.min_shape[0] < 0
    x = np.linspace(-1.4 * A0, 1.4 * A0, 1401)
    assert N.solve_normal(x, x**2 / (2 * R) - D * np.cos(beta * x), PW, M).zones > 1


def test_u_series_against_the_derivative_of_a_chebyshev_series():
    # sum_{m>=1} c_m U_{m-1}(x) = d/dx sum_{m>=1} (c_m / m) T_m(x), as numpy.polynomial.chebyshev evaluates it
    rng = np.random.default_rng(3)
    n, rows, q = 32, 50, 65
    c = rng.standard_normal((rows, n)) / (1 + np.arange(n)) ** 2
    sigma = np.clip(np.linspace(-1.1, 1.1, q)[None, :] * (1 + 0.2 * rng.random((rows, 1))), -1.0, 1.0)
    got = N._u_series(c, sigma)
    d = np.zeros((rows, n))
    d[:, 1:] = c[:, 1:] / np.arange(1, n)
    cheb = np.polynomial.chebyshev
    want = np.array([cheb.chebval(sigma[i], cheb.chebder(d[i])) for i in range(rows)])
    scale = np.sum(np.abs(c) * np.arange(n) ** 2, axis=1, keepdims=True)  # max abs(U_{m-1}) = m, at +-1
    assert np.max(np.abs(got - want) / scale) < 1e-14
    # the compiled recurrence gives numpy's numbers: the same operations in the same order on whole arrays
    b1, b2 = np.zeros((rows, q)), np.zeros((rows, q))
    for m in range(n - 1, 0, -1):
        b1, b2 = c[:, m:m + 1] + 2 * sigma * b1 - b2, b1
    assert np.array_equal(got, b1)
    # leading axes broadcast: row m of the identity gives U_{m-1}
    x = np.linspace(-1, 1, 9)
    U = N._u_series(np.eye(5), x)
    assert np.array_equal(U[0], np.zeros(9))
    assert np.allclose(U[1:], [np.ones(9), 2 * x, 4 * x**2 - 1, 8 * x**3 - 4 * x], rtol=0, atol=1e-14)


@pytest.mark.parametrize("bad, match", [
    (dict(load=-1.0), r"load = -1\.0 N/m is not allowed"),
    (dict(load=np.nan), r"load = nan N/m is not allowed"),
])
def test_solve_normal_refuses_bad_load(bad, match):
    x = np.linspace(-1e-2, 1e-2, 11)
    with pytest.raises(ValueError, match=match):
        N.solve_normal(x, x**2, bad["load"], M)
