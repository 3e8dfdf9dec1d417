"""Hertz normal contact and 2D unsteady tangential rolling contact (report sec. 4.2-4.3).

Conventions
-----------
* The wheel rolls in +x at speed V. The patch coordinate xi is measured from the contact centre
  with the leading edge at xi = +a. Rail particles cross the patch from +a to -a.
* q(xi, t) is the tangential traction (Pa) and p the pressure (Pa). s is the slip velocity of
  eq 26, s = V gamma - V du/dxi + du/dt. In slip, q = -mu_d p sign(s) (eq 27). For a driving
  wheel gamma < 0 and q > 0.
* u(xi, t) is the relative tangential surface displacement (eq 29), u = -k int q(zeta) K(xi, zeta)
  d zeta with k = 4 (1 - nu^2) / (pi E). The kernel depends on the closure::

    report   (eqs 29, 32-33): K = ln|1 - xi/zeta|, plus u(0, t) = q(0, t) / sigma.
    default  (well-posed):    K = ln(|xi - zeta| / l(t)), l = (a / 2) exp(2 s / pi), s = 1.

  The two agree in steady rolling, where only du/dxi matters. The default is the report's rigid
  term linearised about the Cattaneo traction at vanishing force (docs/contact.md). The family
  parameter s scales the report's rigid compliance 1/sigma.

Discretisation (docs/contact.md)
--------------------------------
The grid is fixed to the patch, with nodes xi_n = (n - M) Delta, and the wheel advances
Delta = V dt per step. A rail particle at node m+1 at step i-1 is at node m at step i, so the
material derivative du/dt - V du/dxi is exact along particle paths::

    s_m = V gamma + (u_m(t) - u_{m+1}(t - dt)) / dt.

The traction is q = W sum_n g_n phi_n with W = sqrt(1 - xi^2/a^2) and g_n = q_n / W(xi_n):
square-root weighted hats, exact for the Hertz ellipse, so that the square-root edges of the
traction carry no grid-position error (the unknowns stay the nodal tractions). u is collocated at
the nodes; the log-kernel influence coefficients are rebuilt with a(t) every step (_basis_matrix).
A particle that entered the patch during the step sticks from the edge displacement at its entry
time (interpolated between the steps); the frictional work integrates the Hertz pressure exactly
along each path (_step_work). Each step is a small linear complementarity problem (stick: s = 0,
abs(q) <= mu_s p; slip: q = -mu_d p sign(s)), solved by an active-set iteration that admits any
number of stick and slip zones.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
from numba import njit

__all__ = [
    "ContactMaterial",
    "ContactError",
    "compliance",
    "hertz_half_length",
    "equivalent_radius",
    "hertz_pressure",
    "carter",
    "TangentialSolution",
    "ContactNumerics",
    "MIN_NODES",
    "solve_tangential",
    "rolling_grid",
    "checkerboard_measure",
    "perturbation_growth",
]


class ContactError(RuntimeError):
    """A physical assumption of the contact model no longer holds (multiple contact, no solution)."""


@dataclass(frozen=True)
class ContactMaterial:
    """Contact parameters (section 6).

    youngs_modulus   : E, Pa (both bodies)
    poisson_ratio    : nu, -
    half_width       : b, m (contact width 2b)
    wheel_radius     : R_w, m
    friction_dynamic : mu_d, -
    friction_static  : mu_s, -, >= mu_d
    creepage         : gamma_1, - (eq 25; negative for a driving wheel)
    """

    youngs_modulus: float
    poisson_ratio: float
    half_width: float
    wheel_radius: float
    friction_dynamic: float
    friction_static: float
    creepage: float

    def __post_init__(self):
        if self.friction_static < self.friction_dynamic:
            raise ValueError(
                f"contact.friction_static = {self.friction_static} is not allowed: it must be >= "
                f"contact.friction_dynamic = {self.friction_dynamic}."
            )
        for name in ("youngs_modulus", "half_width", "wheel_radius", "friction_dynamic"):
            if not getattr(self, name) > 0:
                raise ValueError(f"contact.{name} = {getattr(self, name)!r} is not allowed: it must be > 0.")


def compliance(m: ContactMaterial) -> float:
    """Tangential compliance of both bodies together, k = 4 (1 - nu^2) / (pi E) (eqs 29-31).

    Parameters
    ----------
    m : ContactMaterial

    Returns
    -------
    float
        k [1/Pa].
    """
    return 4 * (1 - m.poisson_ratio**2) / (np.pi * m.youngs_modulus)


def equivalent_radius(curvature, m: ContactMaterial):
    """Equivalent radius R from 1/R = 1/R_w + kappa (eq 24).

    Parameters
    ----------
    curvature : float or ndarray
        Rail-head curvature kappa = -z'' [1/m] (convex upwards positive).
    m : ContactMaterial
        Gives the wheel radius R_w [m].

    Returns
    -------
    float or ndarray
        R [m].

    Raises
    ------
    ContactError
        Where the rail is concave more sharply than the wheel (z'' >= 1/R_w): the wheel touches at
        more than one point.
    """
    curvature = np.asarray(curvature, dtype=float)
    inv = 1.0 / m.wheel_radius + curvature
    if np.any(inv <= 0):
        i = int(np.argmin(inv))
        raise ContactError(
            f"multiple contact: the rail curvature z'' = {-np.ravel(curvature)[i]:.4g} 1/m at sample {i} reaches "
            f"1/R_w = {1 / m.wheel_radius:.4g} 1/m; the wheel touches at more than one point (eq 24)."
        )
    return 1.0 / inv


def hertz_half_length(P, R, m: ContactMaterial):
    """Hertz contact half-length a = sqrt(4 (1 - nu^2) P R / (pi b E)) (eq 23).

    Parameters
    ----------
    P : float or ndarray
        Normal force [N], finite and >= 0 (P = 0 gives a = 0).
    R : float or ndarray
        Equivalent radius [m] (eq 24), finite and > 0.
    m : ContactMaterial

    Returns
    -------
    float or ndarray
        a [m].

    Raises
    ------
    ValueError
        If P is negative (the wheel has lost contact: a tension is no Hertz contact; rail.interaction
        reports contact loss before the contact is solved) or not finite, or R is not finite and > 0.
    """
    P = np.asarray(P, dtype=float)
    R = np.asarray(R, dtype=float)
    if not np.all(np.isfinite(P)) or np.any(P < 0):
        bad = np.ravel(P)[np.flatnonzero(~(np.isfinite(np.ravel(P)) & (np.ravel(P) >= 0)))[0]]
        raise ValueError(f"normal force P = {float(bad)!r} N is not allowed in the Hertz contact (eq 23): it must be a finite "
                         "number >= 0 (a negative force means the wheel has lost contact).")
    if not (np.all(np.isfinite(R)) and np.all(R > 0)):
        bad = np.ravel(R)[np.flatnonzero(~(np.isfinite(np.ravel(R)) & (np.ravel(R) > 0)))[0]]
        raise ValueError(f"equivalent radius R = {float(bad)!r} m is not allowed in the Hertz contact (eq 23): it must be a "
                         "finite number > 0.")
    return np.sqrt(4 * (1 - m.poisson_ratio**2) * np.maximum(P, 0) * R / (np.pi * m.half_width * m.youngs_modulus))


def hertz_pressure(xi, P, a, m: ContactMaterial):
    """Hertz pressure p = P / (pi a b) sqrt(1 - (xi/a)^2) inside the patch, 0 outside (eq 22).

    Parameters
    ----------
    xi : float or ndarray
        Position in the patch from its centre [m], leading edge at +a.
    P : float
        Normal force [N], finite and >= 0.
    a : float
        Half-length [m], finite and > 0.
    m : ContactMaterial
        Gives the half-width b [m].

    Returns
    -------
    ndarray
        p [Pa].

    Raises
    ------
    ValueError
        If P is negative or not finite, or a is not finite and > 0.
    """
    if not np.all(np.isfinite(P) & (np.asarray(P) >= 0)):
        raise ValueError(f"normal force P = {np.asarray(P).tolist()!r} N is not allowed in the Hertz pressure (eq 22): it must be "
                         "a finite number >= 0.")
    if not np.all(np.isfinite(a) & (np.asarray(a) > 0)):
        raise ValueError(f"half-length a = {np.asarray(a).tolist()!r} m is not allowed in the Hertz pressure (eq 22): it must be "
                         "a finite number > 0.")
    xi = np.asarray(xi, dtype=float)
    r = np.clip(1 - (xi / a) ** 2, 0, None)
    return P / (np.pi * a * m.half_width) * np.sqrt(r)


def carter(xi, P, m: ContactMaterial, speed: float, R: float):
    """Carter's steady 2D rolling solution (from eqs 26-30).

    1 - c/a = abs(gamma) / (pi k mu p0), Q = mu P (1 - (c/a)^2), the sign of q opposite to gamma.
    Saturation (no stick) when abs(gamma) >= 4 (1 - nu^2) mu_d p0 / E.

    Parameters
    ----------
    xi : float or ndarray
        Positions in the patch [m], leading edge at +a.
    P : float
        Normal force [N].
    m : ContactMaterial
    speed : float
        Rolling speed V [m/s].
    R : float
        Equivalent radius [m].

    Returns
    -------
    q : ndarray
        Tangential traction at xi [Pa].
    s : ndarray
        Slip velocity at xi [m/s] (0 in stick and outside the patch).
    Q : float
        Total tangential force 2b int q [N].
    c : float
        Stick half-length [m]; the stick zone is [a - 2c, a].
    """
    a = float(hertz_half_length(P, R, m))
    p0 = P / (np.pi * a * m.half_width)
    k = compliance(m)
    mu, g = m.friction_dynamic, m.creepage
    xi = np.asarray(xi, dtype=float)
    p = hertz_pressure(xi, P, a, m)
    sgn = -np.sign(g) if g != 0 else 0.0
    frac = abs(g) / (np.pi * k * mu * p0)
    c = a * max(1.0 - frac, 0.0)
    d = a - c  # centre of the stick zone
    inside_stick = np.abs(xi - d) < c
    q = sgn * mu * p.copy()
    if c > 0:
        q_stick = sgn * mu * p0 * (c / a) * np.sqrt(np.clip(1 - ((xi - d) / c) ** 2, 0, None))
    else:  # saturated: full slip, no stick zone
        q_stick = np.zeros_like(xi)
    q = q - np.where(inside_stick, q_stick, 0.0)
    # slip velocity s = V gamma - V du/dxi, du/dxi = -k PV int q / (xi - zeta)
    # full ellipse: PV int p0 sqrt(1 - z^2/a^2)/(xi - z) = pi p0 xi / a (|xi| < a)
    # stick ellipse outside its support: pi p0 (c/a) ((xi-d) - sign sqrt((xi-d)^2 - c^2)) / c
    t = xi - d
    outer = np.where(np.abs(t) > c, t - np.sign(t) * np.sqrt(np.clip(t * t - c * c, 0, None)), t)
    hilbert = np.pi * mu * p0 * (xi / a - (outer / a if c > 0 else 0.0))
    dudxi = -k * sgn * hilbert
    s = speed * g - speed * dudxi
    s = np.where(inside_stick | (np.abs(xi) >= a), 0.0, s)
    Q = sgn * mu * P * (1 - (c / a) ** 2)
    return q, s, Q, c


@njit(cache=True)
def _g0(t: float) -> float:
    """Antiderivative of ln|t|: t ln|t| - t (0 at t = 0)."""
    return t * math.log(abs(t)) - t if t != 0 else 0.0


@njit(cache=True)
def _g1(t: float) -> float:
    """Antiderivative of t ln|t|: t^2 ln|t| / 2 - t^2 / 4 (0 at t = 0)."""
    return t * t * (0.5 * math.log(abs(t)) - 0.25) if t != 0 else 0.0


@dataclass(frozen=True)
class TangentialSolution:
    """Result of one bay of unsteady rolling.

    Attributes
    ----------
    q, s : (steps, nodes) traction (Pa) and slip velocity (m/s) at the grid nodes
    xi : (nodes,) node positions in the patch, m
    a, P : (steps,) half-length (m) and normal force (N)
    Q : (steps,) total tangential force 2b int q, N
    work : (steps + nodes,) frictional work per unit area done on each rail particle, J/m^2;
              particle j is at node m = j - i at step i (x = x_wheel(i) + (j - i - M) Delta)
    power : (steps,) frictional power per unit area of the patch, summed over it, W/m (per unit width)
    delta : grid spacing = V dt, m
    stick_nodes : (steps,) number of stick nodes in the patch; 0 while loaded means full slip
              (saturated creepage or fast unloading: no stick zone, the traction is mu_d p)
    """

    q: np.ndarray
    s: np.ndarray
    xi: np.ndarray
    a: np.ndarray
    P: np.ndarray
    Q: np.ndarray
    work: np.ndarray
    power: np.ndarray
    delta: float
    iterations: int
    stick_nodes: np.ndarray


def checkerboard_measure(q, stick, p0, mu):
    """Largest second difference of the traction inside the stick zones, relative to mu p0.

    Only nodes at least three nodes from a zone boundary count. Used to stop the report's closure
    (eqs 32-33) when it diverges: in steady and slowly varying rolling the default closure keeps it
    <= 0.11 after the first transit, the report's closure reaches 0.29-0.83. Fast load variations
    (1600 Hz) legitimately reach 0.25 with the default closure, whose stability is shown by the
    perturbation test instead (docs/contact.md).

    Parameters
    ----------
    q : ndarray
        Traction at the nodes [Pa].
    stick : ndarray of bool
        Stick nodes.
    p0 : float
        Peak Hertz pressure [Pa].
    mu : float
        Friction coefficient [-].

    Returns
    -------
    float
        max abs(q_{n+1} - 2 q_n + q_{n-1}) / (mu p0) over the stick-zone cores [-].
    """
    core = stick.copy()
    core[1:] &= stick[:-1]
    core[:-1] &= stick[1:]
    inner = core[1:-1] & core[2:] & core[:-2]
    if not inner.any():
        return 0.0
    d2 = np.abs(q[2:] - 2 * q[1:-1] + q[:-2])
    return float(d2[inner].max() / (mu * p0))


CHECKERBOARD_LIMIT = 0.25


# A particle that reaches the leading edge within THETA_EDGE dt of the end of a step counts as
# entering in the next step (its pressure then is below sqrt(2 THETA_EDGE) p0 = 1.4e-5 p0), and one
# that leaves at the trailing edge within THETA_EDGE dt of the start of a step as gone with no work:
# otherwise the entry row (E_n - theta r_a) / (1 - theta) and the exit slip velocity
# (u_exit - u_old) / (phi dt) divide the rounding of a difference of nearly equal values by a
# vanishing time (a wear depth of 1e283 m was seen where the patch shrank as fast as the particles
# moved, |da/dx| = 1.2, under 45 mm corrugation).
THETA_EDGE = 1e-10
MIN_NODES = 11  # fewest grid nodes across the patch (the schema's bound on numerics.contact.nodes; tested equal)
CLOSURES = ("default", "report")
NORMAL_MODELS = ("report", "nonhertzian")


@dataclass(frozen=True)
class ContactNumerics:
    """How the contact is modelled, discretised and closed (config keys ``numerics.contact`` and
    ``contact.closure``, ``contact.closure_scale``, ``contact.normal``).

    Attributes
    ----------
    nodes : grid nodes across the largest patch [-], >= MIN_NODES
    closure : 'default' (well-posed log kernel) or 'report' (eqs 32-33)
    closure_scale : s, scale of the closure's rigid compliance [-], > 0
    normal : normal contact: 'report' (point spring on the roughness at the wheel centre, Hertz
                    patch with the local rail curvature, eqs 22-24) or 'nonhertzian' (the roughness
                    under the patch: the force through the contact filter J0(beta a), the exact
                    single-zone 2D pressure; rail.normal, docs/contact.md)
    """

    nodes: int
    closure: str
    closure_scale: float
    normal: str = "report"

    def __post_init__(self):
        if not isinstance(self.nodes, (int, np.integer)) or self.nodes < MIN_NODES:
            raise ValueError(f"numerics.contact.nodes = {self.nodes!r} is not allowed: it must be an integer >= {MIN_NODES}.")
        if self.closure not in CLOSURES:
            raise ValueError(f"contact.closure = {self.closure!r} is not allowed: it must be one of {list(CLOSURES)}.")
        if not (np.isfinite(self.closure_scale) and self.closure_scale > 0):
            raise ValueError(f"contact.closure_scale = {self.closure_scale!r} is not allowed: it must be > 0.")
        if self.normal not in NORMAL_MODELS:
            raise ValueError(f"contact.normal = {self.normal!r} is not allowed: it must be one of {list(NORMAL_MODELS)}.")


def rolling_grid(a_max: float, L: float, nodes: int):
    """Grid spacing Delta = L / N_x with N_x integer, at least ``nodes`` nodes across 2 a_max.

    Parameters
    ----------
    a_max : float
        Largest contact half-length [m].
    L : float
        Bay length [m]; the spacing divides it.
    nodes : int
        Grid nodes across 2 a_max [-], >= MIN_NODES.

    Returns
    -------
    delta : float
        Grid spacing [m].
    N_x : int
        Grid spacings per bay [-].
    M : int
        Index of the centre node; the grid has 2M + 1 nodes and (2M + 1) Delta > 2 a_max.
    """
    if nodes < MIN_NODES:
        raise ValueError(f"numerics.contact.nodes = {nodes} is not allowed: it must be >= {MIN_NODES}.")
    Nx = int(np.ceil(L * (nodes - 1) / (2 * a_max)))
    delta = L / Nx
    M = int(np.ceil(a_max / delta)) + 1
    return delta, Nx, M


@njit(cache=True)
def _log_hat_scalar(j):
    """int over the unit hat centred at j of ln|t| dt (t in units of the spacing)."""
    left = (_g1(j) - _g1(j - 1.0)) + (1.0 - j) * (_g0(j) - _g0(j - 1.0))
    right = (j + 1.0) * (_g0(j + 1.0) - _g0(j)) - (_g1(j + 1.0) - _g1(j))
    return left + right


# --- Square-root-weighted traction basis ---------------------------------------------------------------
# q(zeta) = W(zeta) sum_n g_n phi_n(zeta), W = sqrt(1 - zeta^2 / a^2), g_n = q_n / W(xi_n): the basis function
# of node n is psi_n = W phi_n / W(xi_n), with phi_n the hats except that the two outermost are constant 1 from
# the outermost loaded node to the edge. All integrals below are in units of the grid spacing (Delta = 1).

@functools.lru_cache(maxsize=1)
def _gauss_legendre_400():
    """The 400-point Gauss-Legendre rule on [-1, 1] (nodes, weights), computed once: its eigenvalue
    problem costs 0.03 s on one BLAS thread and up to 1.7 s CPU on two (measured on the 2-core host),
    and every process importing this module (the Snakemake process among them) needs it twice."""
    return np.polynomial.legendre.leggauss(400)


def _gauss_log_rule(nq: int):
    """Gauss rule for int_0^1 f(t) (-ln t) dt (nodes, weights), exact for polynomials of degree < 2 nq.
    Discretised Stieltjes procedure on t = u^8 (smooth integrand), then the Jacobi matrix."""
    x, wx = _gauss_legendre_400()
    u = 0.5 * (x + 1)
    t = u**8
    wt = 0.5 * wx * 64 * u**7 * (-np.log(u))
    alpha = np.zeros(nq)
    beta = np.zeros(nq)
    p_prev, p = np.zeros_like(t), np.ones_like(t)
    nrm = np.sum(wt)
    b0 = nrm
    for k in range(nq):
        alpha[k] = np.sum(wt * t * p * p) / nrm
        if k + 1 < nq:
            pn = (t - alpha[k]) * p - (beta[k] * p_prev if k > 0 else 0.0)
            nn = np.sum(wt * pn * pn)
            beta[k + 1] = nn / nrm
            p_prev, p, nrm = p, pn, nn
    J = np.diag(alpha) + np.diag(np.sqrt(beta[1:]), 1) + np.diag(np.sqrt(beta[1:]), -1)
    ev, V = np.linalg.eigh(J)
    return np.ascontiguousarray(ev), np.ascontiguousarray(b0 * V[0] ** 2)


def _gauss_legendre01(nq: int):
    x, w = np.polynomial.legendre.leggauss(nq)
    return np.ascontiguousarray(0.5 * (x + 1)), np.ascontiguousarray(0.5 * w)


_GL_X, _GL_W = _gauss_legendre01(10)  # singular points at least half an interval length away: errors < 1e-11
_GL8_X, _GL8_W = _gauss_legendre01(8)
_GL6_X, _GL6_W = _gauss_legendre01(6)
_GL4_X, _GL4_W = _gauss_legendre01(4)
_GL3_X, _GL3_W = _gauss_legendre01(3)
_GM_X, _GM_W = _gauss_legendre01(20)  # moments of the edge basis (exact to degree 39; the higher moments enter with factors < 0.56^k)
_GLOG_X, _GLOG_W = _gauss_log_rule(12)  # exact for degree < 24 (the Chebyshev moments of the hats)
_GLOG8_X, _GLOG8_W = _gauss_log_rule(8)
_EDGE_CELLS = 2  # D: basis functions within D cells of an edge are integrated with the square root explicitly
_N_MOM = 40  # terms of the far-field expansion of the edge columns (rows beyond 0.9 L of its centre)
_KMAX = 20  # Chebyshev terms of W / W_n on the support of an interior hat
_CHEB_TOL = 1e-10
_INV_K = np.r_[0.0, 1.0 / np.arange(1, _N_MOM)]


def _chebyshev_tables(kmax: int):
    """Chebyshev interpolation at K points (K = 1..kmax): nodes t_q and the matrix giving the coefficients."""
    nodes = np.zeros((kmax + 1, kmax))
    mat = np.zeros((kmax + 1, kmax, kmax))
    for K in range(1, kmax + 1):
        th = np.pi * (np.arange(K) + 0.5) / K
        nodes[K, :K] = np.cos(th)
        m = (2.0 / K) * np.cos(np.outer(np.arange(K), th))
        m[0] /= 2
        mat[K, :K, :K] = m
    return nodes, mat


_CHEB_NODES, _CHEB_MAT = _chebyshev_tables(_KMAX)
_N_POW = 48  # far-field terms of the row at +a for an interior column (ratio <= 1/2)


def _hat_chebyshev_powers(kmax: int, npow: int):
    """H[j, i] = int_{-1}^{1} hat(t) T_j(t) t^i dt (exact: 40-point Gauss-Legendre on each half)."""
    x, w = np.polynomial.legendre.leggauss(40)
    H = np.zeros((kmax, npow))
    for t, wt in ((0.5 * (x - 1), 0.5 * w), (0.5 * (x + 1), 0.5 * w)):
        T = np.cos(np.outer(np.arange(kmax), np.arccos(t))) * (1 - np.abs(t))[None, :]
        H += (T * wt[None, :]) @ (t[:, None] ** np.arange(npow)[None, :])
    return np.ascontiguousarray(H)


_HAT_CHEB_POW = _hat_chebyshev_powers(_KMAX, _N_POW)
_MOMENT_CACHE: dict = {}


def chebyshev_hat_moments(n_off: int):
    """Chebyshev moments of the hat functions against the log kernel of eq 29 (cached).

    Smooth cases by 40-point Gauss-Legendre on each half of the hat, the three rows where the log is
    singular at an end of a half by the Gauss rule with the log weight.

    Parameters
    ----------
    n_off : int
        Largest node offset [-].

    Returns
    -------
    M : ndarray, shape (_KMAX, 2 n_off + 1)
        M[j, x + n_off] = int_{-1}^{1} hat(t) T_j(t) ln abs(x - t) dt for integer x in [-n_off, n_off]
        [in units of the grid spacing].
    mu : ndarray, shape (_KMAX,)
        mu[j] = int hat T_j [in units of the grid spacing].
    """
    if n_off in _MOMENT_CACHE:
        return _MOMENT_CACHE[n_off]
    x, w = np.polynomial.legendre.leggauss(40)
    tl, tr = 0.5 * (x - 1), 0.5 * (x + 1)  # left half [-1, 0], right half [0, 1]
    wl = 0.5 * w
    J = _KMAX

    def hat_cheb(t):  # hat(t) T_j(t), j < J, at the points t (rows: j)
        t = np.asarray(t, dtype=float)
        return np.cos(np.outer(np.arange(J), np.arccos(np.clip(t, -1, 1)))) * (1 - np.abs(t))[None, :]

    Tl, Tr = hat_cheb(tl), hat_cheb(tr)
    xs = np.arange(-n_off, n_off + 1)
    Mom = np.empty((J, xs.size))
    for i, xv in enumerate(xs):
        if abs(xv) >= 2:
            Mom[:, i] = (Tl * np.log(np.abs(xv - tl))) @ wl + (Tr * np.log(np.abs(xv - tr))) @ wl
    # the log singular at an end of a half: int_0^1 f(u) ln u du = -sum w_L f(x_L), exact (degree < 24)
    u, wu = _GLOG_X, _GLOG_W
    Mom[:, n_off] = -(hat_cheb(-u) @ wu) - (hat_cheb(u) @ wu)  # x = 0
    Mom[:, n_off + 1] = (Tl * np.log(1 - tl)) @ wl - (hat_cheb(1 - u) @ wu)  # x = 1
    Mom[:, n_off - 1] = -(hat_cheb(u - 1) @ wu) + (Tr * np.log(1 + tr)) @ wl  # x = -1
    mu = Tl @ wl + Tr @ wl
    out = (np.ascontiguousarray(Mom), np.ascontiguousarray(mu))
    _MOMENT_CACHE[n_off] = out
    return out


@njit(cache=True)
def _fw(v, at):
    """2 v^2 S(v^2): the integrand factor of the square-root basis in v = sqrt(a - zeta) (units of the
    spacing), W = sqrt(s) S(s), S(s) = sqrt(2 at - s) / at, s = v^2; d zeta = 2 v dv."""
    s = v * v
    return 2.0 * s * math.sqrt(max(2.0 * at - s, 0.0)) / at


@njit(cache=True)
def _gl_seg(x1, x2, p, cplx, at, out):
    """out += int_{x1}^{x2} 2v^2 S (1, v^2) ln|v - p| dv (cplx: ln(v^2 + p^2)), 12-point Gauss-Legendre."""
    h = x2 - x1
    for q in range(_GL_X.size):
        v = x1 + h * _GL_X[q]
        f = _fw(v, at) * h * _GL_W[q]
        L = math.log(v * v + p * p) if cplx else math.log(abs(v - p))
        out[0] += f * L
        out[1] += f * L * v * v


@njit(cache=True)
def _glog_end(x0, h, at, out):
    """out += int F(v) ln|v - x0| over [x0, x0 + h] (h > 0) or [x0 + h, x0] (h < 0): log weight at x0."""
    ah = abs(h)
    lh = math.log(ah)
    for q in range(_GL_X.size):
        v = x0 + h * _GL_X[q]
        f = _fw(v, at) * ah * _GL_W[q] * lh
        out[0] += f
        out[1] += f * v * v
        v = x0 + h * _GLOG8_X[q]
        f = -_fw(v, at) * ah * _GLOG8_W[q]
        out[0] += f
        out[1] += f * v * v


@njit(cache=True)
def _graded(v1, v2, p, cplx, left, dist, at, out):
    """Gauss-Legendre on [v1, v2] graded (halving) toward the end nearest a singular point at distance dist."""
    h = v2 - v1
    if dist >= 0.5 * h:
        _gl_seg(v1, v2, p, cplx, at, out)
        return
    ell = h
    while ell > 2.0 * dist:
        hi = ell
        ell *= 0.5
        if left:
            _gl_seg(v1 + ell, v1 + hi, p, cplx, at, out)
        else:
            _gl_seg(v2 - hi, v2 - ell, p, cplx, at, out)
    if left:
        _gl_seg(v1, v1 + ell, p, cplx, at, out)
    else:
        _gl_seg(v2 - ell, v2, p, cplx, at, out)


@njit(cache=True)
def _log_term(v1, v2, p, at, out):
    """out += int_{v1}^{v2} 2v^2 S (1, v^2) ln|v - p| dv for real p (singular at p)."""
    if p == v1:
        _glog_end(v1, v2 - v1, at, out)
    elif p == v2:
        _glog_end(v2, v1 - v2, at, out)
    elif v1 < p < v2:
        _glog_end(p, v1 - p, at, out)
        _glog_end(p, v2 - p, at, out)
    elif p < v1:
        _graded(v1, v2, p, False, True, v1 - p, at, out)
    else:
        _graded(v1, v2, p, False, False, p - v2, at, out)


@njit(cache=True)
def _piece_log(v1, v2, d, at, out):
    """out[0], out[1] = int_{v1}^{v2} 2v^2 S(v^2) (1, v^2) ln|v^2 - d| dv, 0 <= v1 < v2: the log-kernel
    integral over s = v^2 in [v1^2, v2^2] of sqrt(s) S(s) (1, s) against a row at s = d (s = a - zeta)."""
    out[0] = 0.0
    out[1] = 0.0
    h = v2 - v1
    if d > 0:
        c = math.sqrt(d)
        if min(abs(c - v1), abs(c - v2)) >= h and (v1 > c or v2 < c):  # both roots far: one rule for both
            if v1 + c >= h:
                for q in range(_GL_X.size):
                    v = v1 + h * _GL_X[q]
                    f = _fw(v, at) * h * _GL_W[q] * math.log(abs(v * v - d))
                    out[0] += f
                    out[1] += f * v * v
                return
        _log_term(v1, v2, c, at, out)
        _log_term(v1, v2, -c, at, out)
    elif d == 0:
        _log_term(v1, v2, 0.0, at, out)
        out[0] *= 2.0
        out[1] *= 2.0
    else:
        b = math.sqrt(-d)
        _graded(v1, v2, b, True, True, math.sqrt(v1 * v1 + b * b), at, out)


@njit(cache=True)
def _log_term_pre(v1, v2, p, at, pv, pf, ps, lf, ls, rf, rs, out):
    """_log_term with the integrand factor precomputed at the Gauss-Legendre points pv (weights included:
    pf, pf * ps) and at the log-weighted points from the left (lf, ls) and right (rf, rs) ends."""
    h = v2 - v1
    if p == v1 or p == v2:
        lh = math.log(h)
        for q in range(pv.size):
            out[0] += lh * pf[q]
            out[1] += lh * pf[q] * ps[q]
        if p == v1:
            for q in range(lf.size):
                out[0] -= lf[q]
                out[1] -= lf[q] * ls[q]
        else:
            for q in range(rf.size):
                out[0] -= rf[q]
                out[1] -= rf[q] * rs[q]
    elif (p < v1 and v1 - p >= 0.5 * h) or (p > v2 and p - v2 >= 0.5 * h):
        for q in range(pv.size):
            f = pf[q] * math.log(abs(pv[q] - p))
            out[0] += f
            out[1] += f * ps[q]
    else:
        _log_term(v1, v2, p, at, out)


@njit(cache=True)
def _piece_log_pre(v1, v2, d, at, pv, pf, ps, lf, ls, rf, rs, out):
    """_piece_log with precomputed integrand factors (see _log_term_pre)."""
    out[0] = 0.0
    out[1] = 0.0
    h = v2 - v1
    if d > 0:
        c = math.sqrt(d)
        if (v1 - c >= 0.5 * h or c - v2 >= 0.5 * h) and v1 + c >= 0.5 * h:  # both roots far: one rule for both
            for q in range(pv.size):
                f = pf[q] * math.log(abs(ps[q] - d))
                out[0] += f
                out[1] += f * ps[q]
            return
        _log_term_pre(v1, v2, c, at, pv, pf, ps, lf, ls, rf, rs, out)
        _log_term_pre(v1, v2, -c, at, pv, pf, ps, lf, ls, rf, rs, out)
    elif d == 0:
        _log_term_pre(v1, v2, 0.0, at, pv, pf, ps, lf, ls, rf, rs, out)
        out[0] *= 2.0
        out[1] *= 2.0
    else:
        b2 = -d
        if v1 * v1 + b2 >= 0.25 * h * h:
            for q in range(pv.size):
                f = pf[q] * math.log(ps[q] + b2)
                out[0] += f
                out[1] += f * ps[q]
        else:
            _graded(v1, v2, math.sqrt(b2), True, True, math.sqrt(v1 * v1 + b2), at, out)


@njit(cache=True)
def _edge_columns(at, e, D, js, res, mom, wts, w1, w3):
    """The D basis functions nearest the leading edge (column i: node lead - i, i < D) against rows at
    s = a - x = e + js[r] (units of the spacing): res[i, r] = int psi_i(s) ln|s - d_r| ds. Also their
    far-field moments mom[i, k] = int psi_i (s - s_c)^k ds about s_c = (e + D) / 2, and wts[i] = int psi_i.
    The trailing edge is the mirror image. Pieces: s in [0, e], where g = q / W is extrapolated linearly
    from the last two nodes (psi_lead = W (1 + t) / W_lead, psi_lead-1 = -W t / W_lead-1, t = (zeta - xi_lead)
    / Delta; a partition of unity, exact for g linear), then whole cells (hats).
    w1, w3: work arrays (_basis_workspace)."""
    npc = D + 1
    sb = w1[0]
    vb = w1[1]
    wc = w1[2]
    out = w1[3]
    ser = w1[4]
    sb[0] = 0.0
    vb[0] = 0.0
    for i in range(1, npc + 1):
        sb[i] = e + (i - 1)
        vb[i] = math.sqrt(sb[i])
    for i in range(D):
        sc = sb[i + 1]
        wc[i] = math.sqrt(sc) * math.sqrt(2.0 * at - sc) / at
    L = sb[npc]
    s_c = 0.5 * L
    # moments (Gauss-Legendre in v: polynomial times the smooth S)
    mom[:, :] = 0.0
    for p in range(npc):
        h = vb[p + 1] - vb[p]
        for q in range(_GM_X.size):
            v = vb[p] + h * _GM_X[q]
            s = v * v
            f = _fw(v, at) * h * _GM_W[q]
            y = s - s_c
            if p == 0 and D == 1:  # (a patch of less than two cells: g constant beyond the last node)
                g0 = f / wc[0]
                m0 = mom[0]
                yk = 1.0
                for k in range(m0.size):
                    m0[k] += g0 * yk
                    yk *= y
                continue
            if p == 0:  # beyond the last node g is extrapolated linearly: phi_lead = 1 + t, phi_lead-1 = -t
                g0 = f * (sb[2] - s) / wc[0]
                g1 = f * (s - sb[1]) / wc[1]
                m0 = mom[0]
                m1 = mom[1]
                yk = 1.0
                for k in range(m0.size):
                    m0[k] += g0 * yk
                    m1[k] += g1 * yk
                    yk *= y
                continue
            g0 = f * (sb[p + 1] - s) / wc[p - 1]
            m0 = mom[p - 1]
            if p < D:
                g1 = f * (s - sb[p]) / wc[p]
                m1 = mom[p]
                yk = 1.0
                for k in range(m0.size):
                    m0[k] += g0 * yk
                    m1[k] += g1 * yk
                    yk *= y
            else:
                yk = 1.0
                for k in range(m0.size):
                    m0[k] += g0 * yk
                    yk *= y
    for i in range(D):
        wts[i] = mom[i, 0]
    nm = mom.shape[1]
    ng, nl = _GL_X.size, _GLOG8_X.size
    pv, pf, ps, lf, ls, rf, rs = w3[0], w3[1], w3[2], w3[3], w3[4], w3[5], w3[6]
    for p in range(npc):
        h = vb[p + 1] - vb[p]
        for q in range(ng):
            v = vb[p] + h * _GL_X[q]
            pv[p, q] = v
            ps[p, q] = v * v
            pf[p, q] = _fw(v, at) * h * _GL_W[q]
        for q in range(nl):
            v = vb[p] + h * _GLOG8_X[q]
            ls[p, q] = v * v
            lf[p, q] = _fw(v, at) * h * _GLOG8_W[q]
            v = vb[p + 1] - h * _GLOG8_X[q]
            rs[p, q] = v * v
            rf[p, q] = _fw(v, at) * h * _GLOG8_W[q]
    for r in range(js.size):
        d = e + js[r]
        dc = s_c - d
        if abs(dc) >= 0.9 * L:  # far field: ln|s - d| = ln|dc| + ln(1 + (s - s_c) / dc)
            ser[0] = math.log(abs(dc))
            my = -1.0 / dc
            # terms while (s_c / |dc|)^k / k > 1e-14 (|s - s_c| <= s_c)
            nk = min(nm, int(math.ceil(-32.2 / math.log(s_c / abs(dc)))) + 1)
            yk = -1.0
            for k in range(1, nk):
                yk *= my
                ser[k] = yk * _INV_K[k]  # (-1)^(k+1) / (k dc^k)
            for i in range(D):
                acc = 0.0
                for k in range(nk):
                    acc += mom[i, k] * ser[k]
                res[i, r] = acc
            continue
        for i in range(D):
            res[i, r] = 0.0
        for p in range(npc):
            _piece_log_pre(vb[p], vb[p + 1], d, at, pv[p, :ng], pf[p, :ng], ps[p, :ng], lf[p, :nl], ls[p, :nl],
                           rf[p, :nl], rs[p, :nl], out)
            if p == 0 and D == 1:
                res[0, r] += out[0] / wc[0]
            elif p == 0:
                res[0, r] += (sb[2] * out[0] - out[1]) / wc[0]
                res[1, r] += (out[1] - sb[1] * out[0]) / wc[1]
            else:
                res[p - 1, r] += (sb[p + 1] * out[0] - out[1]) / wc[p - 1]
                if p < D:
                    res[p, r] += (out[1] - sb[p] * out[0]) / wc[p]


def _basis_workspace(nn: int):
    """Work arrays of _basis_matrix for a grid of nn nodes (allocated once per solve)."""
    nr = nn + 1
    return (np.empty((nn, _KMAX)), np.empty(nr + 1), np.empty((_EDGE_CELLS, nr + 1)), np.empty((_EDGE_CELLS, _N_MOM)),
            np.empty(_EDGE_CELLS), np.empty((5, max(_N_MOM, _EDGE_CELLS + 2))),
            np.empty((7, _EDGE_CELLS + 1, max(_GL_X.size, _GLOG8_X.size))))


@njit(cache=True)
def _basis_matrix(ai, delta, M, Mom, mu, A, r_a, w, ws):
    """The influence of the square-root-weighted basis at half-length ai, in units of the spacing
    (in place): A[n, r] = int psi_n(zeta) ln|x_r - zeta| d zeta (column n, row r: the nodes and the leading
    neighbour), r_a[n] = the same at the row x = +a, w[n] = int psi_n. Columns of unloaded nodes: plain
    hats. ws: work arrays (_basis_workspace). Returns (lead, trail)."""
    cf, js, res, mom, wts, wk1, wk3 = ws
    nn = A.shape[0]
    nr = A.shape[1]
    off = (Mom.shape[1] - 1) // 2
    at = ai / delta
    lead = int(math.floor(at - 1e-12)) + M
    trail = 2 * M - lead
    e = at - (lead - M)
    D = min(_EDGE_CELLS, lead - M)
    if D < 1:
        raise ValueError("the patch must span more than two grid cells")
    # unloaded nodes: plain hats
    for n in range(nn):
        if n > lead or n < trail:
            for r in range(nr):
                A[n, r] = Mom[0, r - n + off]
            w[n] = mu[0]
            r_a[n] = _log_hat_scalar(n - M - at)
    # interior columns: Chebyshev series of W / W_n on the hat's support, Toeplitz moments
    for n in range(trail + D, lead - D + 1):
        xn = float(n - M)
        wn = math.sqrt(1.0 - (xn / at) ** 2)
        dist = at - abs(xn)
        rho = dist + math.sqrt(dist * dist - 1.0)
        K = int(math.ceil(-math.log(_CHEB_TOL) / math.log(rho)))
        K = min(max(K, 3), _KMAX)
        cfn = cf[n]
        for j in range(_KMAX):
            cfn[j] = 0.0
        for qq in range(K):
            z = (xn + _CHEB_NODES[K, qq]) / at
            f = math.sqrt(1.0 - z * z) / wn
            for j in range(K):
                cfn[j] += _CHEB_MAT[K, j, qq] * f
        ww = 0.0
        arow = A[n]
        base = off - n
        c = cfn[0]
        mrow = Mom[0, base:base + nr]
        for r in range(nr):
            arow[r] = c * mrow[r]
        for j in range(K):
            ww += cfn[j] * mu[j]
        for j in range(1, K):
            c = cfn[j]
            mrow = Mom[j, base:base + nr]
            for r in range(nr):
                arow[r] += c * mrow[r]
        w[n] = ww
        r_a[n] = 0.0
    # row at +a for the interior columns, x = a - xi_n >= 2 cells from the hat's centre: the far field
    # ln|x - t| = ln x - sum_i (t / x)^i / i of the same truncated Chebyshev series as the columns
    # (exact moments), so that the row of a particle entering just past a node,
    # (E_n - theta r_a) / (1 - theta), cancels to rounding
    for n in range(trail + D, lead - D + 1):
        x = at - float(n - M)
        cfn = cf[n]
        ni = min(_N_POW, int(math.ceil(32.3 / math.log(x))) + 1)  # (1/x)^i / i < 1e-14
        lx = math.log(x)
        acc = 0.0
        for j in range(_KMAX):
            acc += cfn[j] * _HAT_CHEB_POW[j, 0]
        acc *= lx
        ix = 1.0 / x
        pw = 1.0
        for i in range(1, ni):
            pw *= ix
            nu = 0.0
            for j in range(_KMAX):
                nu += cfn[j] * _HAT_CHEB_POW[j, i]
            acc -= nu * pw / i
        r_a[n] = acc
    # edge columns: lead - i (rows at s = a - x = e + (lead - r)) and trail + i (s = a + x = e + (r - trail))
    for side in range(2):
        for r in range(nr):
            js[r] = float(lead - r) if side == 0 else float(r - trail)
        js[nr] = -e if side == 0 else 2.0 * at - e  # the row at +a
        _edge_columns(at, e, D, js, res[:D], mom[:D], wts[:D], wk1, wk3)
        for i in range(D):
            n = lead - i if side == 0 else trail + i
            for r in range(nr):
                A[n, r] = res[i, r]
            r_a[n] = res[i, nr]
            w[n] = wts[i]
    return lead, trail


@njit(cache=True)
def _closure_matrix(ai, Mom, mu, xi, k, delta, M, closure, closure_scale, report_coef, C, r_edge, w, r_trail, AT,
                    r_a, wu, ws):
    """Influence matrix C of the square-root-weighted basis (rows: nodes plus the leading neighbour), its
    rows r_edge at xi = +a and r_trail at xi = -a and the column weights w = int psi_n, at half-length ai
    (in place; AT, r_a, wu, ws: work arrays of _basis_matrix). The rigid term is that of the closure (0: default,
    1: report)."""
    nn = xi.size
    lead, trail = _basis_matrix(ai, delta, M, Mom, mu, AT, r_a, wu, ws)
    logd = math.log(delta)
    for c in range(nn):
        w[c] = delta * wu[c]
    rigid = np.empty(nn)
    if closure == 0:
        lc = k * math.log(0.5 * ai * math.exp(2 * closure_scale / math.pi))
        for c in range(nn):
            rigid[c] = lc * w[c]
    else:
        for c in range(nn):
            rigid[c] = k * delta * AT[c, M] + k * logd * w[c]  # minus the row at xi = 0
        rigid[M] += closure_scale * report_coef * ai
    for c in range(nn):
        col = -k * logd * w[c] + rigid[c]
        for r in range(nn + 1):
            C[r, c] = -k * delta * AT[c, r] + col
    for n in range(nn):
        r_edge[n] = -k * delta * r_a[n] - k * logd * w[n] + rigid[n]
    for n in range(nn):  # the grid, the basis and the rigid term are symmetric about xi = 0
        r_trail[n] = r_edge[nn - 1 - n]
    return lead, trail


@njit(cache=True)
def _ellipse_area(eta):
    """F(eta) = int_0^eta sqrt(1 - t^2) dt with eta clipped to [-1, 1] (0 outside the patch)."""
    e = min(max(eta, -1.0), 1.0)
    return 0.5 * (e * math.sqrt(max(1.0 - e * e, 0.0)) + math.asin(e))


@njit(cache=True)
def _step_work(n, xi, delta, a_prev, ai, p0m, dt, mu_d, qn, q, p, p_prev, s, s_exit, inside, inside_prev, fm):
    """Frictional work per unit area in one step on the particle now at node n (at xi_{n+1} one step
    before), J/m^2: |s_bar int q dt| with s_bar its mean slip velocity over the time it was loaded.

    The traction is written q = sigma mu_d p + d, with sigma its direction. The pressure part is
    integrated exactly along the path for the Hertz ellipse, with eta = xi / a(t) linear in time
    between the two steps (clipped at the patch edges, where the particle enters or leaves), so the
    square-root edges of p carry no grid-position error; the deviation d (0 in slip) by the
    trapezoidal rule over the loaded time. s_exit : the mean slip velocity of a particle that left the
    patch during the step, over its loaded time. fm : the mean of the pressure's shape factor (non-Hertzian
    pressure = Hertz ellipse x shape, rail.normal) at the particle's two positions; 1 for Hertz."""
    nn = xi.size
    was = n < nn - 1 and inside_prev[n + 1]
    if not (inside[n] or was):
        return 0.0
    q_old = q[n + 1] if was else 0.0
    if inside[n]:
        sbar = s[n]
        ref = qn[n] if qn[n] != 0.0 else q_old
    else:
        sbar = s_exit[n]
        ref = q_old
    if sbar == 0.0 or ref == 0.0:  # stuck over the step (zero mean slip) or unloaded
        return 0.0
    eta0 = (xi[n] + delta) / a_prev
    eta1 = xi[n] / ai
    span = eta0 - eta1
    ip = fm * p0m * dt * (_ellipse_area(eta0) - _ellipse_area(eta1)) / span
    loaded = dt * (min(eta0, 1.0) - max(eta1, -1.0)) / span
    if loaded < 0.0:
        loaded = 0.0
    sig = 1.0 if ref > 0 else -1.0
    d_new = qn[n] - sig * mu_d * p[n] if inside[n] else 0.0
    d_old = q_old - sig * mu_d * p_prev[n + 1] if was else 0.0
    return abs(sbar * (sig * mu_d * ip + 0.5 * (d_old + d_new) * loaded))


@njit(cache=True)
def _march(P, a, shape, xi, Mom, mu, ws, k, delta, M, speed, g, mu_d, mu_s, half_width, closure, closure_scale,
           report_coef, q0, max_iter, checkerboard_limit):
    """The time loop of solve_tangential (compiled). Returns the histories and a status
    (code, step, value): 0 ok, 1 no convergence of the stick/slip iteration, 2 not finite,
    3 the report's closure diverged (value: the checkerboard measure)."""
    nn = xi.size
    steps = P.size
    dt = delta / speed
    b2 = 2 * half_width
    sg = 0.0 if g == 0 else (1.0 if g > 0 else -1.0)
    q_hist = np.zeros((steps, nn))
    s_hist = np.zeros((steps, nn))
    Q_hist = np.zeros(steps)
    work = np.zeros(steps + nn)
    power = np.zeros(steps)
    stick_count = np.zeros(steps, dtype=np.int64)
    status = np.zeros(3)
    C = np.empty((nn + 1, nn))
    r_edge = np.empty(nn)
    r_trail = np.empty(nn)
    w = np.empty(nn)
    AT = np.empty((nn, nn + 1))
    r_a = np.empty(nn)
    wu = np.empty(nn)
    q = q0.copy()
    _closure_matrix(a[0], Mom, mu, xi, k, delta, M, closure, closure_scale, report_coef, C, r_edge, w, r_trail,
                    AT, r_a, wu, ws)
    a_built = a[0]
    u_old = C @ q
    u_edge_old = np.dot(r_edge, q)
    saved = np.empty((nn, nn))  # rows of C replaced by the entry condition during a step
    u_trail_old = np.dot(r_trail, q)
    stick_prev = np.zeros(nn, dtype=np.bool_)
    sign_prev = np.full(nn, -sg)
    stick = np.zeros(nn, dtype=np.bool_)
    inside = np.zeros(nn, dtype=np.bool_)
    sign = np.empty(nn)
    p = np.empty(nn)
    h = np.empty(nn)
    s = np.empty(nn)
    qn = np.zeros(nn)
    dw = np.empty(nn)
    total_iter = 0
    theta = np.zeros(nn)
    enter = np.zeros(nn, dtype=np.bool_)
    s_exit = np.zeros(nn)
    a_prev = a[0]
    p0_prev = P[0] / (math.pi * a[0] * half_width)
    p_prev = np.zeros(nn)
    inside_prev = np.zeros(nn, dtype=np.bool_)
    for n in range(nn):
        rr = 1 - (xi[n] / a[0]) ** 2
        p_prev[n] = p0_prev * math.sqrt(rr if rr > 0 else 0.0) * shape[0, n]
        inside_prev[n] = p_prev[n] > 0
    for i in range(steps):
        ai = a[i]
        if ai != a_built:  # the basis depends on a(t) only
            _closure_matrix(ai, Mom, mu, xi, k, delta, M, closure, closure_scale, report_coef, C, r_edge, w,
                            r_trail, AT, r_a, wu, ws)
            a_built = ai
        E = C[:nn]
        p0 = P[i] / (math.pi * ai * half_width)
        for n in range(nn):
            rr = 1 - (xi[n] / ai) ** 2
            p[n] = p0 * math.sqrt(rr if rr > 0 else 0.0) * shape[i, n]
            inside[n] = p[n] > 0
        for n in range(nn - 1):
            stick[n] = stick_prev[n + 1]
            sign[n] = sign_prev[n + 1]
        stick[nn - 1] = False
        sign[nn - 1] = -sg
        # Regular particle: u_n(t) = u_{n+1}(t - dt) - gamma Delta (exact along its path). A particle
        # that was at or beyond the leading edge a(t - dt) entered at t_e = t - (1 - theta) dt, where
        # its path meets the edge (eta = xi / a linear in time); it has stuck since, from the edge
        # displacement at t_e, interpolated between the steps: u_n(t) = u_a(t_e) - gamma (1 - theta) Delta,
        # u_a(t_e) = theta u_a(t) + (1 - theta) u_a(t - dt). Divided by 1 - theta, its row
        # (E_n - theta r_a) / (1 - theta) q = u_a(t - dt) - gamma Delta tends to the slip-free condition at
        # the edge as the particle nears it (theta -> 1); with the square-root basis the displacement
        # gradient there is finite. (An extrapolation of u_a from the two previous steps leaves a neutral
        # mode when the edge is just past a node.)
        nent = 0
        for n in range(nn):
            h[n] = u_old[n + 1] - g * delta
            enter[n] = False
            if inside[n] and xi[n] + delta >= a_prev:
                eta0, eta1 = (xi[n] + delta) / a_prev, xi[n] / ai
                th = (eta0 - 1.0) / (eta0 - eta1)
                th = min(max(th, 0.0), 1.0)
                if 1.0 - th < THETA_EDGE:
                    # reaches the edge within THETA_EDGE dt of the end of the step: not yet loaded
                    # (pressure below 2e-5 p0; the row below would divide rounding by 1 - theta)
                    inside[n] = False
                    p[n] = 0.0
                    continue
                enter[n] = True
                theta[n] = th
                inv = 1.0 / max(1.0 - th, 1e-300)
                for c in range(nn):
                    saved[nent, c] = C[n, c]
                    C[n, c] = (C[n, c] - th * r_edge[c]) * inv
                nent += 1
                h[n] = u_edge_old - g * delta
                stick[n] = True
                if sign[n] == 0:
                    sign[n] = -sg
        for n in range(nn):
            stick[n] = stick[n] and inside[n]
        converged = False
        it = 0
        while it < max_iter:
            ns = 0
            for n in range(nn):
                if inside[n] and not stick[n]:
                    qn[n] = mu_d * p[n] * sign[n]
                else:
                    qn[n] = 0.0
                if stick[n]:
                    ns += 1
            if ns > 0:
                S = np.empty(ns, dtype=np.int64)
                c = 0
                for n in range(nn):
                    if stick[n]:
                        S[c] = n
                        c += 1
                A = np.empty((ns, ns))
                rhs = np.empty(ns)
                for r in range(ns):
                    acc = h[S[r]]
                    for n in range(nn):
                        if qn[n] != 0.0:  # the slip nodes (qn is 0 on the stick nodes here)
                            acc -= E[S[r], n] * qn[n]
                    rhs[r] = acc
                    for cc in range(ns):
                        A[r, cc] = E[S[r], S[cc]]
                x = np.linalg.solve(A, rhs)
                for r in range(ns):
                    qn[S[r]] = x[r]
            Eq = E @ qn
            for n in range(nn):  # (for an entering particle: its mean slip velocity since it entered)
                s[n] = g * speed + (Eq[n] - h[n] - g * delta) / dt
            changed = False
            for n in range(nn):
                if not inside[n]:
                    s[n] = 0.0
                    continue
                if stick[n]:
                    if abs(qn[n]) > mu_s * p[n]:
                        stick[n] = False
                        sign[n] = np.sign(qn[n])
                        changed = True
                elif s[n] * sign[n] > 0:  # q = -mu p sign(s) violated: the particle sticks
                    stick[n] = True
                    changed = True
            it += 1
            if not changed:
                converged = True
                break
        j = 0
        for n in range(nn):  # restore the rows of the entering particles
            if enter[n]:
                for c in range(nn):
                    C[n, c] = saved[j, c]
                j += 1
        if not converged:
            status[0], status[1] = 1, i
            break
        total_iter += it
        finite = True
        for n in range(nn):
            if not np.isfinite(qn[n]):
                finite = False
        if not finite:
            status[0], status[1] = 2, i
            break
        cnt = 0
        for n in range(nn):
            if stick[n]:
                s[n] = 0.0
                if inside[n]:
                    cnt += 1
        stick_count[i] = cnt
        if closure == 1 and i > nn and P[i] > 0:
            cb = _checkerboard_nb(qn, stick, inside, p0, mu_d)
            if cb > checkerboard_limit:
                status[0], status[1], status[2] = 3, i, cb
                break
        q_hist[i] = qn
        s_hist[i] = s
        Q_hist[i] = b2 * np.dot(w, qn)
        # Frictional work in this step on the particle now at node n (particle index i + n): its
        # step-averaged traction times its slip over the step. The particle that entered at +a during
        # the step was loaded for tau only; the one at the trailing node leaves at -a after tau_exit.
        # Particles that left the patch at -a during the step, after phi dt (eta = xi / a linear in
        # time): their mean slip velocity from the displacement at -a at that time, interpolated
        # between the steps (the mirror image of the entry).
        u_trail_new = np.dot(r_trail, qn)
        u_new = C @ qn
        for n in range(nn - 1):
            s_exit[n] = 0.0
            if inside_prev[n + 1] and not inside[n]:
                eta0, eta1 = xi[n + 1] / a_prev, xi[n] / ai
                if 1.0 - eta1 * eta1 > 0.0:  # the ellipse is loaded here but the pressure is 0: a gap
                    # left a contact zone inside the patch into a gap (several zones, rail.normal.multizone_contact):
                    # its mean slip velocity over the step along its path (first order in the step: where in
                    # the step it left is not resolved)
                    s_exit[n] = g * speed + (u_new[n] - u_old[n + 1]) / dt
                    continue
                phi = min(max((eta0 + 1.0) / (eta0 - eta1), 0.0), 1.0)
                if phi < THETA_EDGE:  # left at the start of the step: no loaded time, no work
                    continue
                u_exit = (1.0 - phi) * u_trail_old + phi * u_trail_new
                s_exit[n] = g * speed + (u_exit - u_old[n + 1]) / (phi * dt)
        p0m = 0.5 * (p0_prev + p0)
        ip = i - 1 if i > 0 else 0
        for n in range(nn):
            fm = 0.5 * (shape[ip, n + 1] + shape[i, n]) if n < nn - 1 else shape[i, n]
            dw[n] = _step_work(n, xi, delta, a_prev, ai, p0m, dt, mu_d, qn, q, p, p_prev, s, s_exit, inside, inside_prev, fm)
        tot = 0.0
        for n in range(nn):
            work[i + n] += dw[n]
            tot += dw[n]
        power[i] = tot * delta / dt
        q[:] = qn
        u_trail_old = u_trail_new
        a_prev = ai
        p0_prev = p0
        p_prev[:] = p
        inside_prev[:] = inside
        u_edge_old = np.dot(r_edge, qn)
        u_old = u_new
        for n in range(nn):
            stick_prev[n] = stick[n]
            sign_prev[n] = np.sign(qn[n]) if stick[n] else sign[n]
    return q_hist, s_hist, Q_hist, work, power, stick_count, total_iter, status


@njit(cache=True)
def _checkerboard_nb(q, stick, inside, p0, mu):
    """Compiled checkerboard_measure of q on the loaded stick nodes (stick & inside)."""
    nn = q.size
    best = 0.0
    for n in range(1, nn - 1):
        ok = True
        for m in range(max(n - 2, 0), min(n + 3, nn)):  # n-1, n, n+1 and their neighbours all stick
            if not (stick[m] and inside[m]):
                ok = False
        if ok:
            d2 = abs(q[n + 1] - 2 * q[n] + q[n - 1])
            if d2 > best:
                best = d2
    return best / (mu * p0)


def solve_tangential(P, a, m: ContactMaterial, speed: float, delta: float, M: int, closure: str = "default",
                     closure_scale: float = 1.0, q0=None, max_iter: int = 200, shape=None) -> TangentialSolution:
    """Time-step the unsteady 2D rolling contact over len(P) steps of Delta = V dt (eqs 26-33).

    Parameters
    ----------
    P, a : ndarray
        Normal force [N] and half-length [m] at each step; the patch is [-a, a] on the fixed grid
        xi_n = (n - M) Delta, n = 0..2M.
    m : ContactMaterial
    speed : float
        Rolling speed V [m/s].
    delta : float
        Grid spacing Delta = V dt [m].
    M : int
        Index of the centre node [-]; M Delta must exceed every a.
    closure : str
        'default' (log kernel with l = (a/2) exp(2 s / pi), s = closure_scale) or 'report'
        (eqs 32-33, u(0) = q(0)/sigma with 1/sigma scaled by closure_scale).
    closure_scale : float
        s [-].
    q0 : ndarray, optional
        Initial traction at the nodes [Pa] (default 0).
    max_iter : int
        Largest number of active-set iterations per step.
    shape : ndarray, shape (len(P), 2M + 1), optional
        Non-Hertzian pressure: p = P / (pi a b) sqrt(1 - xi^2/a^2) shape at the nodes (rail.normal
        .patch_contact: smooth and > 0 in the patch; .multizone_contact: 0 in the gaps between contact
        zones, where a particle carries no traction and does no work) [-]; default 1 (the Hertz ellipse, eq 22).

    Returns
    -------
    TangentialSolution

    Raises
    ------
    ContactError
        When the stick/slip iteration does not converge, the traction is not finite, or the
        report's closure diverges (checkerboard_measure above CHECKERBOARD_LIMIT).

    Notes
    -----
    Each step (eqs 26-33, module docstring): the stick equations E q = h hold on the stick nodes,
    where a regular particle keeps u_m(t) = u_{m+1}(t - dt) - gamma Delta and the particle that
    entered in the last step has stuck since it crossed xi = a at t_e, with the surface displacement
    u_a(t_e) interpolated between the steps: u_lead(t) = u_a(t_e) - gamma (1 - theta) Delta. Slip nodes carry q = -mu_d p sign(s),
    with the slip direction carried by the particles. An active-set iteration moves nodes where
    abs(q) > mu_s p to slip and nodes whose slip opposes their traction to stick. The slip velocity is
    s = V gamma + (E q - h) / dt, exact along the particle path.

    The time loop is compiled with numba (``_march``); ``tests/reference/contact_numpy.py`` holds
    the same scheme in numpy, and the tests check the two agree step by step.
    """
    if closure not in CLOSURES:
        raise ValueError(f"contact.closure = {closure!r} is not allowed: it must be one of {list(CLOSURES)}.")
    if not (np.isfinite(speed) and speed > 0 and np.isfinite(delta) and delta > 0):
        raise ValueError(f"speed = {speed!r} m/s and delta = {delta!r} m are not allowed: both must be finite numbers > 0.")
    P = np.ascontiguousarray(P, dtype=float)
    a = np.ascontiguousarray(a, dtype=float)
    if P.shape != a.shape or P.ndim != 1:
        raise ValueError(f"P and a must be 1-d arrays of one length (one value per step); got shapes {P.shape} and {a.shape}.")
    if not (np.all(np.isfinite(P)) and np.all(np.isfinite(a))):
        raise ValueError("P and a must be finite at every step.")
    if np.any(a >= M * delta):
        raise ValueError(f"the patch half-length {a.max():.4g} m exceeds the grid's {M * delta:.4g} m.")
    if P.size and not (np.all(a > 0) and np.all(P > 0)):
        raise ValueError("solve_tangential needs a loaded patch at every step (P > 0, a > 0); contact loss is "
                         "detected before (rail.interaction).")
    nn = 2 * M + 1
    if shape is None:
        shape = np.ones((P.size, nn))
    shape = np.ascontiguousarray(shape, dtype=float)
    if shape.shape != (P.size, nn) or not np.all(np.isfinite(shape)):
        raise ValueError(f"shape must be finite with one row of {nn} nodes per step; got shape {shape.shape}.")
    xi = (np.arange(nn) - M) * delta
    k = compliance(m)
    Mom, mu = chebyshev_hat_moments(nn)  # Toeplitz Chebyshev moments of the hats (cached)
    q_init = np.zeros(nn) if q0 is None else np.array(q0, dtype=float)
    report_coef = 8 * (1 - m.poisson_ratio**2) / (np.pi * m.youngs_modulus)  # 1/sigma per unit a, eq 33
    q, s, Q, work, power, stick_count, total_iter, status = _march(
        P, a, shape, xi, Mom, mu, _basis_workspace(nn), k, delta, M, float(speed), float(m.creepage), float(m.friction_dynamic),
        float(m.friction_static), float(m.half_width), 0 if closure == "default" else 1, float(closure_scale),
        report_coef, q_init, int(max_iter), CHECKERBOARD_LIMIT)
    code, i = int(status[0]), int(status[1])
    if code == 1:
        raise ContactError(f"the stick/slip iteration did not converge at step {i} (a = {a[i]:.4g} m).")
    if code == 2:
        raise ContactError(f"the tangential traction is not finite at step {i} (a = {a[i]:.4g} m, P = {P[i]:.4g} N).")
    if code == 3:
        raise ContactError(
            f"the tangential solution diverged at step {i} (closure '{closure}', s = {closure_scale}): "
            f"node-to-node oscillation {status[2]:.2f} mu p0 in the stick zone (limit {CHECKERBOARD_LIMIT}). "
            "The report's closure u(0,t) = q(0,t)/sigma (eqs 32-33) is ill-posed for unsteady rolling "
            "(docs/paper-discrepancies.md); use contact.closure: default."
        )
    return TangentialSolution(q, s, xi, a, P, Q, work, power, delta, int(total_iter), stick_count)


def perturbation_growth(m: ContactMaterial, P: float, speed: float, nodes: int, closure: str = "default",
                        closure_scale: float = 1.0, L: float = 0.6, eps: float = 1e-6, transits: int = 8,
                        spin_up: int = 12, seed: int = 1) -> float:
    """Well-posedness measure of the unsteady tangential problem: growth factor per patch transit
    (2a / V) of a small perturbation of the steady rolling state under a constant load.

    Parameters
    ----------
    m : ContactMaterial
    P : float
        Normal force [N].
    speed : float
        Rolling speed [m/s].
    nodes : int
        Grid nodes across the patch [-].
    closure, closure_scale : str, float
        The closure under test (solve_tangential).
    L : float
        Bay length [m] (the grid spacing divides it).
    eps : float
        Relative size of the perturbation [-].
    transits, spin_up : int
        Patch transits measured, and of spin-up to the steady state [-].
    seed : int
        Random seed of the perturbation.

    Returns
    -------
    float
        Growth factor per transit [-]: below 1 perturbations decay (well-posed).

    Notes
    -----

    The discrete steady state is computed with the default closure (the closures differ only by a
    rigid term that is constant in steady rolling, so it is the fixed point of every closure). A
    random perturbation of relative size ``eps`` (of max abs(q), on the loaded nodes) is added, and
    the perturbed and unperturbed states are both time-stepped with the closure under test. The
    growth per transit is (d_last / d_first)^(1 / (transits - 1)), with d_n the largest traction
    difference over transit n. Below 1: perturbations decay (well-posed); above 1 they grow. The
    report's closure (eqs 32-33) gives about 15 at 81 nodes and more on finer grids
    (docs/contact.md). Cost: (spin_up + 2 transits) transits of the solver.
    """
    a = float(hertz_half_length(P, m.wheel_radius, m))
    delta, _, M = rolling_grid(1.05 * a, L, nodes)
    nn = 2 * M + 1
    n_tr = max(int(round(2 * a / delta)), 1)  # steps per transit
    base = solve_tangential(np.full(spin_up * n_tr, P), np.full(spin_up * n_tr, a), m, speed, delta, M).q[-1]
    pert = eps * np.abs(base).max() * np.random.default_rng(seed).standard_normal(nn) * (base != 0)
    steps = transits * n_tr
    kw = dict(closure=closure, closure_scale=closure_scale)
    ref = solve_tangential(np.full(steps, P), np.full(steps, a), m, speed, delta, M, q0=base, **kw).q
    per = solve_tangential(np.full(steps, P), np.full(steps, a), m, speed, delta, M, q0=base + pert, **kw).q
    d = np.abs(per - ref).max(axis=1).reshape(transits, n_tr).max(axis=1)
    return float((d[-1] / max(d[0], 1e-300)) ** (1.0 / (transits - 1)))
