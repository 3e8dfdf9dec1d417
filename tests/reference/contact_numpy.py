"""The numpy implementation of the unsteady tangential contact time stepping, kept as a reference.

This is ``rail.contact.solve_tangential`` as it was before its time loop was compiled with numba
(commit 2b10166; verified there against Carter, the energy balance, the quasi-static limit and
the perturbation test), brought up to the current scheme of the compiled loop (``_march``):

* leading-edge entry: every loaded node n with xi_n + Delta >= a(t - dt) holds a particle that
  entered the patch during the step (possibly two per step), at the fraction theta of the step
  where its path meets the edge (eta = xi / a linear in time). It has stuck since, from the edge
  displacement at the entry time, interpolated between the steps:
  u_n(t) = theta u_a(t) + (1 - theta) u_a(t - dt) - gamma (1 - theta) Delta (its row divided by
  1 - theta); its slip velocity is taken over the loaded time (1 - theta) dt;
* frictional work: the pressure part of the traction integrated exactly along the particle path
  over the Hertz ellipse, the deviation from it by the trapezoidal rule over the loaded time;
  particles that left the patch at -a during the step are counted in that step, with their mean
  slip velocity from the displacement at -a interpolated in time (the mirror image of the entry).
* several contact zones (a pressure that is 0 at nodes inside the ellipse, rail.contact.normal.multizone_contact):
  a particle in a gap carries no traction and does no work; one that re-enters a zone is a regular
  particle (its stick row continues its own displacement through the gap); one that leaves a zone into
  a gap gets its mean slip velocity over the step along its path, (u_n(t) - u_{n+1}(t - dt)) / dt + V gamma;
* the traction basis: q = W sum_n g_n phi_n with W = sqrt(1 - zeta^2 / a^2), g_n = q_n / W(xi_n) (the
  outermost phi constant 1 up to the edges). Its influence coefficients come from the compiled
  ``rail.contact._basis_matrix`` (the one routine of the scheme shared with the loop; it is checked
  against brute-force quadrature in tests/test_contact_basis.py); the closure terms are applied here.

``tests/test_contact_kernel.py`` checks the compiled loop against it step by step, so that a
change in either shows. Same scheme, same arguments, same result; only slower.
"""

import numpy as np

from rail.contact import (
    CHECKERBOARD_LIMIT,
    THETA_EDGE,
    ContactError,
    ContactMaterial,
    TangentialSolution,
    _basis_matrix,
    _basis_workspace,
    checkerboard_measure,
    chebyshev_hat_moments,
    compliance,
    hertz_pressure,
)


# False: the particle that leaves a zone into an interior gap takes the trailing edge's displacement (the
# scheme before several zones; tests/test_multizone.py shows the error it makes)
GAP_EXIT_ALONG_PATH = True


def solve_tangential_numpy(P, a, m: ContactMaterial, speed: float, delta: float, M: int, closure: str = "default",
                     closure_scale: float = 1.0, q0=None, max_iter: int = 200, shape=None) -> TangentialSolution:
    """rail.contact.solve_tangential in numpy: same arguments, same scheme, same result."""
    P = np.asarray(P, dtype=float)
    shape = np.ones((P.size, 2 * M + 1)) if shape is None else np.asarray(shape, dtype=float)
    a = np.asarray(a, dtype=float)
    if np.any(a >= M * delta):
        raise ValueError(f"the patch half-length {a.max():.4g} m exceeds the grid's {M * delta:.4g} m.")
    nn = 2 * M + 1
    xi = (np.arange(nn) - M) * delta
    k = compliance(m)
    Mom, mu = chebyshev_hat_moments(nn)
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
    col_w = np.full(nn, delta)  # int psi_n (updated with the basis each step)

    def full_matrix(ai):
        """Influence matrix of the closure at half-length ai, and its rows at xi = +a and xi = -a.

        The square-root-weighted basis psi_n = W phi_n / W(xi_n) (rail.contact._basis_matrix, shared with
        the compiled loop and checked against brute-force quadrature in tests/test_contact_basis.py):
        int psi_n ln|x_r - zeta| in units of the spacing, at the nodes, the leading neighbour and +a."""
        AT = np.empty((nn, nn + 1))
        r_a = np.empty(nn)
        wu = np.empty(nn)
        _basis_matrix(ai, delta, M, Mom, mu, AT, r_a, wu, _basis_workspace(nn))
        w = delta * wu
        col_w[:] = w
        Bm = -k * delta * AT.T
        if closure == "default":
            rigid = k * np.log(0.5 * ai * np.exp(2 * closure_scale / np.pi)) * w
        else:
            # report: + k int q ln|zeta| + q(0)/sigma, sigma from eq 33 = pi E / (8 (1 - nu^2) a)
            rigid = -(Bm[M, :] - k * np.log(delta) * w)
            rigid[M] += closure_scale * 8 * (1 - m.poisson_ratio**2) * ai / (np.pi * m.youngs_modulus)
        C = Bm - k * np.log(delta) * w[None, :] + rigid[None, :]
        r_edge = -k * delta * r_a - k * np.log(delta) * w + rigid
        return C, r_edge, r_edge[::-1].copy()  # the grid, the basis and the rigid term are symmetric

    def ellipse_area(eta):
        """F(eta) = int_0^eta sqrt(1 - t^2) dt, eta clipped to [-1, 1] (0 outside the patch)."""
        e = np.clip(eta, -1.0, 1.0)
        return 0.5 * (e * np.sqrt(np.clip(1.0 - e * e, 0.0, None)) + np.arcsin(e))

    sg = float(np.sign(g))  # slip direction of a particle entering in slip is -sg
    C, r_edge, r_trail = full_matrix(a[0])
    u_old = C @ q  # displacement of every particle (and of the leading neighbour) at the last step
    u_edge_old = r_edge @ q  # surface displacement at xi = +a and -a at the last step
    u_trail_old = r_trail @ q
    a_prev = a[0]
    p_prev = hertz_pressure(xi, P[0], a[0], m) * shape[0]
    p0_prev = P[0] / (np.pi * a[0] * m.half_width)
    stick_prev = np.zeros(nn, dtype=bool)
    sign_prev = np.full(nn, -sg)
    total_iter = 0
    for i in range(steps):
        ai = a[i]
        C, r_edge, r_trail = full_matrix(ai)
        p = hertz_pressure(xi, P[i], ai, m) * shape[i]
        p0 = P[i] / (np.pi * ai * m.half_width)
        inside = p > 0
        inside_prev = p_prev > 0
        # The particle now at node n was at xi_{n+1} one step before; eta = xi / a is linear in time
        # between the steps, from eta0 (at t - dt) to eta1 (at t).
        eta0 = (xi + delta) / a_prev
        eta1 = xi / ai
        # stick equations: E q = h. Regular particle n: u_n(t) = u_{n+1}(t - dt) - gamma Delta.
        # Entering particle (loaded now, at or beyond the leading edge a(t - dt) one step before):
        # its path meets the edge eta = 1 at t_e = t - (1 - theta) dt; it has stuck since, from the
        # edge displacement at t_e interpolated between the steps:
        #     u_n(t) = theta u_a(t) + (1 - theta) u_a(t - dt) - gamma (1 - theta) Delta,
        # as the row (E_n - theta r_a) / (1 - theta) q = u_a(t - dt) - gamma Delta.
        enter = inside & (xi + delta >= a_prev)
        theta = np.zeros(nn)
        theta[enter] = np.clip((eta0[enter] - 1.0) / (eta0[enter] - eta1[enter]), 0.0, 1.0)
        # a particle that reaches the edge within THETA_EDGE dt of the end of the step counts as
        # not yet loaded (its pressure is below 2e-5 p0); it enters in the next step
        at_edge = enter & (1.0 - theta < THETA_EDGE)
        inside = inside & ~at_edge
        p = np.where(at_edge, 0.0, p)
        enter = enter & ~at_edge
        E = C[:nn].copy()
        E[enter] = (E[enter] - theta[enter, None] * r_edge[None, :]) / np.maximum(1.0 - theta[enter], 1e-300)[:, None]
        h = u_old[1:] - g * delta
        h[enter] = u_edge_old - g * delta
        stick = np.zeros(nn, dtype=bool)
        stick[:-1] = stick_prev[1:]
        stick[enter] = True
        stick &= inside
        sign = np.empty(nn)  # direction of q in slip, carried by the particles
        sign[:-1] = sign_prev[1:]
        sign[-1] = -sg
        sign[enter & (sign == 0)] = -sg
        qn = np.zeros(nn)
        for it in range(max_iter):
            slip = inside & ~stick
            qn[:] = 0.0
            qn[slip] = mu_d * p[slip] * sign[slip]
            if stick.any():
                S = np.where(stick)[0]
                rhs = h[S] - E[np.ix_(S, np.where(slip)[0])] @ qn[slip]
                qn[S] = np.linalg.solve(E[np.ix_(S, S)], rhs)
            # slip velocity: s = V gamma + (E q - h) / dt  (exact along the particle path); for an
            # entering particle, over its loaded time (1 - theta) dt since it crossed the edge
            Eq = E @ qn
            s = g * speed + (Eq - h - g * delta) / dt
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
            raise ContactError(f"the stick/slip iteration did not converge at step {i} (a = {ai:.4g} m).")
        total_iter += it + 1
        if not np.all(np.isfinite(qn)):
            raise ContactError(f"the tangential traction is not finite at step {i} (a = {ai:.4g} m, P = {P[i]:.4g} N).")
        s[stick] = 0.0
        stick_count[i] = int(np.count_nonzero(stick & inside))
        if closure == "report" and i > nn and P[i] > 0:
            cb = checkerboard_measure(qn, stick & inside, p0, mu_d)
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

        # Frictional work in this step on the particle now at node n (particle index i + n), J/m^2:
        # |s_bar int q dt| with s_bar its mean slip velocity over the time it was loaded in the step.
        # was: loaded one step before (at xi_{n+1}); the particle at the last node comes from outside.
        was = np.zeros(nn, dtype=bool)
        was[:-1] = inside_prev[1:]
        q_old = np.zeros(nn)
        q_old[:-1] = q[1:]
        q_old[~was] = 0.0
        p_old = np.zeros(nn)
        p_old[:-1] = p_prev[1:]
        # Particles that left the patch at -a during the step, after phi dt (eta linear in time): their
        # mean slip velocity from the displacement at -a at that time, interpolated between the steps.
        u_trail_new = r_trail @ qn
        left = was & ~inside
        phi_all = np.zeros(nn)
        phi_all[left] = np.clip((eta0[left] + 1.0) / (eta0[left] - eta1[left]), 0.0, 1.0)
        left = left & (phi_all >= THETA_EDGE)  # left at the start of the step: no loaded time, no work
        phi = phi_all[left]
        u_exit = (1.0 - phi) * u_trail_old + phi * u_trail_new
        s_exit = np.zeros(nn)
        s_exit[left] = g * speed + (u_exit - u_old[1:][left]) / (phi * dt)
        # a particle that left a contact zone inside the patch into a gap (several zones): its mean slip
        # velocity over the step along its path
        gap_exit = was & ~inside & (1.0 - eta1**2 > 0.0) & GAP_EXIT_ALONG_PATH  # ellipse loaded, pressure 0
        u_new = C @ qn
        s_exit[gap_exit] = g * speed + (u_new[:nn][gap_exit] - u_old[1:][gap_exit]) / dt
        # mean slip velocity and traction direction sigma (from the new traction, else the old one)
        s_bar = np.where(inside, s, s_exit)
        ref = np.where(inside & (qn != 0), qn, q_old)
        counted = (inside | was) & (s_bar != 0) & (ref != 0)  # not stuck over the step, and loaded
        sig = np.where(ref > 0, 1.0, -1.0)
        # q = sigma mu_d p + d. Pressure part: exact along the path for the Hertz ellipse,
        # int p dt = p0m dt (F(eta0) - F(eta1)) / (eta0 - eta1), p0m the mean of the two steps' p0,
        # clipped to the patch by F; the deviation d (0 in slip) by the trapezoidal rule over the
        # loaded time dt (min(eta0, 1) - max(eta1, -1)) / (eta0 - eta1).
        e0, e1 = eta0[counted], eta1[counted]
        span = e0 - e1
        p0m = 0.5 * (p0_prev + p0)
        # non-Hertzian pressure (ellipse x shape): the shape's mean at the particle's two positions
        f_prev = shape[max(i - 1, 0)]
        fm = np.append(0.5 * (f_prev[1:] + shape[i][:-1]), shape[i][-1])[counted]
        int_p = fm * p0m * dt * (ellipse_area(e0) - ellipse_area(e1)) / span
        loaded = np.maximum(dt * (np.minimum(e0, 1.0) - np.maximum(e1, -1.0)) / span, 0.0)
        sc = sig[counted]
        d_new = np.where(inside[counted], qn[counted] - sc * mu_d * p[counted], 0.0)
        d_old = np.where(was[counted], q_old[counted] - sc * mu_d * p_old[counted], 0.0)
        dw = np.zeros(nn)
        dw[counted] = np.abs(s_bar[counted] * (sc * mu_d * int_p + 0.5 * (d_old + d_new) * loaded))
        work[i : i + nn] += dw
        power[i] = dw.sum() * delta / dt

        q = qn
        u_old = C @ qn
        u_edge_old = r_edge @ qn
        u_trail_old = u_trail_new
        a_prev, p_prev, p0_prev = ai, p, p0
        stick_prev = stick
        sign_prev = np.where(stick, np.sign(qn), sign)
    return TangentialSolution(q_hist, s_hist, xi, a, P, Q_hist, work, power, delta, total_iter, stick_count)
