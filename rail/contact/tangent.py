"""The tangent (linearised) march of the unsteady 2D rolling contact: the derivative of the
frictional work of rail.contact.march.solve_tangential with respect to its inputs, for many input
directions at once (rail.growth_spectrum's method 'linear').

_march_tangent runs the march's own steps (rail.contact.steps: pressure, particle shift, particle
entry, stick solve, exit slip, step work, advance) on the reference inputs (P, a, shape) and, along
with them, the forward-mode derivative of every step with the reference's stick/slip sets held
(their change is of second order in a small perturbation, as in a probe with a small amplitude):
the stick equations, the entering and leaving particles' interpolation, the slip velocities and
the frictional work are differentiated by hand; the influence matrix's dependence on a(t) by a
central difference of rail.contact.basis._closure_matrix (relative step 1e-9: small enough that
the truncation order of its Chebyshev series rarely changes within it; one-sided where a node
crosses the patch edge within it). The directions are real columns: a complex (Bloch) input
direction is carried as two columns, its real and imaginary parts (every step is real-linear).
tests/test_growth_spectrum.py checks the result against probes of the nonlinear march.
"""

from __future__ import annotations

import math

import numpy as np

from .._lazyjit import njit
from .basis import _basis_workspace, _closure_matrix, _influence_arrays, chebyshev_hat_moments
from .influence import INFLUENCE, _influence_d_at, _lead_cell, _table_place, influence_table
from .hertz import ContactError, ContactMaterial, compliance, report_rigid_compliance
from .march import step_times
from .steps import (_advance, _all_finite, _enter_particles, _entry_fraction, _exit_fraction, _exit_slip, _pressure,
                    _restore_rows, _shape_mean, _shift_particles, _stick_solve, _work_terms_of)

__all__ = ["work_tangent"]

_DA_REL = 1e-9  # relative step of a in the (central) difference of the influence matrix


@njit(cache=True, error_model="numpy")
def _solve_columns(A, B):
    """Solve A X = B in place (X left in B, A overwritten by its factors): rail._linalg.solve_in_place's Gaussian
    elimination with partial pivoting, operation for operation (the same numbers bit for bit), its back
    substitution ordered by rows of B so that the inner loop runs along the many right-hand sides (the tangent's
    columns, hundreds with the basis of u_bar: rail.growth_spectrum.creepage) in memory order."""
    n, m = A.shape[0], B.shape[1]
    for k in range(n):
        piv, big = k, abs(A[k, k])
        for r in range(k + 1, n):
            v = abs(A[r, k])
            if v > big:
                piv, big = r, v
        if piv != k:
            for c in range(n):
                A[k, c], A[piv, c] = A[piv, c], A[k, c]
            for c in range(m):
                B[k, c], B[piv, c] = B[piv, c], B[k, c]
        inv = 1.0 / A[k, k]
        for r in range(k + 1, n):
            f = A[r, k] * inv
            if f != 0.0:
                A[r, k] = f
                for c in range(k + 1, n):
                    A[r, c] -= f * A[k, c]
                for c in range(m):
                    B[r, c] -= f * B[k, c]
    for k in range(n - 1, -1, -1):
        inv = 1.0 / A[k, k]
        for j in range(k + 1, n):
            f = A[k, j]
            for c in range(m):
                B[k, c] -= f * B[j, c]
        for c in range(m):
            B[k, c] *= inv


@njit(cache=True)
def _dF(e):
    """d/d eta of _ellipse_area (0 where eta is clipped)."""
    if e <= -1.0 or e >= 1.0:
        return 0.0
    return math.sqrt(1.0 - e * e)


@njit(cache=True)
def _d_pressure(p0, dp0, ai, dai, xi, shape_row, dshape_i, has_dshape, dp):
    """The derivative of _pressure along each column (in place): dp [Pa per unit column]."""
    nc = dp.shape[1]
    for n in range(xi.size):
        rr = 1 - (xi[n] / ai) ** 2
        if rr > 0:
            sq = math.sqrt(rr)
            dsq = xi[n] ** 2 / ai ** 3 / sq
            for c in range(nc):
                dp[n, c] = (dp0[c] * sq + p0 * dsq * dai[c]) * shape_row[n]
                if has_dshape:
                    dp[n, c] += p0 * sq * dshape_i[n, c]
        else:
            for c in range(nc):
                dp[n, c] = 0.0


@njit(cache=True)
def _d_closure_matrix(ai, Mom, mu, xi, k, delta, M, closure, closure_scale, report_coef, C, r_edge, w, r_trail, AT, r_a, wu,
                      ws, C2, r_edge2, w2, r_trail2, AT2, r_a2, wu2, ws2, C3, r_edge3, w3, r_trail3, AT3, r_a3, wu3, ws3, Cd,
                      r_edge_d, r_trail_d, w_d):
    """The influence matrix at ai (C, r_edge, w, r_trail: rail.contact.basis._closure_matrix) and its
    derivative in a (Cd, r_edge_d, r_trail_d and the weights' w_d, in place): a central difference where no
    node crosses the patch edge within +-h, else one-sided (the ...2, ...3 arrays: the matrices at a +- h)."""
    nn = xi.size
    lead, _ = _closure_matrix(ai, Mom, mu, xi, k, delta, M, closure, closure_scale, report_coef, C, r_edge, w, r_trail,
                              AT, r_a, wu, ws)
    hstep = _DA_REL * ai
    lead2, _ = _closure_matrix(ai + hstep, Mom, mu, xi, k, delta, M, closure, closure_scale, report_coef, C2, r_edge2, w2,
                               r_trail2, AT2, r_a2, wu2, ws2)
    lead3, _ = _closure_matrix(ai - hstep, Mom, mu, xi, k, delta, M, closure, closure_scale, report_coef, C3, r_edge3, w3,
                               r_trail3, AT3, r_a3, wu3, ws3)
    if lead2 == lead and lead3 == lead:
        hd = 2 * hstep
    elif lead2 == lead:
        hd = hstep
        C3[:] = C
        r_edge3[:] = r_edge
        r_trail3[:] = r_trail
        w3[:] = w
    else:
        hd = hstep
        C2[:] = C
        r_edge2[:] = r_edge
        r_trail2[:] = r_trail
        w2[:] = w
    for r in range(nn + 1):
        for c in range(nn):
            Cd[r, c] = (C2[r, c] - C3[r, c]) / hd
    for n in range(nn):
        r_edge_d[n] = (r_edge2[n] - r_edge3[n]) / hd
        r_trail_d[n] = (r_trail2[n] - r_trail3[n]) / hd
        w_d[n] = (w2[n] - w3[n]) / hd


@njit(cache=True)
def _table_weights_d(ai, delta, M, pieces, w, w2, w_d):
    """The derivative in a of the column weights w (in place, w_d [m/m]) after _influence_d_at (w2: the
    scaled weights' derivative in the local x that it left; w unscaled): the interpolant's, the two
    outermost loaded columns F / sqrt(e) differentiated as _influence_d_at does the matrix's."""
    lead, e, _, _, dxda = _table_place(ai, delta, M, pieces)
    trail = 2 * M - lead
    for n in range(w.size):
        w_d[n] = w2[n] * dxda
    se = math.sqrt(e)
    g = 0.5 / (e * delta)
    for n in (lead, trail):
        w_d[n] = w_d[n] / se - w[n] * g


@njit(cache=True)
def _tabulated(ai, table, delta, M):
    """Whether the influence table holds the lead cell of ai."""
    slot = table[4]
    lead, _ = _lead_cell(ai, delta, M)
    return lead < slot.size and slot[lead] >= 0


@njit(cache=True)
def _d_enter_particles(xi, delta, a_prev, ai, da_prev, dai, du_old, du_edge_old, was_inside, inside, enter, theta, dp, dh,
                       dtheta, dgd):
    """The derivative of _enter_particles (in place): the right-hand sides dh (dgd: of the step's rigid
    slip), the entry fraction dtheta (0 where it is clipped); a particle not yet loaded (THETA_EDGE)
    carries no pressure (dp 0)."""
    nc = dh.shape[1]
    for n in range(xi.size):
        if was_inside[n] and not inside[n]:
            for c in range(nc):
                dp[n, c] = 0.0
        if enter[n]:
            th0, num, den = _entry_fraction(xi[n], delta, a_prev, ai)
            for c in range(nc):
                dh[n, c] = du_edge_old[c] - dgd[c]
                if th0 == theta[n]:
                    de0 = -(xi[n] + delta) / a_prev ** 2 * da_prev[c]
                    de1 = -xi[n] / ai ** 2 * dai[c]
                    dtheta[n, c] = (de0 * den - num * (de0 - de1)) / den ** 2
                else:
                    dtheta[n, c] = 0.0
        else:
            for c in range(nc):
                dh[n, c] = du_old[n + 1, c] - dgd[c]


@njit(cache=True)
def _d_stick_solve(E, C, Cd, r_edge, r_edge_d, qn, dai, enter, theta, dtheta, inside, stick, sign, dp, dh, S, ns, mu_d, dt,
                   dEq, dqn, ds, s, gV, ddt, dgd, ddub, falling, mus, mu_s, decay, p):
    """The tangent of _stick_solve with its stick set S[:ns] held (in place): dE q (the rows of the
    entering particles as modified, C still holding them), the tractions dqn and the slip velocities ds
    (s = gV + dub / dt + (E q - h - gd) / dt, with the derivatives ddt, dgd of the step's time and of its
    rigid slip gd (which holds the change of u_bar, dub), and ddub of dub). With falling friction
    (``falling``; mus the slip nodes' friction reached, mu_s, decay = s_0) a slip node's traction
    mus p sign follows its slip velocity, d mu / d s = -(mu_s - mu_d) / s_0 exp(-abs(s) / s_0) sign(s),
    and the stick and slip nodes are solved together; else (the step law) the slip nodes' traction is
    mu_d p sign and the stick block alone is solved."""
    nn = qn.size
    nc = dqn.shape[1]
    vq = Cd[:nn] @ qn
    redq = np.dot(r_edge, qn)
    reddq = np.dot(r_edge_d, qn)
    for n in range(nn):
        if enter[n]:
            th = theta[n]
            inv = 1.0 / (1.0 - th)
            eq_mod = np.dot(C[n], qn)  # the modified row
            for c in range(nc):
                dEq[n, c] = (vq[n] * dai[c] - dtheta[n, c] * redq - th * reddq * dai[c]) * inv + eq_mod * dtheta[n, c] * inv
        else:
            for c in range(nc):
                dEq[n, c] = vq[n] * dai[c]
    if falling:
        _d_stick_slip_solve(E, p, inside, stick, sign, dp, dh, dEq, dqn, s, gV, dt, ddt, dgd, ddub, mus, mu_s, mu_d, decay)
    else:
        for n in range(nn):
            for c in range(nc):
                dqn[n, c] = mu_d * sign[n] * dp[n, c] if (inside[n] and not stick[n]) else 0.0
        if ns > 0:
            Edq = E @ dqn
            A = np.empty((ns, ns))
            B = np.empty((ns, nc))
            for r in range(ns):
                for cc in range(ns):
                    A[r, cc] = E[S[r], S[cc]]
                for c in range(nc):
                    B[r, c] = dh[S[r], c] - dEq[S[r], c] - Edq[S[r], c]
            _solve_columns(A, B)
            for r in range(ns):
                for c in range(nc):
                    dqn[S[r], c] = B[r, c]
    Edq = E @ dqn
    for n in range(nn):
        if inside[n] and not stick[n]:
            for c in range(nc):
                ds[n, c] = (dEq[n, c] + Edq[n, c] - dh[n, c] - dgd[c] + ddub[c]) / dt - (s[n] - gV) / dt * ddt[c]
        else:
            for c in range(nc):
                ds[n, c] = 0.0


@njit(cache=True)
def _d_stick_slip_solve(E, p, inside, stick, sign, dp, dh, dEq, dqn, s, gV, dt, ddt, dgd, ddub, mus, mu_s, mu_d, decay):
    """dqn of _d_stick_solve under falling friction (in place): on the loaded nodes U, the stick rows
    (E dq)_n = dh_n - dEq_n and the slip rows dq_n = sign_n (mus_n dp_n + p_n mu'(s_n) ds_n), with
    ds_n = (dEq_n + (E dq)_n - dh_n - dgd + ddub) / dt - (s_n - gV) / dt ddt; one dense solve."""
    nn = p.size
    nc = dqn.shape[1]
    U = np.empty(nn, dtype=np.int64)
    nu = 0
    for n in range(nn):
        for c in range(nc):
            dqn[n, c] = 0.0
        if inside[n]:
            U[nu] = n
            nu += 1
    if nu == 0:
        return
    A = np.zeros((nu, nu))
    B = np.empty((nu, nc))
    for r in range(nu):
        n = U[r]
        if stick[n]:
            for cc in range(nu):
                A[r, cc] = E[n, U[cc]]
            for c in range(nc):
                B[r, c] = dh[n, c] - dEq[n, c]
        else:
            sg = sign[n]
            pn = p[n]
            slope = -(mu_s - mu_d) / decay * math.exp(-abs(s[n]) / decay) * (1.0 if s[n] > 0 else (-1.0 if s[n] < 0 else 0.0))
            kap = sg * pn * slope / dt
            for cc in range(nu):
                A[r, cc] = -kap * E[n, U[cc]]
            A[r, r] += 1.0
            for c in range(nc):
                B[r, c] = sg * mus[n] * dp[n, c] + kap * (dEq[n, c] - dh[n, c] - dgd[c] + ddub[c] - (s[n] - gV) * ddt[c])
    _solve_columns(A, B)
    for r in range(nu):
        for c in range(nc):
            dqn[U[r], c] = B[r, c]


@njit(cache=True)
def _d_exit_slip(xi, a_prev, ai, da_prev, dai, dt, u_old, du_old, du_new, u_trail_old, u_trail_new, du_trail_old,
                 du_trail_new, how, ds_exit, s_exit, gV, ddt, ddub):
    """The derivative of _exit_slip (in place), by its cases ``how`` (ddt: of the step's time; ddub: of the
    step's change of u_bar, whose rate dub / dt the slip holds)."""
    nc = ds_exit.shape[1]
    for n in range(xi.size - 1):
        for c in range(nc):
            ds_exit[n, c] = 0.0
        if how[n] == 2:  # left a zone into a gap: along its path
            for c in range(nc):
                ds_exit[n, c] = (du_new[n, c] - du_old[n + 1, c]) / dt - (s_exit[n] - gV) / dt * ddt[c] + ddub[c] / dt
        elif how[n] == 1:  # left at -a after phi dt
            phi0, num, den, _ = _exit_fraction(xi, n, a_prev, ai)
            phi = min(max(phi0, 0.0), 1.0)
            u_exit = (1.0 - phi) * u_trail_old + phi * u_trail_new
            for c in range(nc):
                if phi0 == phi:
                    de0 = -xi[n + 1] / a_prev ** 2 * da_prev[c]
                    de1 = -xi[n] / ai ** 2 * dai[c]
                    dphi = (de0 * den - num * (de0 - de1)) / den ** 2
                else:
                    dphi = 0.0
                du_exit = (dphi * (u_trail_new - u_trail_old) + (1.0 - phi) * du_trail_old[c] + phi * du_trail_new[c])
                ds_exit[n, c] = ((du_exit - du_old[n + 1, c]) / (phi * dt) - (u_exit - u_old[n + 1]) * dphi / (phi * phi * dt)
                                 - (s_exit[n] - gV) / dt * ddt[c] + ddub[c] / dt)


@njit(cache=True)
def _d_step_work(i, xi, delta, a_prev, ai, da_prev, dai, p0m, dp0_prev, dp0, dt, mu_d, qn, dqn, q, dq, p, dp, p_prev,
                 dp_prev, s, ds, s_exit, ds_exit, inside, inside_prev, shape, dshape, has_dshape, work, dwork, ddt):
    """The step work on the particle now at each node n (rail.contact.steps._work_terms_of, as the march's
    _step_work_all) added to work[i + n], and its derivative to dwork[i + n] (in place; Y, the traction's
    time integral, is proportional to the step's time: ddt adds Y ddt / dt). One call per step, the
    particles' values passed to _work_terms_of as scalars (a compiled call per node with arrays counts
    their references)."""
    nn = xi.size
    nc = dwork.shape[1]
    ip = i - 1 if i > 0 else 0
    for n in range(nn):
        was = n < nn - 1 and inside_prev[n + 1]
        fm = _shape_mean(shape, i, n)
        active, sbar, Y, sig, eta0, eta1, span, Fd, lo, d_old, d_new, was = _work_terms_of(
            xi[n], was, inside[n], q[n + 1] if was else 0.0, p_prev[n + 1] if was else 0.0, qn[n], p[n], s[n], s_exit[n],
            delta, a_prev, ai, p0m, dt, mu_d, fm)
        if not active:
            continue
        loaded = lo if lo > 0.0 else 0.0
        X = sbar * Y
        work[i + n] += abs(X)
        sx = 1.0 if X > 0 else (-1.0 if X < 0 else 0.0)
        for c in range(nc):
            de0 = -(xi[n] + delta) / a_prev ** 2 * da_prev[c]
            de1 = -xi[n] / ai ** 2 * dai[c]
            dspan = de0 - de1
            dfm = 0.0
            if has_dshape:
                dfm = 0.5 * (dshape[ip, n + 1, c] + dshape[i, n, c]) if n < nn - 1 else dshape[i, n, c]
            dp0m = 0.5 * (dp0_prev[c] + dp0[c])
            dipw = (dfm * p0m + fm * dp0m) * dt * Fd / span + fm * p0m * dt * (
                (_dF(eta0) * de0 - _dF(eta1) * de1) / span - Fd * dspan / span ** 2)
            if lo > 0.0:
                dlo = dt * ((de0 if eta0 < 1.0 else 0.0) - (de1 if eta1 > -1.0 else 0.0)) / span - lo * dspan / span
            else:
                dlo = 0.0
            dd_new = dqn[n, c] - sig * mu_d * dp[n, c] if inside[n] else 0.0
            dd_old = dq[n + 1, c] - sig * mu_d * dp_prev[n + 1, c] if was else 0.0
            dY = sig * mu_d * dipw + 0.5 * (dd_old + dd_new) * loaded + 0.5 * (d_old + d_new) * dlo + Y / dt * ddt[c]
            dsbar = ds[n, c] if inside[n] else ds_exit[n, c]
            dwork[i + n, c] += sx * (dsbar * Y + sbar * dY)


@njit(cache=True)
def _march_tangent(P, a, shape, dP, da, dshape, has_dshape, xi, Mom, mu, ws, ws2, ws3, k, delta, M, speed, dts, gds, ddts, g, mu_d,
                   mu_s, half_width, closure, closure_scale, report_coef, max_iter, table, dus, ddus, decay):
    """The march of rail.contact.march._march (its steps, rail.contact.steps) from zero traction and,
    with it, the derivative of every step along the columns of dP, da, dshape, ddts and ddus, the
    stick/slip sets held. dus: the given change of u_bar over each step [m] (rail.creepage.modes; zeros:
    none), ddus its direction; decay: s_0 of the falling friction [m/s] (0: the step law). table: the
    influence matrix's table (rail.contact.influence.influence_table): in its cells the matrix and its
    derivative in a are the interpolant's, elsewhere _d_closure_matrix's.
    Returns (work, dwork, Q, dQ, status): Q the tangential force 2 b int q at each step [N] and dQ its
    derivative; status as _march's (0 ok, 1 no convergence, 2 not finite)."""
    nn = xi.size
    steps = P.size
    nc = dP.shape[1]
    sg = 0.0 if g == 0 else (1.0 if g > 0 else -1.0)
    work = np.zeros(steps + nn)
    dwork = np.zeros((steps + nn, nc))
    Q_hist = np.zeros(steps)
    dQ_hist = np.zeros((steps, nc))
    b2 = 2 * half_width
    w_d = np.zeros(nn)
    falling = decay > 0.0
    status = np.zeros(3)
    C, r_edge, r_trail, w, AT, r_a, wu = _influence_arrays(nn)
    # the matrices at a (1 +- h), for the derivative
    C2, r_edge2, r_trail2, w2, AT2, r_a2, wu2 = _influence_arrays(nn)
    C3, r_edge3, r_trail3, w3, AT3, r_a3, wu3 = _influence_arrays(nn)
    Cd = np.empty((nn + 1, nn))
    lw, dlw = np.empty(table[5].size), np.empty(table[5].size)
    r_edge_d = np.empty(nn)
    r_trail_d = np.empty(nn)
    q = np.zeros(nn)
    dq = np.zeros((nn, nc))
    a_built = -1.0
    u_old = np.zeros(nn + 1)
    du_old = np.zeros((nn + 1, nc))
    u_edge_old = 0.0
    du_edge_old = np.zeros(nc)
    u_trail_old = 0.0
    du_trail_old = np.zeros(nc)
    saved = np.empty((nn, nn))
    stick_prev = np.zeros(nn, dtype=np.bool_)
    sign_prev = np.full(nn, -sg)
    stick = np.zeros(nn, dtype=np.bool_)
    inside = np.zeros(nn, dtype=np.bool_)
    was_inside = np.zeros(nn, dtype=np.bool_)
    sign = np.empty(nn)
    p = np.empty(nn)
    dp = np.zeros((nn, nc))
    h = np.empty(nn)
    dh = np.zeros((nn, nc))
    s = np.zeros(nn)  # the slip velocities (the falling friction starts its nodes there, as _march)
    ds = np.zeros((nn, nc))
    qn = np.zeros(nn)
    dqn = np.zeros((nn, nc))
    S = np.empty(nn, dtype=np.int64)
    mus = np.empty(nn)  # the slip nodes' friction under falling friction
    theta = np.zeros(nn)
    dtheta = np.zeros((nn, nc))
    enter = np.zeros(nn, dtype=np.bool_)
    s_exit = np.zeros(nn)
    how = np.zeros(nn, dtype=np.int64)
    ds_exit = np.zeros((nn, nc))
    dEq = np.zeros((nn, nc))
    a_prev = a[0]
    da_prev = da[0].copy()
    p_prev = np.zeros(nn)
    dp_prev = np.zeros((nn, nc))
    inside_prev = np.zeros(nn, dtype=np.bool_)
    p0_prev = _pressure(P[0], a[0], xi, shape[0], half_width, p_prev, inside_prev)
    dp0_prev = p0_prev * (dP[0] / P[0] - da[0] / a[0])
    _d_pressure(p0_prev, dp0_prev, a[0], da[0], xi, shape[0], dshape[0], has_dshape, dp_prev)
    for i in range(steps):
        ai = a[i]
        if ai != a_built and _tabulated(ai, table, delta, M):
            _influence_d_at(ai, table, C, r_edge, w, r_trail, Cd, r_edge_d, r_trail_d, C2, r_edge2, w2, r_trail2, delta, M,
                            lw, dlw)
            _table_weights_d(ai, delta, M, table[7], w, w2, w_d)
            a_built = ai
        elif ai != a_built:
            _d_closure_matrix(ai, Mom, mu, xi, k, delta, M, closure, closure_scale, report_coef, C, r_edge, w, r_trail, AT,
                              r_a, wu, ws, C2, r_edge2, w2, r_trail2, AT2, r_a2, wu2, ws2, C3, r_edge3, w3, r_trail3, AT3,
                              r_a3, wu3, ws3, Cd, r_edge_d, r_trail_d, w_d)
            a_built = ai
        dai = da[i]
        dt, dub = dts[i], dus[i]  # the step's length in time and its change of u_bar
        gd = gds[i] + dub  # the step's rigid slip gamma V dt and the change of u_bar (as _march)
        ddt = ddts[i]
        ddub = ddus[i]
        dgd = gds[i] / dt * ddt + ddub
        E = C[:nn]
        p0 = _pressure(P[i], ai, xi, shape[i], half_width, p, inside)
        dp0 = p0 * (dP[i] / P[i] - dai / ai)
        _d_pressure(p0, dp0, ai, dai, xi, shape[i], dshape[i] if has_dshape else dshape[0], has_dshape, dp)
        _shift_particles(stick, sign, stick_prev, sign_prev, sg)
        was_inside[:] = inside
        _enter_particles(xi, delta, a_prev, ai, gd, u_old, u_edge_old, C, r_edge, p, inside, stick, sign, sg, h, enter,
                         theta, saved)
        _d_enter_particles(xi, delta, a_prev, ai, da_prev, dai, du_old, du_edge_old, was_inside, inside, enter, theta, dp, dh,
                           dtheta, dgd)
        converged, _, ns = _stick_solve(E, h, p, inside, stick, sign, qn, s, S, g, speed, gd, dt, mu_d, mu_s, max_iter, dub, decay, mus)
        if not converged:
            status[0], status[1] = 1, i
            break
        _d_stick_solve(E, C, Cd, r_edge, r_edge_d, qn, dai, enter, theta, dtheta, inside, stick, sign, dp, dh, S, ns, mu_d,
                       dt, dEq, dqn, ds, s, g * speed, ddt, dgd, ddub, falling, mus, mu_s, decay, p)
        _restore_rows(C, saved, enter)
        if not _all_finite(qn):
            status[0], status[1] = 2, i
            break
        for n in range(nn):
            if stick[n]:
                s[n] = 0.0
        u_trail_new = np.dot(r_trail, qn)
        du_trail_new = (np.dot(r_trail_d, qn) * dai) + (r_trail @ dqn)
        u_new = C @ qn
        vC = Cd @ qn
        du_new = C @ dqn
        for r in range(nn + 1):
            for c in range(nc):
                du_new[r, c] += vC[r] * dai[c]
        _exit_slip(xi, a_prev, ai, g, speed, dt, u_old, u_new, u_trail_old, u_trail_new, inside_prev, inside, s_exit, how, dub)
        _d_exit_slip(xi, a_prev, ai, da_prev, dai, dt, u_old, du_old, du_new, u_trail_old, u_trail_new, du_trail_old,
                     du_trail_new, how, ds_exit, s_exit, g * speed, ddt, ddub)
        # the tangential force 2 b int q and its derivative (the weights w depend on a)
        Q_hist[i] = b2 * np.dot(w, qn)
        wq = np.dot(w_d, qn)
        for c in range(nc):
            acc = wq * dai[c]
            for n in range(nn):
                acc += w[n] * dqn[n, c]
            dQ_hist[i, c] = b2 * acc
        p0m = 0.5 * (p0_prev + p0)
        _d_step_work(i, xi, delta, a_prev, ai, da_prev, dai, p0m, dp0_prev, dp0, dt, mu_d, qn, dqn, q, dq, p, dp, p_prev,
                     dp_prev, s, ds, s_exit, ds_exit, inside, inside_prev, shape, dshape, has_dshape, work, dwork, ddt)
        # the state and its derivative
        _advance(q, qn, p_prev, p, inside_prev, inside, stick_prev, sign_prev, stick, sign)
        dq[:] = dqn
        dp_prev[:] = dp
        u_trail_old = u_trail_new
        du_trail_old[:] = du_trail_new
        a_prev = ai
        da_prev[:] = dai
        p0_prev = p0
        dp0_prev[:] = dp0
        u_edge_old = np.dot(r_edge, qn)
        du_edge_old[:] = np.dot(r_edge_d, qn) * dai + r_edge @ dqn
        u_old = u_new
        du_old = du_new
    return work, dwork, Q_hist, dQ_hist, status


def work_tangent(P, a, m: ContactMaterial, speed: float, delta: float, M: int, dP, da, dshape=None, closure: str = "default",
                 closure_scale: float = 1.0, shape=None, max_iter: int = 200, dt=None, ddt=None, influence: str = "table",
                 ubar=None, dubar=None, force: bool = False):
    """The frictional work of solve_tangential from zero traction and its derivative along input directions.

    Parameters
    ----------
    P, a, shape, m, speed, delta, M, closure, closure_scale, max_iter, dt, ubar
        As rail.contact.solve_tangential (the reference march; ubar: a given u_bar [m] at each step). The
        material's falling friction (m.friction_decay > 0) is differentiated too; its wheelset's modes
        (m.longitudinal) must be None: u_bar enters as given (ubar, dubar), the loop through the modes
        is closed outside (rail.growth_spectrum.creepage).
    dP, da : ndarray, shape (len(P), nc)
        Directions of the force [N] and the half-length [m] at each step (nc real columns).
    dshape : ndarray, shape (len(P), 2M + 1, nc), optional
        Direction of the pressure shape factor (default: none).
    ddt : ndarray, shape (len(P), nc), optional
        Direction of the step times [s] (the patch's true path, rail.contact.passage; default: none).
    influence : str
        As solve_tangential: 'table' (the influence matrix and its derivative in a from the interpolant
        of rail.contact.influence) or 'exact' (rebuilt, the derivative by a central difference).
    dubar : ndarray, shape (len(P), nc), optional
        Direction of u_bar [m] at each step (its change over a step enters that step's slip; none in the
        first step, as solve_tangential's ubar; default: none).
    force : bool
        Also return the tangential force and its derivative.

    Returns
    -------
    work : ndarray, shape (len(P) + 2M + 1,)
        The reference's work per unit area by particle [J/m^2] (solve_tangential's work).
    dwork : ndarray, shape (len(P) + 2M + 1, nc)
        Its derivative along each column, the stick/slip sets held.
    Q, dQ : ndarray, shapes (len(P),) and (len(P), nc)
        With ``force``: the tangential force 2 b int q at each step [N] (solve_tangential's Q) and its
        derivative along each column.
    """
    P = np.ascontiguousarray(P, dtype=float)
    a = np.ascontiguousarray(a, dtype=float)
    nn = 2 * M + 1
    if shape is None:
        shape = np.ones((P.size, nn))
    shape = np.ascontiguousarray(shape, dtype=float)
    dP = np.ascontiguousarray(dP, dtype=float)
    da = np.ascontiguousarray(da, dtype=float)
    has = dshape is not None
    dshape = np.ascontiguousarray(dshape, dtype=float) if has else np.zeros((1, 1, dP.shape[1]))
    if np.any(a >= M * delta) or not (np.all(a > 0) and np.all(P > 0)):
        raise ValueError("work_tangent needs a loaded patch inside the grid at every step.")
    if influence not in INFLUENCE:
        raise ValueError(f"influence = {influence!r} is not allowed: it must be one of {list(INFLUENCE)}.")
    if m.longitudinal is not None:
        raise ValueError("work_tangent takes u_bar as given (ubar, dubar): pass the material without its wheelset's modes "
                         "(ContactMaterial.longitudinal None); rail.growth_spectrum.creepage closes their loop.")
    xi = (np.arange(nn) - M) * delta
    Mom, mu = chebyshev_hat_moments(nn)
    cl = 0 if closure == "default" else 1
    ws = _basis_workspace(nn)
    table = influence_table(a, Mom, mu, xi, compliance(m), delta, M, cl, float(closure_scale), report_rigid_compliance(m), ws,
                            influence)
    dts, gds = step_times(P.size, delta, speed, m.creepage, dt)
    ddts = np.zeros(dP.shape) if ddt is None else np.ascontiguousarray(ddt, dtype=float)
    if ddts.shape != dP.shape:
        raise ValueError(f"ddt must have the shape of dP {dP.shape}; got {ddts.shape}.")
    dus = np.zeros(P.size)
    if ubar is not None:
        ub = np.ascontiguousarray(ubar, dtype=float)
        if ub.shape != P.shape or not np.all(np.isfinite(ub)):
            raise ValueError(f"ubar must hold one finite displacement [m] per step ({P.size}); got shape {ub.shape}.")
        dus = np.diff(ub, prepend=ub[:1])  # the change over each step (none in the first), as solve_tangential
    ddus = np.zeros(dP.shape)
    if dubar is not None:
        du = np.ascontiguousarray(dubar, dtype=float)
        if du.shape != dP.shape:
            raise ValueError(f"dubar must have the shape of dP {dP.shape}; got {du.shape}.")
        ddus = np.ascontiguousarray(np.diff(du, axis=0, prepend=du[:1]))
    decay = float(m.friction_decay)
    work, dwork, Q, dQ, status = _march_tangent(
        P, a, shape, dP, da, dshape, has, xi, Mom, mu, ws, _basis_workspace(nn), _basis_workspace(nn), compliance(m), delta, M,
        float(speed), dts, gds, ddts, float(m.creepage), float(m.friction_dynamic), float(m.friction_static), float(m.half_width),
        cl, float(closure_scale), report_rigid_compliance(m), int(max_iter if decay == 0 else max(max_iter, 2000)), table, dus,
        ddus, decay)
    if int(status[0]) != 0:
        raise ContactError(f"the tangent march failed at step {int(status[1])} (code {int(status[0])}).")
    return (work, dwork, Q, dQ) if force else (work, dwork)
