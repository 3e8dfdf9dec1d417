"""Filon weights (rail.quadrature.filon_weights): exact for piecewise polynomials at any frequency,
the Gauss rule at zero frequency, and convergent for a smooth function against scipy's QAWO."""

import numpy as np
import pytest
from scipy.integrate import quad

from rail.quadrature import filon_weights


def _segments(lo, hi, S, m):
    xg, wg = np.polynomial.legendre.leggauss(m)
    e = np.linspace(lo, hi, S + 1)
    a, b = e[:-1], e[1:]
    return 0.5 * (a + b)[:, None] + 0.5 * (b - a)[:, None] * xg, a, b, np.outer(0.5 * (b - a), wg)


@pytest.mark.parametrize("d", [0.0, 1e-6, 0.7, -13.3, 250.0])
def test_exact_for_a_polynomial_of_degree_m_minus_1_at_any_frequency(d):
    x, a, b, _ = _segments(-2.0, 3.0, 1, 8)
    c = np.array([0.3, -1.0, 0.5, 2.0, -0.7, 0.1, 0.05, -0.02])
    f = np.polynomial.polynomial.polyval(x, c)
    got = (filon_weights(x, a, b, d) * f).sum()
    # exact: int x^n exp(-i d x) by repeated integration by parts is messy; use QAWO on the
    # polynomial (smooth, so QAWO converges to round-off)
    g = lambda t: np.polynomial.polynomial.polyval(t, c)  # noqa: E731
    if d == 0:
        ref = quad(g, -2, 3)[0]
    else:
        ref = quad(g, -2, 3, weight="cos", wvar=d)[0] - 1j * quad(g, -2, 3, weight="sin", wvar=d)[0]
    assert abs(got - ref) <= 1e-12 * max(1.0, abs(ref)) * 10


def test_zero_frequency_on_gauss_nodes_is_the_gauss_rule():
    x, a, b, wg = _segments(-1.0, 4.0, 5, 16)
    np.testing.assert_allclose(filon_weights(x, a, b, 0.0).real, wg, rtol=1e-12, atol=1e-15)
    assert np.abs(filon_weights(x, a, b, 0.0).imag).max() == 0


@pytest.mark.parametrize("d", [2.0, -40.0, 400.0])
def test_smooth_function_at_high_frequency_few_nodes(d):
    # 1 / (1 + x^2) on [-3, 5] with 8 segments of 16 nodes: 128 nodes whatever the frequency
    # (400 rad/m is 500 oscillations); error relative to int |f| = 2.62
    x, a, b, _ = _segments(-3.0, 5.0, 8, 16)
    f = lambda t: 1.0 / (1.0 + t**2)  # noqa: E731
    got = (filon_weights(x, a, b, d) * f(x)).sum()
    ref = quad(f, -3, 5, weight="cos", wvar=d, limit=2000)[0] - 1j * quad(f, -3, 5, weight="sin", wvar=d, limit=2000)[0]
    assert abs(got - ref) < 1e-10 * 2.62
    # the Gauss rule on the same nodes aliases the oscillation at the high frequency
    if abs(d) >= 40:
        gauss = (_segments(-3.0, 5.0, 8, 16)[3] * f(x) * np.exp(-1j * d * x)).sum()
        assert abs(gauss - ref) > 1e-6 * 2.62
