"""The steps of one time step of the unsteady 2D rolling contact (report eqs 26-33), compiled: the
tangential march (rail.contact.march._march) and its tangent (rail.contact.tangent._march_tangent)
both call these, in this order, so that the derivative differentiates the very scheme it runs on.

1. ``_pressure``: the pressure at the nodes (eq 22, times the non-Hertzian shape factor) and which
   nodes are loaded.
2. ``_shift_particles``: every particle moves one node back (the wheel advances Delta = V dt); the
   particle at the leading node is new, in slip against the creepage.
3. ``_enter_particles``: particle entry. A particle that crossed the leading edge a(t) during the
   step sticks from the edge displacement at its entry time (its row of the influence matrix
   modified in place; ``_restore_rows`` undoes it).
4. ``_stick_solve``: the stick solve, an active-set iteration on the small complementarity problem
   of the step (stick: s = 0, abs(q) <= mu_s p; slip: q = -mu_d p sign(s)).
5. ``_exit_slip``: the slip update of the particles that left the patch (or a contact zone) during
   the step: their mean slip velocity over their loaded time.
6. ``_step_work_all`` (``_work_terms_of`` per node): the step work, the frictional work per unit area on each
   particle in the step.
7. ``_advance``: the state carried to the next step.

Conventions as rail.contact.march (the module docstring): nodes xi_n = (n - M) Delta, leading edge
at +a, q and p in Pa, s in m/s, u in m, work in J/m^2. The influence matrix C (rows: the nodes and
the leading neighbour) is that of rail.contact.basis._closure_matrix; E = C[:nn].
"""

from __future__ import annotations

import math

import numpy as np

from .._lazyjit import njit
from .._linalg import getrf_rows, getrs_rows
from .numerics import THETA_EDGE

__all__: list[str] = []


@njit(cache=True)
def _ellipse_area(eta):
    """F(eta) = int_0^eta sqrt(1 - t^2) dt with eta clipped to [-1, 1] (0 outside the patch)."""
    e = min(max(eta, -1.0), 1.0)
    return 0.5 * (e * math.sqrt(max(1.0 - e * e, 0.0)) + math.asin(e))


@njit(cache=True)
def _pressure(Pi, ai, xi, shape_row, half_width, p, inside):
    """Pressure p = P / (pi a b) sqrt(1 - xi^2 / a^2) shape at the nodes (eq 22 times the shape
    factor; in place) and the loaded nodes (p > 0). Returns the peak Hertz pressure p0 [Pa]."""
    p0 = Pi / (math.pi * ai * half_width)
    for n in range(xi.size):
        rr = 1 - (xi[n] / ai) ** 2
        p[n] = p0 * math.sqrt(rr if rr > 0 else 0.0) * shape_row[n]
        inside[n] = p[n] > 0
    return p0


@njit(cache=True)
def _shift_particles(stick, sign, stick_prev, sign_prev, sg):
    """Each particle one node back (in place); the new particle at the leading node slips against the
    creepage (sign -sg)."""
    nn = stick.size
    for n in range(nn - 1):
        stick[n] = stick_prev[n + 1]
        sign[n] = sign_prev[n + 1]
    stick[nn - 1] = False
    sign[nn - 1] = -sg


@njit(cache=True)
def _entry_fraction(xi_n, delta, a_prev, ai):
    """Where in the step the particle now at xi_n crossed the leading edge: theta unclipped, with
    eta = xi / a linear in time from (xi_n + Delta) / a(t - dt) to xi_n / a(t). Returns (theta0,
    eta0 - 1, eta0 - eta1)."""
    eta0, eta1 = (xi_n + delta) / a_prev, xi_n / ai
    num, den = eta0 - 1.0, eta0 - eta1
    return num / den, num, den


@njit(cache=True)
def _enter_particles(xi, delta, a_prev, ai, gd, u_old, u_edge_old, C, r_edge, p, inside, stick, sign, sg, h, enter,
                     theta, saved):
    """Particle entry (in place): the right-hand sides h of the stick equations and the rows of the
    particles that entered during the step. Returns how many entered (their original rows in saved).

    gd = gamma V dt is the rigid slip over the step (gamma Delta when the patch moves with the wheel,
    Delta = V dt; the patch's true path moves it by Delta over the rail in a step of its own length
    dt, rail.contact.passage). Regular particle: u_n(t) = u_{n+1}(t - dt) - gd (exact along its path). A particle that
    was at or beyond the leading edge a(t - dt) entered at t_e = t - (1 - theta) dt, where its path
    meets the edge (eta = xi / a linear in time); it has stuck since, from the edge displacement at
    t_e, interpolated between the steps: u_n(t) = u_a(t_e) - (1 - theta) gd,
    u_a(t_e) = theta u_a(t) + (1 - theta) u_a(t - dt). Divided by 1 - theta, its row
    (E_n - theta r_a) / (1 - theta) q = u_a(t - dt) - gd tends to the slip-free condition at
    the edge as the particle nears it (theta -> 1); with the square-root basis the displacement
    gradient there is finite. (An extrapolation of u_a from the two previous steps leaves a neutral
    mode when the edge is just past a node.) A particle that reaches the edge within THETA_EDGE dt of
    the end of the step is not yet loaded (pressure below 2e-5 p0; its row would divide rounding by
    1 - theta): its p is set to 0.
    """
    nn = xi.size
    nent = 0
    for n in range(nn):
        h[n] = u_old[n + 1] - gd
        enter[n] = False
        if inside[n] and xi[n] + delta >= a_prev:
            th0, _, _ = _entry_fraction(xi[n], delta, a_prev, ai)
            th = min(max(th0, 0.0), 1.0)
            if 1.0 - th < THETA_EDGE:
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
            h[n] = u_edge_old - gd
            stick[n] = True
            if sign[n] == 0:
                sign[n] = -sg
    for n in range(nn):
        stick[n] = stick[n] and inside[n]
    return nent


@njit(cache=True)
def _restore_rows(C, saved, enter):
    """Put back the rows of C that _enter_particles replaced (in place)."""
    j = 0
    for n in range(enter.size):
        if enter[n]:
            for c in range(C.shape[1]):
                C[n, c] = saved[j, c]
            j += 1


_BORDER_MAX = 2  # stick nodes released in one pass that the last factors still serve (more: factor afresh)


@njit(cache=True)
def _factor_stick(E, S, ns, LU, piv, pos):
    """LU factors of the stick block E[S, S] (S = S[:ns]) into LU, piv; pos[n] the place of node n in S."""
    for n in range(pos.size):
        pos[n] = -1
    for r in range(ns):
        pos[S[r]] = r
        for c in range(ns):
            LU[r, c] = E[S[r], S[c]]
    getrf_rows(LU, ns, piv)


@njit(cache=True)
def _stick_subset(S, ns, pos, nf, released):
    """Whether the stick set S[:ns] is the factored set less at most _BORDER_MAX nodes (released of them)."""
    if released < 0 or released > _BORDER_MAX:
        return False
    for r in range(ns):
        if pos[S[r]] < 0:
            return False
    return True


@njit(cache=True)
def _bordered_solve(h, Es, qn, stick, ns, LU, piv, Sf, nf, z, ek):
    """The stick solve on the stick nodes (stick[n]; ns of them), the factored set Sf[:nf] less r = nf - ns
    released nodes R, from the factors of E[Sf, Sf] (in place on qn). With A = E[Sf, Sf], z = A^-1 c (c:
    the stick equations' right-hand sides h - Es, Es the slip nodes' part of E q; 0 in the rows of R) and
    e_k = A^-1 u_k for k in R, x = z - sum tau_k e_k with x_R = 0 (an r x r system, r <= _BORDER_MAX = 2,
    by Cramer's rule) satisfies the rows of S: A x = c - sum tau_k u_k. Two triangular solves per released node instead of a new factorisation (the
    active set usually releases one stick node per step). Returns False (qn unchanged) if the r x r system
    is singular or not finite."""
    r = nf - ns
    R = np.empty(r, dtype=np.int64)  # the released nodes' places in Sf
    j = 0
    for m in range(nf):
        n = Sf[m]
        if not stick[n]:
            R[j] = m
            j += 1
            z[m, 0] = 0.0
        else:
            z[m, 0] = h[n] - Es[n]
    getrs_rows(LU, nf, piv, z)
    for a in range(r):
        e = ek[a]
        for m in range(nf):
            e[m, 0] = 0.0
        e[R[a], 0] = 1.0
        getrs_rows(LU, nf, piv, e)
    # tau from G tau = z_R, G = (e_b[R_a]); r <= 2, by Cramer's rule
    t0, t1 = 0.0, 0.0
    if r == 1:
        if ek[0, R[0], 0] == 0.0:
            return False
        t0 = z[R[0], 0] / ek[0, R[0], 0]
    elif r == 2:
        g00, g01, g10, g11 = ek[0, R[0], 0], ek[1, R[0], 0], ek[0, R[1], 0], ek[1, R[1], 0]
        det = g00 * g11 - g01 * g10
        if det == 0.0:
            return False
        t0 = (z[R[0], 0] * g11 - g01 * z[R[1], 0]) / det
        t1 = (g00 * z[R[1], 0] - g10 * z[R[0], 0]) / det
    if not (math.isfinite(t0) and math.isfinite(t1)):
        return False
    for m in range(nf):
        if stick[Sf[m]]:
            x = z[m, 0]
            if r >= 1:
                x -= t0 * ek[0, m, 0]
            if r == 2:
                x -= t1 * ek[1, m, 0]
            qn[Sf[m]] = x
    return True


@njit(cache=True)
def _stick_solve(E, h, p, inside, stick, sign, qn, s, S, g, speed, gd, dt, mu_d, mu_s, max_iter, dub, decay, mus):
    """The stick solve of one step (in place): E q = h on the stick nodes, q = mu_d p sign on the slip
    nodes, and the slip velocity s = V gamma + (E q - h - gd) / dt, exact along each path
    (for an entering particle: its mean slip velocity since it entered). An active-set iteration
    moves nodes where abs(q) > mu_s p to slip and nodes whose slip opposes their traction to stick.

    dub : the step's change of the global relative displacement u_bar [m] (rail.creepage.modes; in gd
    already, gd = gamma V dt + dub): the slip velocity gains dub / dt. decay : s_0 [m/s] of the falling
    friction mu(s) = mu_d + (mu_s - mu_d) exp(-abs(s) / s_0) on the slip nodes (0: mu_d, the report's);
    mus : (nodes,) workspace, the slip nodes' friction, iterated with the active set to a fixed point
    (under-relaxed by half after four passes).

    Returns (converged, iterations, ns): S[:ns] are the stick nodes of the last iteration.
    """
    nn = h.size
    converged = False
    it = 0
    ns = 0
    falling = decay > 0.0
    if falling:
        for n in range(nn):
            mus[n] = mu_d + (mu_s - mu_d) * math.exp(-abs(s[n]) / decay)
    # the factors of the stick block of the set Sf[:nf] last factored (nf = 0: none), kept through the passes
    LU = np.empty((nn, nn))
    piv = np.empty(nn, dtype=np.int32)
    Sf = np.empty(nn, dtype=np.int64)
    pos = np.full(nn, -1, dtype=np.int64)  # a node's place in Sf (-1: not in it)
    z = np.empty((nn, 1))
    ek = np.empty((_BORDER_MAX, nn, 1))
    nf = 0
    while it < max_iter:
        ns = 0
        for n in range(nn):
            if inside[n] and not stick[n]:
                qn[n] = (mus[n] if falling else mu_d) * p[n] * sign[n]
            else:
                qn[n] = 0.0
            if stick[n]:
                S[ns] = n
                ns += 1
        if ns > 0:
            Es = E @ qn  # the slip nodes' part of E q (qn is 0 on the stick nodes here)
            if nf > 0 and _stick_subset(S, ns, pos, nf, nf - ns):
                ok = _bordered_solve(h, Es, qn, stick, ns, LU, piv, Sf, nf, z, ek)
            else:
                ok = False
            if not ok:  # factor the stick block afresh (a node joined the stick set, or the first pass)
                nf = ns
                for r in range(nf):
                    Sf[r] = S[r]
                _factor_stick(E, S, ns, LU, piv, pos)
                for r in range(ns):
                    z[r, 0] = h[S[r]] - Es[S[r]]
                getrs_rows(LU, ns, piv, z)
                for r in range(ns):
                    qn[S[r]] = z[r, 0]
        Eq = E @ qn
        for n in range(nn):
            s[n] = g * speed + dub / dt + (Eq[n] - h[n] - gd) / dt
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
            elif falling:  # the slip node's friction at its new slip velocity
                mu_new = mu_d + (mu_s - mu_d) * math.exp(-abs(s[n]) / decay)
                if abs(mu_new - mus[n]) > 1e-12 * mu_d:
                    changed = True
                    # under-relaxed after the first passes: the falling law's fixed point alternates otherwise
                    mus[n] = mu_new if it < 4 else 0.5 * (mus[n] + mu_new)
        it += 1
        if not changed:
            converged = True
            break
    return converged, it, ns


@njit(cache=True)
def _all_finite(x):
    """Whether every entry of x is finite."""
    for v in x:
        if not np.isfinite(v):
            return False
    return True


@njit(cache=True)
def _exit_fraction(xi, n, a_prev, ai):
    """Where in the step the particle now at node n (at node n + 1 before) left at the trailing edge
    -a: phi unclipped, with eta = xi / a linear in time. Returns (phi0, eta0 + 1, eta0 - eta1, eta1)."""
    eta0, eta1 = xi[n + 1] / a_prev, xi[n] / ai
    num, den = eta0 + 1.0, eta0 - eta1
    return num / den, num, den, eta1


@njit(cache=True)
def _exit_slip(xi, a_prev, ai, g, speed, dt, u_old, u_new, u_trail_old, u_trail_new, inside_prev, inside, s_exit, how, dub):
    """The slip update of the particles that left the loaded region during the step (in place):
    s_exit[n] their mean slip velocity over their loaded time; how[n] 0 (did not leave, or left at the
    start of the step: no loaded time), 1 (left the patch at -a after phi dt: the displacement at -a
    at that time interpolated between the steps, the mirror image of the entry) or 2 (left a contact
    zone inside the patch into a gap, rail.contact.normal.multizone_contact: its mean slip velocity
    over the step along its path, first order in the step). dub: the step's change of u_bar [m]
    (rail.creepage.modes), at a uniform rate over the step."""
    nn = xi.size
    for n in range(nn - 1):
        s_exit[n] = 0.0
        how[n] = 0
        if inside_prev[n + 1] and not inside[n]:
            phi0, _, _, eta1 = _exit_fraction(xi, n, a_prev, ai)
            if 1.0 - eta1 * eta1 > 0.0:  # the ellipse is loaded here but the pressure is 0: a gap
                s_exit[n] = g * speed + dub / dt + (u_new[n] - u_old[n + 1]) / dt
                how[n] = 2
                continue
            phi = min(max(phi0, 0.0), 1.0)
            if phi < THETA_EDGE:  # left at the start of the step: no loaded time, no work
                continue
            u_exit = (1.0 - phi) * u_trail_old + phi * u_trail_new
            s_exit[n] = g * speed + dub / dt + (u_exit - u_old[n + 1]) / (phi * dt)
            how[n] = 1


@njit(cache=True)
def _shape_mean(shape, i, n):
    """The mean of the pressure's shape factor at the particle's two positions (node n + 1 at step
    i - 1, node n at step i); at the leading node its value now."""
    nn = shape.shape[1]
    ip = i - 1 if i > 0 else 0
    return 0.5 * (shape[ip, n + 1] + shape[i, n]) if n < nn - 1 else shape[i, n]


@njit(cache=True)
def _work_terms_of(x, was, ins, q_old, p_old, qn_n, p_n, s_n, s_exit_n, delta, a_prev, ai, p0m, dt, mu_d, fm):
    """The parts of the step work on one particle (see _step_work_all), from its values, scalars only (a
    compiled call with arrays counts their references, which cost more than the work itself when made for
    every node of every step): x its node [m]; was, ins whether it was loaded one step before (then at the
    next node) and is now; q_old, p_old its traction and pressure then [Pa] (0 if not loaded); qn_n, p_n,
    s_n now [Pa, Pa, m/s]; s_exit_n its mean slip velocity if it left the loaded region in the step [m/s];
    fm the mean of the pressure's shape factor at its two positions (_shape_mean).

    Returns (active, sbar, Y, sig, eta0, eta1, span, Fd, lo, d_old, d_new, was): the work is
    |sbar Y| when active, Y = sig mu_d ip + (d_old + d_new) / 2 max(lo, 0) with ip = fm p0m dt Fd / span
    the pressure's time integral, Fd = F(eta0) - F(eta1) (_ellipse_area), lo the loaded time."""
    if not (ins or was):
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, was
    if ins:
        sbar = s_n
        ref = qn_n if qn_n != 0.0 else q_old
    else:
        sbar = s_exit_n
        ref = q_old
    if sbar == 0.0 or ref == 0.0:  # stuck over the step (zero mean slip) or unloaded
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, was
    eta0 = (x + delta) / a_prev
    eta1 = x / ai
    span = eta0 - eta1
    Fd = _ellipse_area(eta0) - _ellipse_area(eta1)
    ip = fm * p0m * dt * Fd / span
    lo = dt * (min(eta0, 1.0) - max(eta1, -1.0)) / span
    loaded = lo if lo > 0.0 else 0.0
    sig = 1.0 if ref > 0 else -1.0
    d_new = qn_n - sig * mu_d * p_n if ins else 0.0
    d_old = q_old - sig * mu_d * p_old if was else 0.0
    Y = sig * mu_d * ip + 0.5 * (d_old + d_new) * loaded
    return True, sbar, Y, sig, eta0, eta1, span, Fd, lo, d_old, d_new, was


@njit(cache=True)
def _step_work_all(dw, i, shape, xi, delta, a_prev, ai, p0m, dt, mu_d, qn, q, p, p_prev, s, s_exit, inside, inside_prev):
    """Frictional work per unit area in step i on the particle now at each node n (at xi_{n+1} one step
    before), J/m^2, into dw (in place): |s_bar int q dt| with s_bar its mean slip velocity over the time it
    was loaded.

    The traction is written q = sigma mu_d p + d, with sigma its direction. The pressure part is
    integrated exactly along the path for the Hertz ellipse, with eta = xi / a(t) linear in time
    between the two steps (clipped at the patch edges, where the particle enters or leaves), so the
    square-root edges of p carry no grid-position error; the deviation d (0 in slip) by the
    trapezoidal rule over the loaded time. s_exit : the mean slip velocity of a particle that left the
    patch during the step, over its loaded time. shape : (steps, nodes) the pressure's shape factor
    (non-Hertzian pressure = Hertz ellipse x shape, rail.contact.normal; 1 for Hertz), taken as its mean
    at the particle's two positions (_shape_mean)."""
    nn = xi.size
    for n in range(nn):
        was = n < nn - 1 and inside_prev[n + 1]
        active, sbar, Y, _, _, _, _, _, _, _, _, _ = _work_terms_of(
            xi[n], was, inside[n], q[n + 1] if was else 0.0, p_prev[n + 1] if was else 0.0, qn[n], p[n], s[n], s_exit[n],
            delta, a_prev, ai, p0m, dt, mu_d, _shape_mean(shape, i, n))
        dw[n] = abs(sbar * Y) if active else 0.0


@njit(cache=True)
def _advance(q, qn, p_prev, p, inside_prev, inside, stick_prev, sign_prev, stick, sign):
    """The particles' state carried to the next step (in place): traction, pressure, loaded set, and
    each particle's stick state and slip direction (a stuck particle keeps its traction's sign)."""
    for n in range(q.size):
        q[n] = qn[n]
        p_prev[n] = p[n]
        inside_prev[n] = inside[n]
        stick_prev[n] = stick[n]
        sign_prev[n] = np.sign(qn[n]) if stick[n] else sign[n]
