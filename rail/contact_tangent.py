"""The tangent (linearised) march of the unsteady 2D rolling contact: the derivative of the
frictional work of rail.contact.solve_tangential with respect to its inputs, for many input
directions at once (rail.growth_spectrum's method 'linear').

_march_tangent runs rail.contact._march's scheme on the reference inputs (P, a, shape) and, along
with it, the forward-mode derivative of every step with the reference's stick/slip sets held
(their change is of second order in a small perturbation, as in a probe with a small amplitude):
the stick equations, the entering and leaving particles' interpolation, the slip velocities and
the frictional work (_step_work) are differentiated by hand; the influence matrix's dependence on
a(t) by a central difference of rail.contact._closure_matrix (relative step 1e-9: small enough that
the truncation order of its Chebyshev series rarely changes within it; one-sided where a node
crosses the patch edge within it). The directions are real columns: a complex (Bloch) input
direction is carried as two columns, its real and imaginary parts (every step is real-linear).
tests/test_growth_spectrum.py checks the result against probes of the nonlinear march.
"""

from __future__ import annotations

import math

import numpy as np
from ._lazyjit import njit

from .contact import (CHECKERBOARD_LIMIT, THETA_EDGE, ContactError, ContactMaterial, _basis_workspace, _closure_matrix,
                      _ellipse_area, _march, chebyshev_hat_moments, compliance)

__all__ = ["work_tangent"]

_DA_REL = 1e-9  # relative step of a in the (central) difference of the influence matrix


@njit(cache=True)
def _dF(e):
    """d/d eta of _ellipse_area (0 where eta is clipped)."""
    if e <= -1.0 or e >= 1.0:
        return 0.0
    return math.sqrt(1.0 - e * e)


@njit(cache=True)
def _march_tangent(P, a, shape, dP, da, dshape, has_dshape, xi, Mom, mu, ws, ws2, ws3, k, delta, M, speed, g, mu_d, mu_s,
                   half_width, closure, closure_scale, report_coef, max_iter):
    nn = xi.size
    steps = P.size
    nc = dP.shape[1]
    dt = delta / speed
    sg = 0.0 if g == 0 else (1.0 if g > 0 else -1.0)
    work = np.zeros(steps + nn)
    dwork = np.zeros((steps + nn, nc))
    status = np.zeros(3)
    C = np.empty((nn + 1, nn))
    r_edge = np.empty(nn)
    r_trail = np.empty(nn)
    w = np.empty(nn)
    AT = np.empty((nn, nn + 1))
    r_a = np.empty(nn)
    wu = np.empty(nn)
    # the matrices at a (1 + h), for the derivative
    C2 = np.empty((nn + 1, nn))
    r_edge2 = np.empty(nn)
    r_trail2 = np.empty(nn)
    w2 = np.empty(nn)
    AT2 = np.empty((nn, nn + 1))
    r_a2 = np.empty(nn)
    wu2 = np.empty(nn)
    C3 = np.empty((nn + 1, nn))
    r_edge3 = np.empty(nn)
    r_trail3 = np.empty(nn)
    w3 = np.empty(nn)
    AT3 = np.empty((nn, nn + 1))
    r_a3 = np.empty(nn)
    wu3 = np.empty(nn)
    Cd = np.empty((nn + 1, nn))
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
    sign = np.empty(nn)
    p = np.empty(nn)
    dp = np.zeros((nn, nc))
    h = np.empty(nn)
    dh = np.zeros((nn, nc))
    s = np.empty(nn)
    ds = np.zeros((nn, nc))
    qn = np.zeros(nn)
    dqn = np.zeros((nn, nc))
    theta = np.zeros(nn)
    dtheta = np.zeros((nn, nc))
    enter = np.zeros(nn, dtype=np.bool_)
    s_exit = np.zeros(nn)
    ds_exit = np.zeros((nn, nc))
    dEq = np.zeros((nn, nc))
    a_prev = a[0]
    da_prev = da[0].copy()
    p0_prev = P[0] / (math.pi * a[0] * half_width)
    dp0_prev = p0_prev * (dP[0] / P[0] - da[0] / a[0])
    p_prev = np.zeros(nn)
    dp_prev = np.zeros((nn, nc))
    inside_prev = np.zeros(nn, dtype=np.bool_)
    for n in range(nn):
        rr = 1 - (xi[n] / a[0]) ** 2
        sq = math.sqrt(rr) if rr > 0 else 0.0
        p_prev[n] = p0_prev * sq * shape[0, n]
        inside_prev[n] = p_prev[n] > 0
        if rr > 0:
            dsq = xi[n] ** 2 / a[0] ** 3 / sq
            for c in range(nc):
                dp_prev[n, c] = (dp0_prev[c] * sq + p0_prev * dsq * da[0, c]) * shape[0, n]
                if has_dshape:
                    dp_prev[n, c] += p0_prev * sq * dshape[0, n, c]
    for i in range(steps):
        ai = a[i]
        if ai != a_built:
            lead, _ = _closure_matrix(ai, Mom, mu, xi, k, delta, M, closure, closure_scale, report_coef, C, r_edge, w,
                                      r_trail, AT, r_a, wu, ws)
            # central difference where no node crosses the edge within +-h, else one-sided
            hstep = _DA_REL * ai
            lead2, _ = _closure_matrix(ai + hstep, Mom, mu, xi, k, delta, M, closure, closure_scale, report_coef, C2,
                                       r_edge2, w2, r_trail2, AT2, r_a2, wu2, ws2)
            lead3, _ = _closure_matrix(ai - hstep, Mom, mu, xi, k, delta, M, closure, closure_scale, report_coef, C3,
                                       r_edge3, w3, r_trail3, AT3, r_a3, wu3, ws3)
            if lead2 == lead and lead3 == lead:
                hd = 2 * hstep
            elif lead2 == lead:
                hd = hstep
                C3[:] = C
                r_edge3[:] = r_edge
                r_trail3[:] = r_trail
            else:
                hd = hstep
                C2[:] = C
                r_edge2[:] = r_edge
                r_trail2[:] = r_trail
            for r in range(nn + 1):
                for c in range(nn):
                    Cd[r, c] = (C2[r, c] - C3[r, c]) / hd
            for n in range(nn):
                r_edge_d[n] = (r_edge2[n] - r_edge3[n]) / hd
                r_trail_d[n] = (r_trail2[n] - r_trail3[n]) / hd
            a_built = ai
        dai = da[i]
        E = C[:nn]
        p0 = P[i] / (math.pi * ai * half_width)
        dp0 = p0 * (dP[i] / P[i] - dai / ai)
        for n in range(nn):
            rr = 1 - (xi[n] / ai) ** 2
            sq = math.sqrt(rr) if rr > 0 else 0.0
            p[n] = p0 * sq * shape[i, n]
            inside[n] = p[n] > 0
            if rr > 0:
                dsq = xi[n] ** 2 / ai ** 3 / sq
                for c in range(nc):
                    dp[n, c] = (dp0[c] * sq + p0 * dsq * dai[c]) * shape[i, n]
                    if has_dshape:
                        dp[n, c] += p0 * sq * dshape[i, n, c]
            else:
                for c in range(nc):
                    dp[n, c] = 0.0
        for n in range(nn - 1):
            stick[n] = stick_prev[n + 1]
            sign[n] = sign_prev[n + 1]
        stick[nn - 1] = False
        sign[nn - 1] = -sg
        nent = 0
        for n in range(nn):
            h[n] = u_old[n + 1] - g * delta
            for c in range(nc):
                dh[n, c] = du_old[n + 1, c]
            enter[n] = False
            if inside[n] and xi[n] + delta >= a_prev:
                eta0, eta1 = (xi[n] + delta) / a_prev, xi[n] / ai
                num, den = eta0 - 1.0, eta0 - eta1
                th0 = num / den
                th = min(max(th0, 0.0), 1.0)
                if 1.0 - th < THETA_EDGE:
                    inside[n] = False
                    p[n] = 0.0
                    for c in range(nc):
                        dp[n, c] = 0.0
                    continue
                enter[n] = True
                theta[n] = th
                for c in range(nc):
                    if th0 == th:
                        de0 = -(xi[n] + delta) / a_prev ** 2 * da_prev[c]
                        de1 = -xi[n] / ai ** 2 * dai[c]
                        dtheta[n, c] = (de0 * den - num * (de0 - de1)) / den ** 2
                    else:
                        dtheta[n, c] = 0.0
                inv = 1.0 / max(1.0 - th, 1e-300)
                for c in range(nn):
                    saved[nent, c] = C[n, c]
                    C[n, c] = (C[n, c] - th * r_edge[c]) * inv
                nent += 1
                h[n] = u_edge_old - g * delta
                for c in range(nc):
                    dh[n, c] = du_edge_old[c]
                stick[n] = True
                if sign[n] == 0:
                    sign[n] = -sg
        for n in range(nn):
            stick[n] = stick[n] and inside[n]
        converged = False
        it = 0
        ns = 0
        S = np.empty(nn, dtype=np.int64)
        while it < max_iter:
            ns = 0
            for n in range(nn):
                if inside[n] and not stick[n]:
                    qn[n] = mu_d * p[n] * sign[n]
                else:
                    qn[n] = 0.0
                if stick[n]:
                    S[ns] = n
                    ns += 1
            if ns > 0:
                A = np.empty((ns, ns))
                rhs = np.empty(ns)
                for r in range(ns):
                    acc = h[S[r]]
                    for n in range(nn):
                        if qn[n] != 0.0:
                            acc -= E[S[r], n] * qn[n]
                    rhs[r] = acc
                    for cc in range(ns):
                        A[r, cc] = E[S[r], S[cc]]
                x = np.linalg.solve(A, rhs)
                for r in range(ns):
                    qn[S[r]] = x[r]
            Eq = E @ qn
            for n in range(nn):
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
                elif s[n] * sign[n] > 0:
                    stick[n] = True
                    changed = True
            it += 1
            if not changed:
                converged = True
                break
        if not converged:
            status[0], status[1] = 1, i
            break
        # tangent of the step, with the stick set held: dE q (the rows of entering particles modified)
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
            X = np.linalg.solve(A, B)
            for r in range(ns):
                for c in range(nc):
                    dqn[S[r], c] = X[r, c]
        Edq = E @ dqn
        for n in range(nn):
            if inside[n] and not stick[n]:
                for c in range(nc):
                    ds[n, c] = (dEq[n, c] + Edq[n, c] - dh[n, c]) / dt
            else:
                for c in range(nc):
                    ds[n, c] = 0.0
        j = 0
        for n in range(nn):
            if enter[n]:
                for c in range(nn):
                    C[n, c] = saved[j, c]
                j += 1
        finite = True
        for n in range(nn):
            if not np.isfinite(qn[n]):
                finite = False
        if not finite:
            status[0], status[1] = 2, i
            break
        for n in range(nn):
            if stick[n]:
                s[n] = 0.0
        u_trail_new = np.dot(r_trail, qn)
        du_trail_new = (np.dot(r_trail_d, qn) * dai) + (r_trail @ dqn)
        for n in range(nn - 1):
            s_exit[n] = 0.0
            for c in range(nc):
                ds_exit[n, c] = 0.0
            if inside_prev[n + 1] and not inside[n]:
                eta0, eta1 = xi[n + 1] / a_prev, xi[n] / ai
                num, den = eta0 + 1.0, eta0 - eta1
                phi0 = num / den
                phi = min(max(phi0, 0.0), 1.0)
                if phi < THETA_EDGE:
                    continue
                u_exit = (1.0 - phi) * u_trail_old + phi * u_trail_new
                s_exit[n] = g * speed + (u_exit - u_old[n + 1]) / (phi * dt)
                for c in range(nc):
                    if phi0 == phi:
                        de0 = -xi[n + 1] / a_prev ** 2 * da_prev[c]
                        de1 = -xi[n] / ai ** 2 * dai[c]
                        dphi = (de0 * den - num * (de0 - de1)) / den ** 2
                    else:
                        dphi = 0.0
                    du_exit = (dphi * (u_trail_new - u_trail_old) + (1.0 - phi) * du_trail_old[c] + phi * du_trail_new[c])
                    ds_exit[n, c] = (du_exit - du_old[n + 1, c]) / (phi * dt) - (u_exit - u_old[n + 1]) * dphi / (phi * phi * dt)
        p0m = 0.5 * (p0_prev + p0)
        ip = i - 1 if i > 0 else 0
        for n in range(nn):
            # _step_work and its derivative
            if n < nn - 1:
                fm = 0.5 * (shape[ip, n + 1] + shape[i, n])
            else:
                fm = shape[i, n]
            was = n < nn - 1 and inside_prev[n + 1]
            if not (inside[n] or was):
                continue
            q_old = q[n + 1] if was else 0.0
            if inside[n]:
                sbar = s[n]
                ref = qn[n] if qn[n] != 0.0 else q_old
            else:
                sbar = s_exit[n]
                ref = q_old
            if sbar == 0.0 or ref == 0.0:
                continue
            eta0 = (xi[n] + delta) / a_prev
            eta1 = xi[n] / ai
            span = eta0 - eta1
            Fd = _ellipse_area(eta0) - _ellipse_area(eta1)
            ipw = fm * p0m * dt * Fd / span
            lo = dt * (min(eta0, 1.0) - max(eta1, -1.0)) / span
            loaded = lo if lo > 0.0 else 0.0
            sig = 1.0 if ref > 0 else -1.0
            d_new = qn[n] - sig * mu_d * p[n] if inside[n] else 0.0
            d_old = q_old - sig * mu_d * p_prev[n + 1] if was else 0.0
            Y = sig * mu_d * ipw + 0.5 * (d_old + d_new) * loaded
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
                dY = sig * mu_d * dipw + 0.5 * (dd_old + dd_new) * loaded + 0.5 * (d_old + d_new) * dlo
                dsbar = ds[n, c] if inside[n] else ds_exit[n, c]
                dwork[i + n, c] += sx * (dsbar * Y + sbar * dY)
        # the state
        for n in range(nn):
            q[n] = qn[n]
            p_prev[n] = p[n]
            inside_prev[n] = inside[n]
            for c in range(nc):
                dq[n, c] = dqn[n, c]
                dp_prev[n, c] = dp[n, c]
        u_trail_old = u_trail_new
        du_trail_old[:] = du_trail_new
        a_prev = ai
        da_prev[:] = dai
        p0_prev = p0
        dp0_prev[:] = dp0
        u_edge_old = np.dot(r_edge, qn)
        du_edge_old[:] = np.dot(r_edge_d, qn) * dai + r_edge @ dqn
        u_old = C @ qn
        vC = Cd @ qn
        du_old = C @ dqn
        for r in range(nn + 1):
            for c in range(nc):
                du_old[r, c] += vC[r] * dai[c]
        for n in range(nn):
            stick_prev[n] = stick[n]
            sign_prev[n] = np.sign(qn[n]) if stick[n] else sign[n]
    return work, dwork, status


def work_tangent(P, a, m: ContactMaterial, speed: float, delta: float, M: int, dP, da, dshape=None, closure: str = "default",
                 closure_scale: float = 1.0, shape=None, max_iter: int = 200):
    """The frictional work of solve_tangential from zero traction and its derivative along input directions.

    Parameters
    ----------
    P, a, shape, m, speed, delta, M, closure, closure_scale, max_iter
        As rail.contact.solve_tangential (the reference march).
    dP, da : ndarray, shape (len(P), nc)
        Directions of the force [N] and the half-length [m] at each step (nc real columns).
    dshape : ndarray, shape (len(P), 2M + 1, nc), optional
        Direction of the pressure shape factor (default: none).

    Returns
    -------
    work : ndarray, shape (len(P) + 2M + 1,)
        The reference's work per unit area by particle [J/m^2] (solve_tangential's work).
    dwork : ndarray, shape (len(P) + 2M + 1, nc)
        Its derivative along each column, the stick/slip sets held.
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
    xi = (np.arange(nn) - M) * delta
    Mom, mu = chebyshev_hat_moments(nn)
    report_coef = 8 * (1 - m.poisson_ratio**2) / (np.pi * m.youngs_modulus)
    work, dwork, status = _march_tangent(
        P, a, shape, dP, da, dshape, has, xi, Mom, mu, _basis_workspace(nn), _basis_workspace(nn), _basis_workspace(nn), compliance(m), delta, M,
        float(speed), float(m.creepage), float(m.friction_dynamic), float(m.friction_static), float(m.half_width),
        0 if closure == "default" else 1, float(closure_scale), report_coef, int(max_iter))
    if int(status[0]) != 0:
        raise ContactError(f"the tangent march failed at step {int(status[1])} (code {int(status[0])}).")
    return work, dwork


_ = (_march, CHECKERBOARD_LIMIT)  # the scheme differentiated (rail.contact._march) and its limit, for reference
