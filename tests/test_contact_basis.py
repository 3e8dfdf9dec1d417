"""The square-root-weighted traction basis of the contact solver (rail.contact._basis_matrix):
every influence coefficient against brute-force adaptive quadrature, and exactness for the Hertz
ellipse q proportional to W = sqrt(1 - zeta^2 / a^2)."""

import numpy as np
import pytest
from scipy.integrate import quad

from rail import contact as C


def _psi(n, at, M, lead, trail):
    """(psi_n, support): the basis function of node n in units of the spacing (Delta = 1)."""
    xn = float(n - M)
    if n > lead or n < trail:  # unloaded node: plain hat
        return (lambda z: max(1 - abs(z - xn), 0.0)), (xn - 1, xn + 1)
    W = lambda z: np.sqrt(max(1 - (z / at) ** 2, 0.0))  # noqa: E731
    wn = W(xn)
    if n == lead:  # g extrapolated linearly beyond the last node: phi = 1 + t there
        phi, sup = (lambda z: 1 + (z - xn) if z >= xn else max(1 - (xn - z), 0.0)), (xn - 1, at)
    elif n == trail:
        phi, sup = (lambda z: 1 + (xn - z) if z <= xn else max(1 - (z - xn), 0.0)), (-at, xn + 1)
    elif n == lead - 1:  # phi = -t beyond the last node
        phi, sup = (lambda z: -(z - xn - 1) if z >= xn + 1 else max(1 - abs(z - xn), 0.0)), (xn - 1, at)
    elif n == trail + 1:
        phi, sup = (lambda z: -(xn - 1 - z) if z <= xn - 1 else max(1 - abs(z - xn), 0.0)), (-at, xn + 1)
    else:
        phi, sup = (lambda z: max(1 - abs(z - xn), 0.0)), (xn - 1, xn + 1)
    return (lambda z: W(z) * phi(z) / wn), sup


def _brute(f, sup, x, xn):
    lo, hi = sup
    pts = sorted({p for p in (xn - 1, xn, xn + 1, x) if lo < p < hi}) or None
    g = lambda z: f(z) * np.log(abs(x - z)) if z != x else 0.0  # noqa: E731
    return quad(g, lo, hi, points=pts, limit=400, epsabs=1e-14, epsrel=1e-13)[0]


@pytest.mark.parametrize("base, M", [(9.0, 12), (3.0, 6)])
@pytest.mark.parametrize("e", [1e-6, 0.01, 0.3, 0.99])
def test_every_column_matches_brute_force_quadrature(base, M, e):
    # Rows: the nodes, the leading neighbour and the row at +a; all columns (edge, interior and
    # unloaded). Measured worst error 3.5e-10 of the column's magnitude (at e = 1e-6, where psi_lead
    # is large and the reference quadrature is the limit), else below 1e-12.
    nn = 2 * M + 1
    at = base + e
    Mom, mu = C.chebyshev_hat_moments(nn)
    A = np.empty((nn, nn + 1))
    r_a = np.empty(nn)
    w = np.empty(nn)
    lead, trail = C._basis_matrix(at, 1.0, M, Mom, mu, A, r_a, w, C._basis_workspace(nn))
    assert lead == M + int(base) and trail == 2 * M - lead
    for n in range(nn):
        f, sup = _psi(n, at, M, lead, trail)
        xn = float(n - M)
        ref = np.array([_brute(f, sup, r - M, xn) for r in range(nn + 1)] + [_brute(f, sup, at, xn)])
        got = np.r_[A[n], r_a[n]]
        assert np.abs(got - ref).max() <= 1e-8 * np.abs(ref).max(), (n, np.abs(got - ref).max())
        w_ref = quad(f, *sup, points=[p for p in (xn - 1, xn, xn + 1) if sup[0] < p < sup[1]] or None,
                     limit=400, epsabs=1e-14, epsrel=1e-13)[0]
        assert w[n] == pytest.approx(w_ref, rel=1e-8, abs=1e-12)


@pytest.mark.parametrize("at", [20.0 + 1e-6, 20.37, 20.999])
def test_the_hertz_ellipse_is_represented_exactly(at):
    # q = W (g = 1 at every loaded node): int W ln|x - zeta| = (pi a / 2)(ln(a / 2) - 1/2) + pi x^2 / (2 a)
    # inside the patch, int W = pi a / 2 (units of the spacing).
    M = 23
    nn = 2 * M + 1
    Mom, mu = C.chebyshev_hat_moments(nn)
    A = np.empty((nn, nn + 1))
    r_a = np.empty(nn)
    w = np.empty(nn)
    lead, trail = C._basis_matrix(at, 1.0, M, Mom, mu, A, r_a, w, C._basis_workspace(nn))
    x = np.arange(nn + 1) - M
    loaded = np.arange(trail, lead + 1)
    Wn = np.sqrt(1 - ((loaded - M) / at) ** 2)
    u = Wn @ A[loaded]
    inside = np.abs(x) <= at
    exact = np.pi * at / 2 * (np.log(at / 2) - 0.5) + np.pi * x**2 / (2 * at)
    assert np.abs(u - exact)[inside].max() < 1e-9 * np.abs(exact).max()
    assert Wn @ r_a[loaded] == pytest.approx(np.pi * at / 2 * (np.log(at / 2) - 0.5) + np.pi * at / 2, rel=1e-9)
    assert Wn @ w[loaded] == pytest.approx(np.pi * at / 2, rel=1e-12)
