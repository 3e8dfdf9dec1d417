"""Normal contact that sees the roughness inside the patch: 2D elastic half-space (plane strain).

The report's normal contact (sec. 4.2-4.3, eqs 22-24) is a point spring on the roughness at the
wheel centre and a Hertz patch whose radius follows the local rail curvature, 1/R = 1/R_w - z''.
That holds for wavelengths much longer than the patch 2a. This module gives the contact that holds
down to and below the patch length (docs/contact.md, "Normal contact with roughness in the patch"):

* ``solve_normal``: brute force. The pressure on a fine grid of piecewise-constant elements from
  the elastic half-space's influence coefficients (the log kernel of the tangential problem, or its
  periodic form), any number of contact zones (an active-set iteration on the complementarity
  problem gap >= 0, p >= 0, gap p = 0). Slow, general: the reference.
* ``patch_contact``: production. The exact single-zone solution of the 2D problem (the bounded
  solution of the airfoil equation) for the wheel's parabola plus the rail roughness under the
  patch, by a Chebyshev expansion of the gap slope over the patch: the half-length from the load,
  the pressure as the Hertz ellipse times a smooth shape factor, vectorised over the steps of a
  wheel passage. Its validity is checked: a shape factor < 0 is contact lost inside the patch.
* ``approach_filter``, ``half_length_filter``: the contact filters of the linearised problem about
  the smooth-rail Hertz patch (J0(beta a) on the roughness that drives the normal force;
  2 J1(beta a) / (beta a) on the curvature that sets the half-length).

Conventions
-----------
* x along the rail in the wheel's direction of travel, the wheel centre at x_w; the patch
  coordinate s = x - x_w, the patch [-a, a] (leading edge at +a), tau = s / a.
* Rail roughness r(x) is the rail-head height, positive upwards (rail.interaction, eq 18). The
  undeformed gap between wheel and rail is h(s) = s^2 / (2 R_w) - r(x_w + s) (up to a constant).
* Plane strain per unit width of a strip of width 2b (the report's 2D contact: its eq 23 is the 2D
  Hertz half-length with the load per unit width P' = P / (2b)). Composite modulus
  1/E* = (1 - nu_1^2)/E_1 + (1 - nu_2^2)/E_2 = 2 (1 - nu^2) / E for two steel bodies. The surface
  approach of both bodies under a pressure p is u(x) = -k int p(s) ln abs(x - s) ds + const with
  k = 2 / (pi E*) = 4 (1 - nu^2) / (pi E), the compliance of the tangential problem (eq 29).
* Pressure p >= 0 in Pa; loads in N (the whole strip) unless called "per unit width" (N/m).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from .._lazyjit import njit
from .hertz import ContactError, ContactMaterial, composite_modulus, compliance

__all__ = ["composite_modulus", "influence_matrix", "NormalSolution", "solve_normal", "approach_filter",
           "half_length_filter", "PatchContact", "patch_contact", "CHEBYSHEV_NODES", "MultizoneContact",
           "multizone_contact", "passage_contact", "MULTIZONE_REFINE"]

CHEBYSHEV_NODES = 32  # Chebyshev nodes across the patch in patch_contact (error: tests/test_normal.py)


def _log_element(t0, t1):
    """int_{t0}^{t1} ln|t| dt (exact), elementwise."""
    def g(t):
        t = np.asarray(t, dtype=float)
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(t == 0, 0.0, t * np.log(np.abs(t)) - t)
    return g(t1) - g(t0)


def influence_matrix(x, h: float, period: float | None = None):
    """Influence coefficients of piecewise-constant pressure elements on a 2D half-space.

    A[i, j] = -int over element j of ln abs(x_i - s) ds (open surface) or of ln abs(2 sin(pi (x_i - s) / lambda))
    (pressure periodic over lambda), so that the approach of both bodies is u = k A p + const with
    k = 2 / (pi E*).

    Parameters
    ----------
    x : ndarray, shape (n,)
        Element centres [m], uniformly spaced by ``h``.
    h : float
        Element length [m], > 0.
    period : float, optional
        lambda [m]: the pressure repeats with this period (x spans one period, n h = lambda).

    Returns
    -------
    ndarray, shape (n, n)
        A [m].
    """
    x = np.asarray(x, dtype=float)
    if not (np.isfinite(h) and h > 0):
        raise ValueError(f"element length h = {h!r} m is not allowed: it must be a finite number > 0.")
    t = x[None, :] - x[:, None]
    if period is None:
        return -_log_element(t - h / 2, t + h / 2)
    if not (np.isfinite(period) and period > 0):
        raise ValueError(f"period = {period!r} m is not allowed: it must be a finite number > 0.")
    t = (t + period / 2) % period - period / 2  # nearest image, in [-lambda/2, lambda/2)
    # ln|2 sin(pi t / lambda)| = ln|t| + ln(2 pi / lambda) + ln(sinc(t / lambda)): the last term is smooth
    # for |t| < lambda; 4-point Gauss-Legendre per element
    g, w = np.polynomial.legendre.leggauss(4)
    smooth = sum(wk * np.log(np.sinc((t + gk * h / 2) / period)) for gk, wk in zip(g, w)) * h / 2
    return -(_log_element(t - h / 2, t + h / 2) + h * np.log(2 * np.pi / period) + smooth)


@dataclass(frozen=True)
class NormalSolution:
    """Brute-force normal contact on a grid (solve_normal).

    Attributes
    ----------
    x : (n,) element centres, m
    p : (n,) pressure, Pa (>= 0)
    approach : rigid approach delta of the two bodies, m (the gap is h + k A p - delta), defined
               up to the constant of the 2D kernel (differences at equal load are meaningful)
    zones : number of separate contact zones
    """

    x: np.ndarray
    p: np.ndarray
    approach: float
    zones: int

    @property
    def contact(self) -> np.ndarray:
        return self.p > 0


def solve_normal(x, gap, load: float, m: ContactMaterial, period: float | None = None, max_iter: int = 500):
    """Frictionless normal contact of two elastic bodies on a grid, any number of contact zones.

    Solves gap_i + k (A p)_i - delta >= 0, p_i >= 0, their product 0, with h sum(p) = ``load``
    (Kalker's active-set method for the complementarity problem).

    Parameters
    ----------
    x : ndarray, shape (n,)
        Element centres [m], uniformly spaced.
    gap : ndarray, shape (n,)
        Undeformed gap h(x_i) [m], e.g. x^2 / (2 R) - r(x).
    load : float
        Load per unit width P' [N/m] (open surface), or the mean pressure times the period
        (periodic), > 0.
    m : ContactMaterial
        E and nu (k = rail.contact.compliance(m)).
    period : float, optional
        Pressure periodic over this length [m] (influence_matrix).
    max_iter : int
        Largest number of active-set changes.

    Returns
    -------
    NormalSolution

    Raises
    ------
    ContactError
        If the active set does not settle within max_iter.
    """
    x = np.asarray(x, dtype=float)
    gap = np.asarray(gap, dtype=float)
    if not (np.isfinite(load) and load > 0):
        raise ValueError(f"load = {load!r} N/m is not allowed: it must be a finite number > 0.")
    if gap.shape != x.shape or not np.all(np.isfinite(gap)):
        raise ValueError("gap must be finite with one value per element.")
    h = float(x[1] - x[0])
    A = compliance(m) * influence_matrix(x, h, period)
    p, delta, active = _active_set(A, gap, load, h, max_iter=max_iter)
    zones = int(np.sum(np.diff(np.concatenate([[0], active.astype(int), [0]])) == 1))
    if period is not None and active[0] and active[-1] and zones > 1:
        zones -= 1  # a zone across the period's ends is one zone
    return NormalSolution(x, p, float(delta), zones)


def _active_set(A, gap, load, h, active=None, max_iter: int = 500):
    """Kalker's active set for gap + A p - delta >= 0, p >= 0, (gap + A p - delta) p = 0, h sum(p) = load.

    A : (n, n) influence matrix times the compliance [m/Pa]; gap (n,) [m]; load [N/m]; h element
    length [m]; active : (n,) bool, optional first guess (a warm start: the previous step's set).
    Returns p (n,) [Pa], delta [m], the active set (n,) bool. Raises ContactError if it does not settle.
    """
    n = gap.size
    if active is None or not active.any():
        active = np.zeros(n, dtype=bool)
        active[np.argmin(gap)] = True
    else:
        active = active.copy()
    tol = 1e-12 * max(np.ptp(gap), 1e-30)
    for _ in range(max_iter):
        idx = np.flatnonzero(active)
        na = idx.size
        K = np.zeros((na + 1, na + 1))
        K[:na, :na] = A[np.ix_(idx, idx)]
        K[:na, na] = -1.0
        K[na, :na] = h
        rhs = np.concatenate([-gap[idx], [load]])
        sol = np.linalg.solve(K, rhs)
        p_a, delta = sol[:na], sol[na]
        if np.any(p_a < 0):  # release the tensile elements
            active[idx[p_a < 0]] = False
            if not active.any():
                active[idx[np.argmax(p_a)]] = True
            continue
        p = np.zeros(n)
        p[idx] = p_a
        g = gap + A @ p - delta
        pen = (~active) & (g < -tol)
        if not pen.any():
            return p, delta, active
        active |= pen
    raise ContactError(f"the normal contact's active set did not settle in {max_iter} changes.")


def approach_filter(beta, a):
    """Contact filter of the roughness that drives the normal force: J0(beta a).

    Linearised about the Hertz patch [-a, a], the approach at fixed load changes by the roughness
    averaged with the weight 1 / (pi sqrt(a^2 - s^2)) (the pressure increment of a load increment,
    by reciprocity); for r = cos(beta s) that is J0(beta a) (docs/contact.md). Tends to 1 for
    beta a -> 0, first zero at beta a = 2.405 (lambda = 1.31 x 2a), negative beyond.

    Parameters
    ----------
    beta : float or ndarray
        Roughness wavenumber 2 pi / lambda [rad/m].
    a : float
        Patch half-length [m], >= 0.

    Returns
    -------
    float or ndarray
        H [-].
    """
    from scipy.special import j0  # here, not at the top: importing scipy costs jobs that do not use it about 0.7 s CPU

    return j0(np.abs(np.asarray(beta, dtype=float)) * a)


def half_length_filter(beta, a):
    """Contact filter of the curvature that sets the half-length: 2 J1(beta a) / (beta a).

    The load condition of the single-zone solution, P' = (E*/2) int s h'(s) / sqrt(a^2 - s^2) ds,
    gives the Hertz relation with 1/R = 1/R_w + kappa_eff, where a cosine roughness of curvature
    kappa = beta^2 Delta contributes kappa_eff = kappa 2 J1(beta a) / (beta a) (report eq 24 is the
    limit beta a -> 0).

    Parameters
    ----------
    beta : float or ndarray
        Roughness wavenumber [rad/m].
    a : float
        Half-length [m].

    Returns
    -------
    float or ndarray
        [-].
    """
    from scipy.special import j1

    z = np.abs(np.asarray(beta, dtype=float)) * a
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(z > 1e-8, 2 * j1(z) / np.where(z > 1e-8, z, 1.0), 1.0 - z * z / 8)


@dataclass(frozen=True)
class PatchContact:
    """Single-zone normal contact along a wheel passage (patch_contact).

    Attributes
    ----------
    a : (steps,) half-length, m
    shape : (steps, nodes) pressure / Hertz ellipse of the same P and a at the patch nodes, -
              (p = P / (pi a b) sqrt(1 - xi^2/a^2) shape); 1 on a smooth rail
    min_shape : (steps,) smallest shape factor over the patch, edges included; < 0 means contact lost
              inside the patch
    shift : (steps,) where the single-zone contact would centre relative to the wheel, c = R_w x
              (the Chebyshev mean of the gap slope), m; neglected (the patch stays centred on the
              wheel, as in the report)
    zones : (steps,) number of contact zones (passage_contact; None from patch_contact: one)
    """

    a: np.ndarray
    shape: np.ndarray
    min_shape: np.ndarray
    shift: np.ndarray
    zones: np.ndarray | None = None


def _cheb_coefficients(f):
    """Chebyshev coefficients c_m of samples at the Gauss-Chebyshev nodes (last axis): f = sum c_m T_m."""
    n = f.shape[-1]
    k = np.arange(n)
    theta = (k + 0.5) * np.pi / n
    T = np.cos(np.outer(np.arange(n), theta))  # (m, k)
    c = f @ T.T * (2.0 / n)
    c[..., 0] /= 2
    return c


@njit(cache=True)
def _clenshaw_u(c, sigma, out):
    """out = sum_{m>=1} c_m U_{m-1}(sigma) row by row, by Clenshaw's recurrence (compiled).

    Parameters
    ----------
    c : ndarray, shape (rows, n)
        Chebyshev coefficients c_m [any unit].
    sigma : ndarray, shape (rows, q)
        Points in [-1, 1] [-].
    out : ndarray, shape (rows, q)
        Filled with the sum [unit of c]: b_m = c_m + 2 sigma b_{m+1} - b_{m+2} from b_n = b_{n+1} = 0,
        evaluated in that order (numpy's operations on whole arrays give the same numbers).
    """
    rows, n = c.shape
    q = sigma.shape[1]
    two_sigma = np.empty(q)
    b1 = np.empty(q)
    b2 = np.empty(q)
    for i in range(rows):
        for k in range(q):
            two_sigma[k] = 2 * sigma[i, k]
            b1[k] = 0.0
            b2[k] = 0.0
        for m in range(n - 1, 0, -1):  # sum_{j=0}^{n-2} c_{j+1} U_j(sigma)
            cm = c[i, m]
            for k in range(q):
                t = cm + two_sigma[k] * b1[k] - b2[k]
                b2[k] = b1[k]
                b1[k] = t
        for k in range(q):
            out[i, k] = b1[k]


def _u_series(c, sigma):
    """sum_{m>=1} c_m U_{m-1}(sigma) for c (..., n) and sigma (..., q) by Clenshaw's recurrence.

    Parameters
    ----------
    c : ndarray, shape (..., n)
        Chebyshev coefficients c_m, m = 0..n-1 (c_0 does not enter) [any unit].
    sigma : ndarray, shape (..., q)
        Points in [-1, 1] [-]; the leading axes of c and sigma broadcast.

    Returns
    -------
    ndarray, shape (..., q)
        The sum [unit of c].
    """
    c = np.asarray(c, dtype=float)
    sigma = np.asarray(sigma, dtype=float)
    lead = np.broadcast_shapes(c.shape[:-1], sigma.shape[:-1])
    n, q = c.shape[-1], sigma.shape[-1]
    c2 = np.ascontiguousarray(np.broadcast_to(c, lead + (n,)).reshape(-1, n))
    s2 = np.ascontiguousarray(np.broadcast_to(sigma, lead + (q,)).reshape(-1, q))
    out = np.empty((s2.shape[0], q))
    _clenshaw_u(c2, s2, out)
    return out.reshape(lead + (q,))


def patch_contact(P, x_wheel, slope, m: ContactMaterial, xi, nodes: int = CHEBYSHEV_NODES, a_start=None, tol: float = 1e-13,
                  max_iter: int = 60, strict: bool = True) -> PatchContact:
    """The exact single-zone 2D contact of the wheel on the rough rail at each step of a passage.

    With the gap slope h'(s) = s / R_w - r'(x_w + s) = sum_m c_m T_m(s / a) over the patch, the
    bounded solution of u' = -h' in [-a, a] (Johnson, Contact Mechanics, eqs 2.44-2.49) is::

        p(s) = (E*/2) sqrt(1 - s^2/a^2) sum_{m>=1} c_m U_{m-1}(s / a),

    and the load fixes a: P / (2b) = pi E* a c_1 / 4. A smooth rail gives c_1 = a / R_w: Hertz
    (eq 23). The mean slope c_0 (a tilt) does not enter the pressure; it would move the patch centre
    by c = R_w c_0, which is neglected as in the report (returned as ``shift``).

    Parameters
    ----------
    P : ndarray, shape (steps,)
        Normal force [N], > 0.
    x_wheel : ndarray, shape (steps,)
        Wheel-centre position along the rail [m].
    slope : callable
        r'(x) [-] of the rail roughness at positions x [m] (any array shape).
    m : ContactMaterial
    xi : ndarray, shape (nodes_grid,)
        Patch nodes where the shape factor is wanted [m].
    nodes : int
        Chebyshev nodes across the patch [-].
    a_start : ndarray, optional
        First guess of a [m] (default: Hertz with R_w).
    tol : float
        Residual of the load condition, relative to the load, at which the secant iteration stops [-].
    max_iter : int
        Largest number of iterations.
    strict : bool
        True: a step with no single-zone solution is an error. False: such a step gets a = shift = NaN,
        shape = NaN and min_shape = -inf (passage_contact solves it with several zones).

    Returns
    -------
    PatchContact

    Raises
    ------
    ContactError
        (strict) Multiple contact: the load has no single-zone solution (the effective curvature
        c_1 / a <= 0, the wheel bridges a trough) or the iteration does not converge.
    """
    P = np.asarray(P, dtype=float)
    xw = np.asarray(x_wheel, dtype=float)
    Estar = composite_modulus(m)
    Pw = P / (2 * m.half_width)
    tau = np.cos((np.arange(nodes) + 0.5) * np.pi / nodes)  # Gauss-Chebyshev nodes
    target = 4 * Pw / (np.pi * Estar)  # a c_1(a) must equal this [m]

    def coefficients(a):  # the gap slope's Chebyshev coefficients over the patch [-]
        at = a[:, None] * tau[None, :]
        return _cheb_coefficients(at / m.wheel_radius - slope(xw[:, None] + at))

    def load(a):  # a c_1(a) - target, c_1 / a (the effective curvature) and the coefficients
        c = coefficients(a)
        return a * c[:, 1] - target, c[:, 1] / a, c

    # secant iteration on a c_1(a) = 4 P' / (pi E*), from Hertz with R_w and with 1/R_eq
    a0 = np.sqrt(target * m.wheel_radius) if a_start is None else np.asarray(a_start, dtype=float).copy()
    f0, kappa, _ = load(a0)
    a1 = np.sqrt(target / np.where(kappa > 0, kappa, 1 / m.wheel_radius))
    a1 = np.where(np.abs(a1 - a0) > 1e-9 * a0, a1, a0 * (1 + 1e-6))
    a_last = c_last = None
    for _ in range(max_iter):
        f1, kappa, c_last = load(a1)
        a_last = a1
        if np.all(np.abs(f1) <= tol * target):
            break
        den = np.where(f1 != f0, f1 - f0, 1.0)
        a2 = np.where(f1 != f0, a1 - f1 * (a1 - a0) / den, a1)
        a0, f0, a1 = a1, f1, np.clip(a2, 0.5 * a1, 2.0 * a1)
    else:
        if strict:
            i = int(np.argmax(np.abs(f1)))
            raise ContactError(f"multiple contact: at x = {xw[i]:.5g} m the load has no single-zone contact (the roughness "
                               f"under the patch, a = {a1[i] * 1e3:.3g} mm, is too large for one contact zone).")
    none = ~(np.abs(f1) <= tol * target) | ~(kappa > 0)  # no single-zone solution at these steps
    if none.any() and not strict:
        a1 = np.where(none, np.sqrt(target * m.wheel_radius), a1)  # placeholders, replaced by NaN below
    elif np.any(kappa <= 0):
        i = int(np.argmin(kappa))
        raise ContactError(f"multiple contact: at x = {xw[i]:.5g} m the roughness under the patch (a = {a1[i] * 1e3:.3g} mm) "
                           "leaves no single contact zone (effective curvature <= 0).")
    a = a1
    c = c_last if a is a_last else coefficients(a)  # converged: the last iteration's coefficients
    sigma = np.clip(np.asarray(xi, dtype=float)[None, :] / a[:, None], -1.0, 1.0)
    # smallest shape over the whole patch, edges included: on a fixed fine sigma grid, by one product
    check = np.linspace(-1, 1, 4 * nodes + 1)
    U = _u_series(np.eye(nodes), check[None, :].repeat(nodes, 0))  # row m: U_{m-1}(check), 0 for m = 0
    with np.errstate(divide="ignore", invalid="ignore"):  # c_1 = 0 only at the steps without a single zone (NaN below)
        shape = _u_series(c, sigma) / c[:, 1:2]
        min_shape = np.minimum(np.min(c @ U, axis=1) / c[:, 1], np.min(shape, axis=1))
    shift = -m.wheel_radius * c[:, 0]
    if none.any():
        a, shift = np.where(none, np.nan, a), np.where(none, np.nan, shift)
        shape[none], min_shape[none] = np.nan, -np.inf
    return PatchContact(a=a, shape=shape, min_shape=min_shape, shift=shift)


MULTIZONE_REFINE = 5  # brute-force elements per contact-grid spacing in multizone_contact (odd: one centred on each node)


@dataclass(frozen=True)
class MultizoneContact:
    """Normal contact with any number of zones at the steps of a passage (multizone_contact).

    Attributes
    ----------
    a : (steps,) half-length of the hull of the contact zones (the outermost edges, centred on the
            wheel; where the hull jumps with the tilt, the larger of its two ends), m
    offset : (steps,) the hull's centre that remains, m (0 within 5 % of a brute-force element unless
            the hull jumps)
    shape : (steps, nodes) pressure / Hertz ellipse of the same P and a at the patch nodes, -; 0 in a gap
    zones : (steps,) number of contact zones
    tilt : (steps,) gap slope removed to centre the hull on the wheel, -: the neglected move of the
            contact centre is shift = -R_w tilt (as PatchContact.shift)
    """

    a: np.ndarray
    shape: np.ndarray
    zones: np.ndarray
    tilt: np.ndarray
    offset: np.ndarray


def _hull(p, s, hf):
    """Outermost edges (lo, hi) of the contact [m] from the element pressures p at centres s [m], each
    from a square-root edge fitted to its last two elements (p^2 linear), within its edge element."""
    idx = np.flatnonzero(p > 0)
    out = []
    for k, nb, sgn in ((idx[-1], idx[-1] - 1, 1.0), (idx[0], idx[0] + 1, -1.0)):
        pk2 = p[k] ** 2
        pn2 = p[nb] ** 2 if 0 <= nb < p.size else 0.0
        frac = pk2 / (pn2 - pk2) if pn2 > pk2 else 0.5  # distance of the edge past the centre, in elements
        out.append(s[k] + sgn * hf * min(max(frac, 0.0), 1.0))
    return out[1], out[0]


def _centred_contact(A, h0, s, load, hf, R, active, t, max_iter):
    """The active set of gap h0 - t s (as _active_set) together with the tilt t that centres the hull of
    the contact on s = 0 (to 5 % of an element, or as well as it can where the hull jumps with t).

    For a fixed active set the pressure is linear in t (one factorisation, two right-hand sides), so
    t is iterated at that set (first with the parabola's dc/dt = R, then a secant clipped to R/20..2R,
    secant or bisection once bracketed) until the set no longer holds; then the set is updated as in
    _active_set.
    Returns p [Pa], t [-], the hull centre f [m], the active set, the hull edges lo, hi [m].
    """
    n = h0.size
    if active is None or not active.any():
        active = np.zeros(n, dtype=bool)
        active[np.argmin(h0 - t * s)] = True
    else:
        active = active.copy()
    tol = 1e-12 * max(np.ptp(h0), 1e-30)
    lo_t = hi_t = f_lo = f_hi = last = None
    for _ in range(max_iter):
        idx = np.flatnonzero(active)
        na = idx.size
        K = np.zeros((na + 1, na + 1))
        K[:na, :na] = A[np.ix_(idx, idx)]
        K[:na, na] = -1.0
        K[na, :na] = hf
        rhs = np.zeros((na + 1, 2))
        rhs[:na, 0], rhs[na, 0], rhs[:na, 1] = -h0[idx], load, s[idx]
        X = np.linalg.solve(K, rhs)  # (p, delta) = X[:, 0] + t X[:, 1]
        g0 = h0 - A[:, idx] @ (-X[:na, 0]) - X[na, 0]  # gap at t = 0 of this set's solution, and its slope in t
        g1 = -s + A[:, idx] @ X[:na, 1] - X[na, 1]
        for _ in range(max_iter):
            p_a = X[:na, 0] + t * X[:na, 1]
            if np.any(p_a < 0):  # release the tensile elements
                active[idx[p_a < 0]] = False
                if not active.any():
                    active[idx[np.argmax(p_a)]] = True
                break
            pen = (~active) & (g0 + t * g1 < -tol)
            if pen.any():
                active |= pen
                break
            p = np.zeros(n)
            p[idx] = p_a
            lo, hi = _hull(p, s, hf)
            f = 0.5 * (lo + hi)  # hull centre; rises with t (the tilt leans the gap down ahead)
            if abs(f) <= 0.05 * hf or (lo_t is not None and hi_t is not None and abs(hi_t - lo_t) * R < 0.05 * hf):
                return p, t, f, active, lo, hi  # centred, or the hull jumps here (a zone at its end appears or goes)
            if f < 0:
                lo_t, f_lo = t, f
            else:
                hi_t, f_hi = t, f
            if lo_t is not None and hi_t is not None:  # secant inside the bracket, bisection as a guard
                t_new = lo_t - f_lo * (hi_t - lo_t) / (f_hi - f_lo)
                if not (min(lo_t, hi_t) < t_new < max(lo_t, hi_t)) or abs(t_new - t) < 1e-3 * abs(hi_t - lo_t):
                    t_new = 0.5 * (lo_t + hi_t)
            else:  # no bracket yet: secant through the last two points (dc/dt between R / 20 and 2 R: the
                # hull of several zones, held by crests, moves less than the parabola's tangent point, R dt)
                slope_t = R if last is None or last[0] == t else (f - last[1]) / (t - last[0])
                t_new = t - f / min(max(slope_t, R / 20), 2 * R)
            last = (t, f)
            t = t_new
    raise ContactError(f"the multi-zone normal contact did not settle in {max_iter} active-set changes.")


def multizone_contact(P, x_wheel, slope, m: ContactMaterial, xi, tilt_start=None, refine: int = MULTIZONE_REFINE,
                      max_iter: int = 200) -> MultizoneContact:
    """Normal contact of the wheel on the rough rail with any number of contact zones, centred on the wheel.

    The gap h(s) = s^2 / (2 R_w) - r(x_w + s) - t s is solved by the brute force (solve_normal's active
    set, piecewise-constant elements ``refine`` per contact-grid spacing over the grid and a quarter of
    it again on each side; warm-started from the previous step's set) for the
    load P' = P / (2b), with the tilt t chosen so that the hull of the contact zones is centred on the
    wheel: this is the single-zone model's convention (patch_contact keeps the patch on the wheel,
    which is the exact solution for the gap less its Chebyshev mean slope c_0 s), continued to several
    zones; a single zone gives t = c_0 and patch_contact's pressure (to the brute force's accuracy).
    The pressure is handed to the tangential march as the Hertz ellipse of the hull's half-length a
    times a shape factor that is 0 in the gaps.

    Parameters
    ----------
    P : ndarray, shape (steps,)
        Normal force [N], > 0.
    x_wheel : ndarray, shape (steps,)
        Wheel-centre position [m].
    slope : callable
        r'(x) [-] of the rail roughness (rail.wear.roughness_slope); the gap is its integral.
    m : ContactMaterial
    xi : ndarray, shape (nodes,)
        The contact grid's nodes [m], uniformly spaced, symmetric about 0.
    tilt_start : ndarray, shape (steps,), optional
        First guess of t [-] (default: 0 at the first step, then the previous step's).
    refine : int
        Brute-force elements per grid spacing [-], odd, >= 1.
    max_iter : int
        Largest number of tilt iterations per step.

    Returns
    -------
    MultizoneContact

    Raises
    ------
    ContactError
        If the contact reaches 1.5 times the grid's half-length (the brute force covers that much; a hull
        beyond the grid's own end is returned, for the caller to widen the grid).
    """
    if not (isinstance(refine, (int, np.integer)) and refine >= 1 and refine % 2 == 1):
        raise ValueError(f"refine = {refine!r} is not allowed: it must be an odd integer >= 1.")
    P = np.atleast_1d(np.asarray(P, dtype=float))
    xw = np.atleast_1d(np.asarray(x_wheel, dtype=float))
    xi = np.asarray(xi, dtype=float)
    nn = xi.size
    delta = float(xi[1] - xi[0])
    hf = delta / refine
    extra = nn // 4  # nodes of margin on each side: a contact that outgrows the grid is measured, not cut
    s = xi[0] - (extra + 0.5) * delta + (np.arange((nn + 2 * extra) * refine) + 0.5) * hf  # element centres
    at_node = (np.arange(nn) + extra) * refine + refine // 2  # the element centred on node n
    A = compliance(m) * influence_matrix(s, hf)
    R = m.wheel_radius
    a_out = np.empty(P.size)
    shape = np.zeros((P.size, nn))
    zones = np.zeros(P.size, dtype=int)
    tilt = np.zeros(P.size)
    offset = np.zeros(P.size)
    active, t = None, 0.0
    for i in range(P.size):
        dh = s / R - slope(xw[i] + s)  # gap slope at the centres; the gap by the trapezoidal rule (exact for the parabola)
        h0 = np.concatenate([[0.0], np.cumsum(0.5 * (dh[1:] + dh[:-1]) * hf)])
        load = P[i] / (2 * m.half_width)
        moved = int(round((xw[i] - xw[i - 1]) / hf)) if i else -1
        if active is not None and 0 <= moved < s.size:  # warm start: the previous contact, `moved` elements behind,
            active = np.concatenate([active[moved:], np.zeros(moved, dtype=bool)])  # and its tilt
        else:
            active = None
            if tilt_start is not None and np.isfinite(tilt_start[i]):
                t = float(tilt_start[i])
        p, t, f, active, lo, hi = _centred_contact(A, h0, s, load, hf, R, active, t, max_iter)
        if p[0] > 0 or p[-1] > 0:
            raise ContactError(f"multiple contact: at x = {xw[i]:.5g} m the contact zones reach {abs(s[0]) * 1e3:.3g} mm from "
                               "the wheel (1.5 times the contact grid): the roughness spreads the contact far beyond the patch.")
        a_i = max(hi, -lo)  # (hi = -lo but where the hull jumps with the tilt: then one end lies inside the ellipse)
        pn = p[at_node]
        if pn.any():
            a_i = max(a_i, float(np.max(np.abs(xi[pn > 0]))) + 1e-6 * delta)  # every loaded node inside the ellipse
        ell = P[i] / (np.pi * a_i * m.half_width) * np.sqrt(np.clip(1 - (xi / a_i) ** 2, 0.0, None))
        shape[i] = np.where(pn > 0, pn / np.where(ell > 0, ell, 1.0), 0.0)
        a_out[i] = a_i
        zones[i] = int(np.sum(np.diff(np.concatenate([[0], (p > 0).astype(int), [0]])) == 1))
        tilt[i] = t
        offset[i] = f
    return MultizoneContact(a=a_out, shape=shape, zones=zones, tilt=tilt, offset=offset)


def passage_contact(P, x_wheel, slope, m: ContactMaterial, xi, refine: int = MULTIZONE_REFINE) -> PatchContact:
    """The normal contact at the steps of a wheel passage: patch_contact's exact single zone where it holds,
    multizone_contact where it does not (its pressure would turn negative inside the patch, or the load
    has no single-zone half-length).

    Parameters
    ----------
    P, x_wheel, slope, m, xi
        As patch_contact (P [N], x_wheel [m], slope r' [-], xi [m]: the contact grid's nodes).
    refine : int
        Brute-force elements per grid spacing in the multi-zone steps [-] (multizone_contact).

    Returns
    -------
    PatchContact
        With min_shape = 0 and ``zones`` > 1 (or a single zone that the brute force found) at the
        multi-zone steps, shift = -R_w tilt there.
    """
    pc = patch_contact(P, x_wheel, slope, m, xi, strict=False)
    zones = np.ones(np.size(P), dtype=int)
    multi = ~(pc.min_shape > 0)
    if not multi.any():
        return dataclasses.replace(pc, zones=zones)
    idx = np.flatnonzero(multi)
    mz = multizone_contact(np.asarray(P, dtype=float)[idx], np.asarray(x_wheel, dtype=float)[idx], slope, m, xi,
                           tilt_start=-pc.shift[idx] / m.wheel_radius, refine=refine)
    a, shape, min_shape, shift = pc.a.copy(), pc.shape.copy(), pc.min_shape.copy(), pc.shift.copy()
    a[idx], shape[idx], min_shape[idx], shift[idx] = mz.a, mz.shape, 0.0, -m.wheel_radius * mz.tilt
    zones[idx] = mz.zones
    return PatchContact(a=a, shape=shape, min_shape=min_shape, shift=shift, zones=zones)
