"""The numpy implementation of the unsteady tangential contact time stepping, kept as a reference.

This is ``rail.contact.solve_tangential`` as it was before its time loop was compiled with numba
(commit 2b10166; verified there against Carter, the energy balance, the quasi-static limit and
the perturbation test). ``tests/test_contact.py`` checks the compiled loop against it step by step,
so that a change in either shows. Same scheme, same arguments, same result; only slower.
"""

import numpy as np

from rail.contact import (
    CHECKERBOARD_LIMIT,
    ContactError,
    ContactMaterial,
    TangentialSolution,
    _half_hat,
    _half_hat_scalar,
    _log_hat,
    checkerboard_measure,
    compliance,
    hertz_pressure,
    influence_matrix,
)


def solve_tangential_numpy(P, a, m: ContactMaterial, speed: float, delta: float, M: int, closure: str = "default",
                     closure_scale: float = 1.0, q0=None, max_iter: int = 200) -> TangentialSolution:
    """rail.contact.solve_tangential in numpy: same arguments, same scheme, same result."""
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
