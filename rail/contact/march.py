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
along each path (_step_work_all). Each step is a small linear complementarity problem (stick: s = 0,
abs(q) <= mu_s p; slip: q = -mu_d p sign(s)), solved by an active-set iteration that admits any
number of stick and slip zones.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._lazyjit import njit
from ..creepage.modes import LongitudinalModes, advance_modes
from .steady import carter
from .basis import _basis_workspace, _influence_arrays, chebyshev_hat_moments
from .influence import INFLUENCE, _influence_at, influence_table
from .hertz import ContactError, ContactMaterial, compliance, hertz_half_length, report_rigid_compliance
from .numerics import CLOSURES, rolling_grid
from .steps import (_advance, _all_finite, _enter_particles, _exit_slip, _pressure, _restore_rows, _shift_particles,
                    _step_work_all, _stick_solve)

__all__ = ["TangentialSolution", "solve_tangential", "step_times", "checkerboard_measure", "CHECKERBOARD_LIMIT", "perturbation_growth"]


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
    ubar : (steps,) the global relative displacement u_bar of eq 26 at each step [m] (rail.creepage.modes),
              None when there is none (the report's rigid wheel)
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
    ubar: np.ndarray | None = None


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


@njit(cache=True)
def _march(P, a, shape, xi, Mom, mu, ws, k, delta, M, speed, dts, gds, g, mu_d, mu_s, half_width, closure, closure_scale,
           report_coef, q0, max_iter, checkerboard_limit, dus, om, ze, cp, q_ref, decay, settle, xm0, vm0, table):
    """The time loop of solve_tangential (compiled): each step is the sequence of rail.contact.steps.
    dus: the given change of u_bar in each step [m]; om, ze, cp: the modes of the longitudinal
    receptance at the contact (rail.creepage.modes; empty: none), driven by Q - q_ref [N] extrapolated
    from the two steps before, from step ``settle`` on (before it the traction builds up from zero, which
    is no force on the wheelset: its torque holds q_ref); decay: s_0 of the falling friction [m/s] (0: the step law);
    table: the influence matrix's table (rail.contact.influence.influence_table; its cells are interpolated,
    the others rebuilt exactly).
    Returns the histories and a status (code, step, value): 0 ok, 1 no convergence of the stick/slip
    iteration, 2 not finite, 3 the report's closure diverged (value: the checkerboard measure)."""
    nn = xi.size
    steps = P.size
    b2 = 2 * half_width
    sg = 0.0 if g == 0 else (1.0 if g > 0 else -1.0)
    q_hist = np.zeros((steps, nn))
    s_hist = np.zeros((steps, nn))
    Q_hist = np.zeros(steps)
    work = np.zeros(steps + nn)
    power = np.zeros(steps)
    stick_count = np.zeros(steps, dtype=np.int64)
    status = np.zeros(3)
    C, r_edge, r_trail, w, AT, r_a, wu = _influence_arrays(nn)
    q = q0.copy()
    lw, dlw = np.empty(table[5].size), np.empty(table[5].size)
    _influence_at(a[0], table, Mom, mu, xi, k, delta, M, closure, closure_scale, report_coef, C, r_edge, w, r_trail, AT,
                  r_a, wu, ws, lw, dlw)
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
    s = np.zeros(nn)
    mus = np.empty(nn)
    ubar = np.zeros(steps)
    xm = xm0.copy()  # the modes' state [m, m/s]
    vm = vm0.copy()
    Q_last = q_ref
    Q_last2 = q_ref
    ub = 0.0
    qn = np.zeros(nn)
    dw = np.empty(nn)
    S = np.empty(nn, dtype=np.int64)
    total_iter = 0
    theta = np.zeros(nn)
    enter = np.zeros(nn, dtype=np.bool_)
    s_exit = np.zeros(nn)
    how = np.zeros(nn, dtype=np.int64)
    a_prev = a[0]
    p_prev = np.zeros(nn)
    inside_prev = np.zeros(nn, dtype=np.bool_)
    p0_prev = _pressure(P[0], a[0], xi, shape[0], half_width, p_prev, inside_prev)
    for i in range(steps):
        ai = a[i]
        dt = dts[i]  # the step's length in time
        dub = dus[i]  # the change of u_bar over the step: given, and from the modes under the last step's force
        if om.size > 0 and i >= settle:
            # the force over the step extrapolated from the two steps before (second order in the step)
            dub += advance_modes(xm, vm, om, ze, cp, 1.5 * Q_last - 0.5 * Q_last2 - q_ref, dt)
        ub += dub
        ubar[i] = ub
        gd = gds[i] + dub  # the step's rigid slip gamma V dt and the change of u_bar
        if ai != a_built:  # the basis depends on a(t) only
            _influence_at(ai, table, Mom, mu, xi, k, delta, M, closure, closure_scale, report_coef, C, r_edge, w, r_trail,
                          AT, r_a, wu, ws, lw, dlw)
            a_built = ai
        E = C[:nn]
        p0 = _pressure(P[i], ai, xi, shape[i], half_width, p, inside)
        _shift_particles(stick, sign, stick_prev, sign_prev, sg)
        _enter_particles(xi, delta, a_prev, ai, gd, u_old, u_edge_old, C, r_edge, p, inside, stick, sign, sg, h, enter,
                         theta, saved)
        converged, it, _ = _stick_solve(E, h, p, inside, stick, sign, qn, s, S, g, speed, gd, dt, mu_d, mu_s, max_iter, dub,
                                        decay, mus)
        _restore_rows(C, saved, enter)
        if not converged:
            status[0], status[1] = 1, i
            break
        total_iter += it
        if not _all_finite(qn):
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
        Q_last2 = Q_last
        Q_last = Q_hist[i]
        # Frictional work in this step on the particle now at node n (particle index i + n): its
        # step-averaged traction times its slip over the step; the particles that left the patch
        # during the step by their mean slip velocity over their loaded time (_exit_slip).
        u_trail_new = np.dot(r_trail, qn)
        u_new = C @ qn
        _exit_slip(xi, a_prev, ai, g, speed, dt, u_old, u_new, u_trail_old, u_trail_new, inside_prev, inside, s_exit, how, dub)
        p0m = 0.5 * (p0_prev + p0)
        _step_work_all(dw, i, shape, xi, delta, a_prev, ai, p0m, dt, mu_d, qn, q, p, p_prev, s, s_exit, inside, inside_prev)
        tot = 0.0
        for n in range(nn):
            work[i + n] += dw[n]
            tot += dw[n]
        power[i] = tot * delta / dt
        _advance(q, qn, p_prev, p, inside_prev, inside, stick_prev, sign_prev, stick, sign)
        u_trail_old = u_trail_new
        a_prev = ai
        p0_prev = p0
        u_edge_old = np.dot(r_edge, qn)
        u_old = u_new
    return q_hist, s_hist, Q_hist, work, power, stick_count, total_iter, status, ubar

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
                     closure_scale: float = 1.0, q0=None, max_iter: int = 200, shape=None, dt=None, ubar=None,
                     influence: str = "table") -> TangentialSolution:
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
        Largest number of active-set iterations per step (at least 2000 with falling friction, whose
        slip-node friction is iterated with the active set).
    shape : ndarray, shape (len(P), 2M + 1), optional
        Non-Hertzian pressure: p = P / (pi a b) sqrt(1 - xi^2/a^2) shape at the nodes (rail.contact.normal
        .patch_contact: smooth and > 0 in the patch; .multizone_contact: 0 in the gaps between contact
        zones, where a particle carries no traction and does no work) [-]; default 1 (the Hertz ellipse, eq 22).
    dt : ndarray, shape (len(P),), optional
        The time of each step [s]: the patch moves Delta over the rail in each step, the wheel at speed
        V (the rigid slip of a step is gamma V dt). Default Delta / V: the patch moves with the wheel.
        On the patch's true path (rail.contact.passage) the wheel travels V dt while its patch moves
        Delta, so dt = Delta / (V (1 + dc/dx)).
    ubar : ndarray, shape (len(P),), optional
        A given global relative displacement u_bar [m] at each step (eq 26; rail.creepage.modes), added to
        that of m.longitudinal's modes; its change over a step enters the step's slip. Default 0.
    influence : str
        How the influence matrix follows a(t) (rail.contact.influence): 'table' (interpolated in a
        within each grid cell the patch edge visits, from exact rebuilds; 2e-10 of the matrix's scale)
        or 'exact' (rebuilt at every step where a changes).

    The material's ``longitudinal`` modes (rail.creepage.modes.LongitudinalModes), when given, are driven
    by Q - Q_ref (Q of the step before; Q_ref the modes' reference_force, or Carter's steady traction
    at the mean of P with the wheel radius); its ``friction_decay`` s_0 > 0 makes the slip nodes'
    friction fall with the slip velocity.

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
    if influence not in INFLUENCE:
        raise ValueError(f"influence = {influence!r} is not allowed: it must be one of {list(INFLUENCE)}.")
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
    report_coef = report_rigid_compliance(m)  # 1/sigma per unit a, eq 33
    dts, gds = step_times(P.size, delta, speed, m.creepage, dt)
    dus, om, ze, cp, q_ref = _creep_inputs(m, P, speed, ubar)
    _check_modes_resolved(om, dts, delta, speed)
    cl = 0 if closure == "default" else 1
    ws = _basis_workspace(nn)
    table = influence_table(a, Mom, mu, xi, k, delta, M, cl, float(closure_scale), report_coef, ws, influence)
    q, s, Q, work, power, stick_count, total_iter, status, ub = _march(
        P, a, shape, xi, Mom, mu, ws, k, delta, M, float(speed), dts, gds, float(m.creepage), float(m.friction_dynamic),
        float(m.friction_static), float(m.half_width), cl, float(closure_scale),
        report_coef, q_init, int(max_iter if m.friction_decay == 0 else max(max_iter, 2000)),
        CHECKERBOARD_LIMIT, dus, om, ze, cp, q_ref, float(m.friction_decay),
        _settle_steps(a, delta, q0), np.zeros(om.size), np.zeros(om.size), table)  # the modes start at rest
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
    if m.friction_decay > 0 and Q.size > 4:
        _check_falling_friction(Q, m)
    dynamic = m.longitudinal is not None or ubar is not None
    return TangentialSolution(q, s, xi, a, P, Q, work, power, delta, int(total_iter), stick_count, ub if dynamic else None)


# the largest step-to-step second difference of Q (after the first half of the march), relative to max |Q|,
# that falling friction may leave: the step law's is 0.006 (a load varying by 10 % over 41 steps); a falling
# law steeper than the march resolves ((mu_s - mu_d) / s_0 = 0.5 s/m at 0.2 % creepage) alternates by 0.13
FALLING_FRICTION_ALTERNATION = 0.05


def _check_falling_friction(Q, m: ContactMaterial):
    """Raise ContactError where the traction alternates from step to step under friction falling with the
    slip velocity (a fixed point of the law the march does not resolve)."""
    tail = Q[Q.size // 2:]
    alt = float(np.max(np.abs(np.diff(tail, 2)))) / max(float(np.max(np.abs(Q))), 1e-300)
    if alt > FALLING_FRICTION_ALTERNATION:
        raise ContactError(
            f"with friction falling with the slip velocity (contact.friction_decay = {m.friction_decay:g} m/s, mu_s = "
            f"{m.friction_static:g}, mu_d = {m.friction_dynamic:g}) the traction alternates from step to step by {alt:.2g} of its "
            f"largest (limit {FALLING_FRICTION_ALTERNATION}): the law's slope (mu_s - mu_d) / s_0 = "
            f"{(m.friction_static - m.friction_dynamic) / m.friction_decay:.3g} s/m is steeper than the march resolves; use a "
            "larger contact.friction_decay (0.5 m/s and above ran smoothly at 0.1 difference of friction).")


def _check_modes_resolved(om, dts, delta: float, speed: float) -> None:
    """Raise ContactError if a mode of the wheelset lies above the Nyquist frequency 1 / (2 dt) of the
    march's longest step (dt = Delta / V on the wheel's path): the mode would be aliased, and its force,
    held over a step, drives it unstably (rail.setup.build.dynamic_creepage_problems refuses it at
    start-up from the static patch; this is the march's own grid, coarser where the dynamic load's patch
    is larger)."""
    if om.size == 0 or dts.size == 0:
        return
    nyquist = 1.0 / (2.0 * float(np.max(dts)))
    f = float(np.max(om)) / (2 * np.pi)
    if f > nyquist:
        raise ContactError(f"a wheelset mode at {f:.4g} Hz lies above the {nyquist:.4g} Hz the contact march "
                           f"resolves (the Nyquist frequency of its step, grid spacing {delta * 1e3:.3g} mm at "
                           f"{speed:g} m/s): raise the wheelset's inertias or lower its stiffnesses (wheelset.*), or "
                           "refine numerics.contact.nodes.")


def _settle_steps(a, delta: float, q0) -> int:
    """Steps before the wheelset's modes feel the traction: one patch transit when the march starts from
    zero traction (the traction building up is not a force on the wheelset), else 0."""
    if q0 is not None or a.size == 0:
        return 0
    return int(np.ceil(2 * float(a[0]) / delta)) + 1


def _creep_inputs(m: ContactMaterial, P, speed: float, ubar):
    """The march's inputs of dynamic creepage (rail.creepage.modes): the given change of u_bar per step
    [m], the modes (omega [rad/s], zeta [-], c [1/kg]; empty without) and Q_ref [N]."""
    if ubar is None:
        dus = np.zeros(P.size)
    else:
        ub = np.ascontiguousarray(ubar, dtype=float)
        if ub.shape != P.shape or not np.all(np.isfinite(ub)):
            raise ValueError(f"ubar must hold one finite displacement [m] per step ({P.size}); got shape {ub.shape}.")
        dus = np.diff(ub, prepend=ub[:1])  # the change over each step (none in the first)
    modes = m.longitudinal
    if modes is None:
        e = np.zeros(0)
        return dus, e, e, e, 0.0
    if not isinstance(modes, LongitudinalModes):
        raise TypeError(f"ContactMaterial.longitudinal must be a rail.creepage.modes.LongitudinalModes or None, not {type(modes).__name__}.")
    om, ze, cp = modes.arrays()
    q_ref = modes.reference_force
    if q_ref is None:
        q_ref = carter(0.0, float(np.mean(P)), m, speed, m.wheel_radius)[2] if P.size else 0.0
    return dus, om, ze, cp, float(q_ref)


def step_times(steps: int, delta: float, speed: float, creepage: float, dt=None):
    """The time of each step and its rigid slip gamma V dt (the march's dts, gds).

    Parameters
    ----------
    steps : int
        Steps of the march [-].
    delta, speed, creepage : float
        Grid spacing [m], rolling speed V [m/s], creepage gamma [-].
    dt : ndarray, optional
        The step times [s], finite and > 0; default Delta / V at every step.

    Returns
    -------
    dts : ndarray
        [s]
    gds : ndarray
        gamma V dt [m], written gamma Delta (dt / (Delta / V)) so that it is gamma Delta to the last bit
        where dt = Delta / V.
    """
    dt0 = delta / speed
    if dt is None:
        dts = np.full(steps, dt0)
    else:
        dts = np.ascontiguousarray(dt, dtype=float)
        if dts.shape != (steps,) or not (np.all(np.isfinite(dts)) and np.all(dts > 0)):
            raise ValueError(f"dt must hold one finite time > 0 per step ({steps}); got shape {dts.shape}.")
    return dts, creepage * delta * (dts / dt0)


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
