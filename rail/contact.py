"""Hertz normal contact and 2D unsteady tangential rolling contact (report sec. 4.2-4.3).

Conventions
-----------
* The wheel rolls in +x at speed V. The patch coordinate xi is measured from the contact centre
  with the leading edge at xi = +a. Rail particles cross the patch from +a to -a.
* q(xi, t) is the tangential traction (Pa) and p the pressure (Pa). s is the slip velocity of
  eq 26, s = V gamma - V du/dxi + du/dt. In slip, q = -mu_d p sign(s) (eq 27). For a driving
  wheel gamma < 0 and q > 0.
* u(xi, t) is the relative tangential surface displacement (eq 29), u = -k int q(zeta) K(xi, zeta)
  d zeta with k = 4 (1 - nu^2) / (pi E). The kernel depends on the closure:
    report   (eqs 29, 32-33): K = ln|1 - xi/zeta|, plus u(0, t) = q(0, t) / sigma.
    default  (well-posed):    K = ln(|xi - zeta| / l(t)), l = (a / 2) exp(2 s / pi), s = 1.
  The two agree in steady rolling, where only du/dxi matters. The default is the report's rigid
  term linearised about the Cattaneo traction at vanishing force (docs/contact.md). The family
  parameter s scales the report's rigid compliance 1/sigma.

Discretisation (docs/contact.md)
--------------------------------
The grid is fixed to the patch, with nodes xi_n = (n - M) Delta, and the wheel advances
Delta = V dt per step. A rail particle at node m+1 at step i-1 is at node m at step i, so the
material derivative du/dt - V du/dxi is exact along particle paths:
    s_m = V gamma + (u_m(t) - u_{m+1}(t - dt)) / dt.
The traction is piecewise linear (hat functions at the nodes) and u is collocated at the
nodes, with closed-form log-kernel integrals. Each step is a small linear complementarity
problem (stick: s = 0, |q| <= mu_s p; slip: q = -mu_d p sign(s)), solved by an active-set
iteration that admits any number of stick and slip zones.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = [
    "ContactMaterial",
    "ContactError",
    "compliance",
    "hertz_half_length",
    "equivalent_radius",
    "hertz_pressure",
    "carter",
    "influence_matrix",
    "TangentialSolution",
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
    """k = 4 (1 - nu^2) / (pi E), 1/Pa: both bodies together (eqs 29-31)."""
    return 4 * (1 - m.poisson_ratio**2) / (np.pi * m.youngs_modulus)


def equivalent_radius(curvature, m: ContactMaterial):
    """R from 1/R = 1/R_w + kappa (eq 24), m. kappa = -z'' (1/m).

    Raises ContactError where the rail is concave more sharply than the wheel (z'' >= 1/R_w),
    where the wheel touches at more than one point.
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
    """a = sqrt(4 (1 - nu^2) P R / (pi b E)), m (eq 23). P : N (>= 0), R : m."""
    P = np.asarray(P, dtype=float)
    return np.sqrt(4 * (1 - m.poisson_ratio**2) * np.maximum(P, 0) * R / (np.pi * m.half_width * m.youngs_modulus))


def hertz_pressure(xi, P, a, m: ContactMaterial):
    """p = P / (pi a b) sqrt(1 - (xi/a)^2) inside the patch, 0 outside, Pa (eq 22)."""
    xi = np.asarray(xi, dtype=float)
    r = np.clip(1 - (xi / a) ** 2, 0, None)
    return P / (np.pi * a * m.half_width) * np.sqrt(r)


def carter(xi, P, m: ContactMaterial, speed: float, R: float):
    """Carter's steady 2D rolling solution: (q, s, Q, c).

    q : Pa, tangential traction at xi; s : m/s, slip velocity (0 in stick);
    Q : N, total tangential force 2b int q; c : m, stick half-length (stick zone [a - 2c, a]).
    Saturation (no stick) when |gamma| >= 4 (1 - nu^2) mu_d p0 / E. From eqs 26-30:
    1 - c/a = |gamma| / (pi k mu p0), Q = mu P (1 - (c/a)^2), sign of q opposite to gamma.
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


def _log_hat(j):
    """int over the unit hat centred at j of ln|t| dt (t in units of the spacing): c(j)."""

    j = np.asarray(j, dtype=float)
    t = np.stack([j - 1, j, j + 1])
    g0, g1 = _G0(t), _G1(t)
    # left half (from j-1 up to j) and right half (from j down to j+1) of the unit hat
    left = (g1[1] - g1[0]) + (1 - j) * (g0[1] - g0[0])
    right = (j + 1) * (g0[2] - g0[1]) - (g1[2] - g1[1])
    return left + right


def _log_abs(t):
    """ln|t| where t != 0, and 0 at t = 0 (where t ln|t| and t^2 ln|t| vanish)."""
    out = np.zeros_like(t)
    nz = t != 0
    out[nz] = np.log(np.abs(t[nz]))
    return out


def _G0(t):
    """Antiderivative of ln|t|: t ln|t| - t (0 at t = 0)."""
    t = np.asarray(t, dtype=float)
    return t * _log_abs(t) - t


def _G1(t):
    """Antiderivative of t ln|t|: t^2 ln|t| / 2 - t^2 / 4 (0 at t = 0)."""
    t = np.asarray(t, dtype=float)
    return t * t * (0.5 * _log_abs(t) - 0.25)


def _g0(t: float) -> float:
    """Scalar _G0 (the per-step edge terms, where numpy's call overhead dominates)."""
    return t * math.log(abs(t)) - t if t != 0 else 0.0


def _g1(t: float) -> float:
    """Scalar _G1."""
    return t * t * (0.5 * math.log(abs(t)) - 0.25) if t != 0 else 0.0


def _half_hat_scalar(j: float, e: float, side: int) -> float:
    """Scalar _half_hat."""
    if side > 0:
        return ((j + e) / e) * (_g0(j + e) - _g0(j)) - (_g1(j + e) - _g1(j)) / e
    return (_g1(j) - _g1(j - e)) / e + ((e - j) / e) * (_g0(j) - _g0(j - e))


def _half_hat(j, e, side):
    """int of ln|t| times a half hat from 1 at t = j to 0 at t = j + e (side +1) or j - e (side -1),
    t in units of the spacing; e in (0, 1]. The full right half is e = 1."""
    j = np.asarray(j, dtype=float)
    if side > 0:
        return ((j + e) / e) * (_G0(j + e) - _G0(j)) - (_G1(j + e) - _G1(j)) / e
    return (_G1(j) - _G1(j - e)) / e + ((e - j) / e) * (_G0(j) - _G0(j - e))


def influence_matrix(n_rows: int, n_cols: int, delta: float, k: float):
    """Base influence matrix B[m, n] = -k int hat_n(zeta) ln(|xi_m - zeta| / delta) d zeta, m/Pa.

    Rows and columns both index the grid nodes xi = (n - M) Delta (rows may run one node further, for
    the leading-edge neighbour). Closed form through the antiderivatives of ln|t| and t ln|t|.
    """
    m = np.arange(n_rows)[:, None]
    n = np.arange(n_cols)[None, :]
    return -k * delta * _log_hat(n - m)


@dataclass(frozen=True)
class TangentialSolution:
    """Result of one bay of unsteady rolling.

    q, s    : (steps, nodes) traction (Pa) and slip velocity (m/s) at the grid nodes
    xi      : (nodes,) node positions in the patch, m
    a, P    : (steps,) half-length (m) and normal force (N)
    Q       : (steps,) total tangential force 2b int q, N
    work    : (steps + nodes,) frictional work per unit area done on each rail particle, J/m^2;
              particle j is at node m = j - i at step i (x = x_wheel(i) + (j - i - M) Delta)
    power   : (steps,) frictional power per unit area of the patch, summed over it, W/m (per unit width)
    delta   : grid spacing = V dt, m
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
    """Largest second difference of the traction inside the stick zones (at least three nodes from
    a zone boundary), relative to mu p0. Used to stop the report's closure when it diverges: in
    steady and slowly varying rolling the default closure keeps it <= 0.11 after the first
    transit, the report's closure reaches 0.29-0.83. Fast load variations (1600 Hz) legitimately
    reach 0.25 with the default closure, whose stability is shown by the perturbation test instead
    (docs/contact.md)."""
    core = stick.copy()
    core[1:] &= stick[:-1]
    core[:-1] &= stick[1:]
    inner = core[1:-1] & core[2:] & core[:-2]
    if not inner.any():
        return 0.0
    d2 = np.abs(q[2:] - 2 * q[1:-1] + q[:-2])
    return float(d2[inner].max() / (mu * p0))


CHECKERBOARD_LIMIT = 0.25


def rolling_grid(a_max: float, L: float, nodes: int):
    """Grid spacing Delta = L / N_x with N_x integer, at least ``nodes`` nodes across 2 a_max.

    Returns (delta, N_x, M) with M the index of the centre node; the grid has 2M + 1 nodes and
    (2M + 1) Delta > 2 a_max.
    """
    if nodes < 5:
        raise ValueError(f"numerics.contact.nodes = {nodes} is not allowed: it must be >= 5.")
    Nx = int(np.ceil(L * (nodes - 1) / (2 * a_max)))
    delta = L / Nx
    M = int(np.ceil(a_max / delta)) + 1
    return delta, Nx, M


def solve_tangential(P, a, m: ContactMaterial, speed: float, delta: float, M: int, closure: str = "default",
                     closure_scale: float = 1.0, q0=None, max_iter: int = 200) -> TangentialSolution:
    """Time-step the unsteady 2D rolling contact over len(P) steps of Delta = V dt.

    P, a : normal force (N) and half-length (m) at each step; the patch is [-a, a] on the
    fixed grid xi_n = (n - M) Delta, n = 0..2M. q0 : initial traction at the nodes (default 0).
    closure : 'default' (log kernel with l = (a/2) exp(2 s / pi), s = closure_scale) or 'report'
    (eqs 32-33, u(0) = q(0)/sigma with 1/sigma scaled by closure_scale).
    """
    P = np.asarray(P, dtype=float)
    a = np.asarray(a, dtype=float)
    if np.any(a >= M * delta):
        raise ValueError(f"the patch half-length {a.max():.4g} m exceeds the grid's {M * delta:.4g} m.")
    nn = 2 * M + 1
    xi = (np.arange(nn) - M) * delta
    k = compliance(m)
    B = influence_matrix(nn + 1, nn, delta, k)  # rows: nodes plus the leading neighbour
    dt = delta / speed
    g = m.creepage
    mu_d, mu_s = m.friction_dynamic, m.friction_static
    b2 = 2 * m.half_width

    steps = len(P)
    q_hist = np.zeros((steps, nn))
    s_hist = np.zeros((steps, nn))
    Q_hist = np.zeros(steps)
    work = np.zeros(steps + nn)
    power = np.zeros(steps)
    stick_count = np.zeros(steps, dtype=int)
    q = np.zeros(nn) if q0 is None else np.asarray(q0, dtype=float).copy()
    col_w = np.full(nn, delta)  # int hat_n (updated with the edge hats each step)

    rows = np.arange(nn + 1)

    # full half hats of every column at every row, tabulated once (the edge columns replace them)
    cols = np.arange(nn)
    H_right = _half_hat(cols[:, None] - rows[None, :], 1.0, +1)  # (column, row)
    H_left = _half_hat(cols[:, None] - rows[None, :], 1.0, -1)

    def edge_geometry(ai):
        lead = int(np.floor(ai / delta - 1e-12)) + M  # last node with xi < a
        return lead, 2 * M - lead, ai / delta - (lead - M)  # (a - xi_lead) / Delta in (0, 1]

    def edge_columns(ai):
        """Base matrix with the two outermost hats ending exactly at -a and +a (continuous in a)."""
        lead, trail, e = edge_geometry(ai)
        Bm = B.copy()
        w = col_w.copy()
        Bm[:, lead] += -k * delta * (_half_hat(lead - rows, e, +1) - H_right[lead])
        Bm[:, trail] += -k * delta * (_half_hat(trail - rows, e, -1) - H_left[trail])
        w[:] = delta
        w[lead] = w[trail] = delta * 0.5 * (1 + e)
        return Bm, w

    def row_at(x_pt, ai, w):
        """-k int hat_n ln|x_pt - zeta| d zeta for every column n (edge hats as in edge_columns)."""
        lead, trail, e = edge_geometry(ai)
        j = (xi - x_pt) / delta
        r = -k * delta * _log_hat(j)
        jl, jt = float(j[lead]), float(j[trail])
        r[lead] += -k * delta * (_half_hat_scalar(jl, e, +1) - _half_hat_scalar(jl, 1.0, +1))
        r[trail] += -k * delta * (_half_hat_scalar(jt, e, -1) - _half_hat_scalar(jt, 1.0, -1))
        return r - k * np.log(delta) * w

    def full_matrix(ai):
        """Influence matrix of the closure at half-length ai, and its row at xi = +a."""
        Bm, w = edge_columns(ai)
        col_w[:] = w
        if closure == "default":
            rigid = k * np.log(0.5 * ai * np.exp(2 * closure_scale / np.pi)) * w
        else:
            # report: + k int q ln|zeta| + q(0)/sigma, sigma from eq 33 = pi E / (8 (1 - nu^2) a)
            rigid = -(Bm[M, :] - k * np.log(delta) * w)
            rigid[M] += closure_scale * 8 * (1 - m.poisson_ratio**2) * ai / (np.pi * m.youngs_modulus)
        C = Bm - k * np.log(delta) * w[None, :] + rigid[None, :]
        return C, row_at(ai, ai, w) + rigid

    C, r_edge = full_matrix(a[0])
    u_old = C @ q
    u_edge_old = r_edge @ q
    stick_prev = np.zeros(nn, dtype=bool)
    sign_prev = np.full(nn, -np.sign(g) if g != 0 else 0.0)
    total_iter = 0
    for i in range(steps):
        C, r_edge = full_matrix(a[i])
        p = hertz_pressure(xi, P[i], a[i], m)
        inside = p > 0
        lead = int(np.floor(a[i] / delta - 1e-12)) + M
        tau = (a[i] - xi[lead]) / speed  # time since the leading particle entered the patch
        # stick equations: E q = h. Regular particle m: u_m(t) = u_{m+1}(t - dt) - gamma Delta.
        # The particle that entered in the last step has stuck since it crossed xi = a, where the
        # surface displacement was u_a (taken at the previous step, which keeps the strong
        # self-influence of the log kernel on the diagonal): u_lead(t) = u_a - gamma (a - xi_lead).
        E = C[:nn]
        h = u_old[1:] - g * delta
        h[lead] = u_edge_old - g * (a[i] - xi[lead])
        stick = np.zeros(nn, dtype=bool)
        stick[:-1] = stick_prev[1:]
        stick[lead] = True
        stick &= inside
        sign = np.empty(nn)  # direction of q in slip, carried by the particles
        sign[:-1] = sign_prev[1:]
        sign[-1] = -np.sign(g) if g != 0 else 0.0
        sign[lead] = sign[lead] if sign[lead] != 0 else (-np.sign(g) if g != 0 else 0.0)
        qn = np.zeros(nn)
        for it in range(max_iter):
            slip = inside & ~stick
            qn[:] = 0.0
            qn[slip] = mu_d * p[slip] * sign[slip]
            if stick.any():
                S = np.where(stick)[0]
                rhs = h[S] - E[np.ix_(S, np.where(slip)[0])] @ qn[slip]
                qn[S] = np.linalg.solve(E[np.ix_(S, S)], rhs)
            # slip velocity: s = V gamma + (E q - h) / dt  (exact along the particle path)
            s = g * speed + (E @ qn - h - g * delta) / dt
            s[lead] = g * speed + (E[lead] @ qn - u_edge_old) / max(tau, 1e-300)
            s[~inside] = 0.0
            changed = False
            over = stick & (np.abs(qn) > mu_s * p)
            if over.any():
                stick[over] = False
                sign[over] = np.sign(qn[over])
                changed = True
            wrong = slip & (s * sign > 0)  # q = -mu p sign(s) violated: the particle sticks
            if wrong.any():
                stick[wrong] = True
                changed = True
            if not changed:
                break
        else:
            raise ContactError(f"the stick/slip iteration did not converge at step {i} (a = {a[i]:.4g} m).")
        total_iter += it + 1
        if not np.all(np.isfinite(qn)):
            raise ContactError(f"the tangential traction is not finite at step {i} (a = {a[i]:.4g} m, P = {P[i]:.4g} N).")
        s[stick] = 0.0
        stick_count[i] = int(np.count_nonzero(stick & inside))
        if closure == "report" and i > nn and P[i] > 0:
            cb = checkerboard_measure(qn, stick & inside, P[i] / (np.pi * a[i] * m.half_width), mu_d)
            if cb > CHECKERBOARD_LIMIT:
                raise ContactError(
                    f"the tangential solution diverged at step {i} (closure '{closure}', s = {closure_scale}): "
                    f"node-to-node oscillation {cb:.2f} mu p0 in the stick zone (limit {CHECKERBOARD_LIMIT}). "
                    "The report's closure u(0,t) = q(0,t)/sigma (eqs 32-33) is ill-posed for unsteady rolling "
                    "(docs/paper-discrepancies.md); use contact.closure: default."
                )
        q_hist[i] = qn
        s_hist[i] = s
        Q_hist[i] = b2 * col_w @ qn
        # Frictional work in this step on the particle now at node m (particle index i + m): its
        # step-averaged traction times its slip over the step (s is the step-average slip velocity).
        # The particle that entered at +a during the step was loaded for tau only; the particle at
        # the trailing node leaves the patch at -a after tau_exit, with the traction falling to 0.
        q_same = np.zeros(nn)
        q_same[:-1] = q[1:]
        dw = np.abs(0.5 * (qn + q_same) * s) * dt
        dw[lead] = np.abs(0.5 * qn[lead] * s[lead]) * tau
        trail = 2 * M - lead
        dw[trail] += np.abs(0.5 * qn[trail] * s[trail]) * (xi[trail] + a[i]) / speed
        work[i : i + nn] += dw
        power[i] = dw.sum() * delta / dt
        q = qn
        u_old = C @ qn
        u_edge_old = r_edge @ qn
        stick_prev = stick
        sign_prev = np.where(stick, np.sign(qn), sign)
    return TangentialSolution(q_hist, s_hist, xi, a, P, Q_hist, work, power, delta, total_iter, stick_count)


def perturbation_growth(m: ContactMaterial, P: float, speed: float, nodes: int, closure: str = "default",
                        closure_scale: float = 1.0, L: float = 0.6, eps: float = 1e-6, transits: int = 8,
                        spin_up: int = 12, seed: int = 1) -> float:
    """Well-posedness measure of the unsteady tangential problem: growth factor per patch transit
    (2a / V) of a small perturbation of the steady rolling state, constant load P (N).

    The discrete steady state is computed with the default closure (the closures differ only by a
    rigid term that is constant in steady rolling, so it is the fixed point of every closure). A
    random perturbation of relative size ``eps`` (of max |q|, on the loaded nodes) is added, and
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
