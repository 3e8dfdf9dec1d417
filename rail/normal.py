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
  approach of both bodies under a pressure p is u(x) = -k int p(s) ln|x - s| ds + const with
  k = 2 / (pi E*) = 4 (1 - nu^2) / (pi E), the compliance of the tangential problem (eq 29).
* Pressure p >= 0 in Pa; loads in N (the whole strip) unless called "per unit width" (N/m).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.special import j0, j1

from .contact import ContactError, ContactMaterial, compliance

__all__ = ["composite_modulus", "influence_matrix", "NormalSolution", "solve_normal", "approach_filter",
           "half_length_filter", "PatchContact", "patch_contact", "CHEBYSHEV_NODES"]

CHEBYSHEV_NODES = 32  # Chebyshev nodes across the patch in patch_contact (error: tests/test_normal.py)


def composite_modulus(m: ContactMaterial) -> float:
    """Composite plane-strain modulus E* = E / (2 (1 - nu^2)) of two steel bodies [Pa].

    Parameters
    ----------
    m : ContactMaterial

    Returns
    -------
    float
        E* [Pa]; 2 / (pi E*) equals rail.contact.compliance(m).
    """
    return m.youngs_modulus / (2 * (1 - m.poisson_ratio**2))


def _log_element(t0, t1):
    """int_{t0}^{t1} ln|t| dt (exact), elementwise."""
    def g(t):
        t = np.asarray(t, dtype=float)
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(t == 0, 0.0, t * np.log(np.abs(t)) - t)
    return g(t1) - g(t0)


def influence_matrix(x, h: float, period: float | None = None):
    """Influence coefficients of piecewise-constant pressure elements on a 2D half-space.

    A[i, j] = -int over element j of ln|x_i - s| ds (open surface) or of ln|2 sin(pi (x_i - s) / lambda)|
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

    x        : (n,) element centres, m
    p        : (n,) pressure, Pa (>= 0)
    approach : rigid approach delta of the two bodies, m (the gap is h + k A p - delta), defined
               up to the constant of the 2D kernel (differences at equal load are meaningful)
    zones    : number of separate contact zones
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
    n = x.size
    active = np.zeros(n, dtype=bool)
    active[np.argmin(gap)] = True
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
        pen = (~active) & (g < -1e-12 * max(np.ptp(gap), 1e-30))
        if not pen.any():
            zones = int(np.sum(np.diff(np.concatenate([[0], active.astype(int), [0]])) == 1))
            if period is not None and active[0] and active[-1] and zones > 1:
                zones -= 1  # a zone across the period's ends is one zone
            return NormalSolution(x, p, float(delta), zones)
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
    z = np.abs(np.asarray(beta, dtype=float)) * a
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(z > 1e-8, 2 * j1(z) / np.where(z > 1e-8, z, 1.0), 1.0 - z * z / 8)


@dataclass(frozen=True)
class PatchContact:
    """Single-zone normal contact along a wheel passage (patch_contact).

    a       : (steps,) half-length, m
    shape   : (steps, nodes) pressure / Hertz ellipse of the same P and a at the patch nodes, -
              (p = P / (pi a b) sqrt(1 - xi^2/a^2) shape); 1 on a smooth rail
    min_shape : (steps,) smallest shape factor over the patch, edges included; < 0 means contact lost
              inside the patch
    shift   : (steps,) where the single-zone contact would centre relative to the wheel, c = R_w x
              (the Chebyshev mean of the gap slope), m; neglected (the patch stays centred on the
              wheel, as in the report)
    """

    a: np.ndarray
    shape: np.ndarray
    min_shape: np.ndarray
    shift: np.ndarray


def _cheb_coefficients(f):
    """Chebyshev coefficients c_m of samples at the Gauss-Chebyshev nodes (last axis): f = sum c_m T_m."""
    n = f.shape[-1]
    k = np.arange(n)
    theta = (k + 0.5) * np.pi / n
    T = np.cos(np.outer(np.arange(n), theta))  # (m, k)
    c = f @ T.T * (2.0 / n)
    c[..., 0] /= 2
    return c


def _u_series(c, sigma):
    """sum_{m>=1} c_m U_{m-1}(sigma) for c (..., n) and sigma (..., q) by Clenshaw's recurrence."""
    n = c.shape[-1]
    b1 = np.zeros(c.shape[:-1] + (sigma.shape[-1],))
    b2 = np.zeros_like(b1)
    for m in range(n - 1, 0, -1):  # sum_{j=0}^{n-2} c_{j+1} U_j(sigma)
        b1, b2 = c[..., m:m + 1] + 2 * sigma * b1 - b2, b1
    return b1


def patch_contact(P, x_wheel, slope, m: ContactMaterial, xi, nodes: int = CHEBYSHEV_NODES, a_start=None, tol: float = 1e-13,
                  max_iter: int = 60) -> PatchContact:
    """The exact single-zone 2D contact of the wheel on the rough rail at each step of a passage.

    With the gap slope h'(s) = s / R_w - r'(x_w + s) = sum_m c_m T_m(s / a) over the patch, the
    bounded solution of u' = -h' in [-a, a] (Johnson, Contact Mechanics, eqs 2.44-2.49) is
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

    Returns
    -------
    PatchContact

    Raises
    ------
    ContactError
        Multiple contact: the load has no single-zone solution (the effective curvature
        c_1 / a <= 0, the wheel bridges a trough) or the iteration does not converge.
    """
    P = np.asarray(P, dtype=float)
    xw = np.asarray(x_wheel, dtype=float)
    Estar = composite_modulus(m)
    Pw = P / (2 * m.half_width)
    tau = np.cos((np.arange(nodes) + 0.5) * np.pi / nodes)  # Gauss-Chebyshev nodes
    target = 4 * Pw / (np.pi * Estar)  # a c_1(a) must equal this [m]

    def load(a):  # a c_1(a) - target, and c_1 / a (the effective curvature)
        c1 = _cheb_coefficients(a[:, None] * tau[None, :] / m.wheel_radius
                                - slope(xw[:, None] + a[:, None] * tau[None, :]))[:, 1]
        return a * c1 - target, c1 / a

    # secant iteration on a c_1(a) = 4 P' / (pi E*), from Hertz with R_w and with 1/R_eq
    a0 = np.sqrt(target * m.wheel_radius) if a_start is None else np.asarray(a_start, dtype=float).copy()
    f0, kappa = load(a0)
    a1 = np.sqrt(target / np.where(kappa > 0, kappa, 1 / m.wheel_radius))
    a1 = np.where(np.abs(a1 - a0) > 1e-9 * a0, a1, a0 * (1 + 1e-6))
    for _ in range(max_iter):
        f1, kappa = load(a1)
        if np.all(np.abs(f1) <= tol * target):
            break
        den = np.where(f1 != f0, f1 - f0, 1.0)
        a2 = np.where(f1 != f0, a1 - f1 * (a1 - a0) / den, a1)
        a0, f0, a1 = a1, f1, np.clip(a2, 0.5 * a1, 2.0 * a1)
    else:
        i = int(np.argmax(np.abs(f1)))
        raise ContactError(f"multiple contact: at x = {xw[i]:.5g} m the load has no single-zone contact (the roughness under "
                           f"the patch, a = {a1[i] * 1e3:.3g} mm, is too large for one contact zone).")
    if np.any(kappa <= 0):
        i = int(np.argmin(kappa))
        raise ContactError(f"multiple contact: at x = {xw[i]:.5g} m the roughness under the patch (a = {a1[i] * 1e3:.3g} mm) "
                           "leaves no single contact zone (effective curvature <= 0).")
    a = a1
    c = _cheb_coefficients(a[:, None] * tau[None, :] / m.wheel_radius - slope(xw[:, None] + a[:, None] * tau[None, :]))
    sigma = np.clip(np.asarray(xi, dtype=float)[None, :] / a[:, None], -1.0, 1.0)
    shape = _u_series(c, sigma) / c[:, 1:2]
    # smallest shape over the whole patch, edges included: on a fixed fine sigma grid, by one product
    check = np.linspace(-1, 1, 4 * nodes + 1)
    U = _u_series(np.eye(nodes), check[None, :].repeat(nodes, 0))  # row m: U_{m-1}(check), 0 for m = 0
    min_shape = np.minimum(np.min(c @ U, axis=1) / c[:, 1], np.min(shape, axis=1))
    return PatchContact(a=a, shape=shape, min_shape=min_shape, shift=-m.wheel_radius * c[:, 0])
