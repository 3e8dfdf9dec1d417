"""The rail head's stationary longitudinal receptances by a direct solution, written without rail.creepage.rail_flexibility.

The free infinite rail's Green's functions in x by residues (Timoshenko beam: w, psi from a force F
and a moment M; axial rod: u from a longitudinal force), and a finite row of 2 n + 1 supports at
x_j = j L, j = -n..n, whose reactions are solved for directly (a dense linear system): no lattice
sum, no Bloch wave, no wavenumber quadrature. With the rail's damping the supports beyond n carry
nothing the load point feels (the tests check the row's length).

Conventions as rail.track: exp(+i omega t), w and F downwards, psi = dw/dx in the Euler-Bernoulli
limit, M conjugate to psi.
"""

import numpy as np


def _stiff(track, omega):
    r = track.rail
    f = 1 + 1j * r.loss_factor * np.sign(omega) if track.damping == "hysteretic" else 1 + 1j * omega * r.damping_time
    return r.youngs_modulus * r.second_moment_of_area * f, r.shear_coefficient * r.shear_modulus * r.area * f, r.youngs_modulus * r.area * f


def beam_green(x, omega, track):
    """(G_wF, G_wM, G_psiF, G_psiM)(x): response at x to a unit load at 0, by residues of the 2 x 2 inverse."""
    EI, kGA, _ = _stiff(track, omega)
    r = track.rail
    rA, rI = r.density * r.area, r.density * r.second_moment_of_area
    a = kGA * EI
    b = -omega**2 * (kGA * rI + rA * EI)
    c = -rA * omega**2 * (kGA - rI * omega**2)
    disc = np.sqrt(b * b - 4 * a * c + 0j)
    s = np.array([(-b + disc) / (2 * a), (-b - disc) / (2 * a)])
    d = np.array([1 / (s[0] - s[1]), 1 / (s[1] - s[0])]) / a
    p = np.sqrt(s + 0j)
    p = np.where(p.imag < 0, -p, p)
    x = np.asarray(x, dtype=float)
    ax, sg = np.abs(x)[..., None], np.sign(x)[..., None]
    E = np.exp(1j * p * ax)
    even = 1j * E / (2 * p)  # (1/2pi) int e^{-i b x} / (b^2 - s) db
    odd = -sg * E / 2  # (1/2pi) int (-i b) e^{-i b x} / (b^2 - s) db
    GwF = np.sum(d * (EI * s + kGA - rI * omega**2) * even, axis=-1)
    GpM = np.sum(d * (kGA * s - rA * omega**2) * even, axis=-1)
    GpF = np.sum(d * kGA * odd, axis=-1)  # -i b kGA / det
    GwM = -GpF  # i b kGA / det
    return GwF, GwM, GpF, GpM


def dpsi_green(x, omega, track):
    """d psi / dx at x per unit force at 0: -(kGA / 2) sum_j d_j i p_j exp(i p_j abs(x)), continuous at 0."""
    EI, kGA, _ = _stiff(track, omega)
    r = track.rail
    rA, rI = r.density * r.area, r.density * r.second_moment_of_area
    a = kGA * EI
    b = -omega**2 * (kGA * rI + rA * EI)
    c = -rA * omega**2 * (kGA - rI * omega**2)
    disc = np.sqrt(b * b - 4 * a * c + 0j)
    s = np.array([(-b + disc) / (2 * a), (-b - disc) / (2 * a)])
    d = np.array([1 / (s[0] - s[1]), 1 / (s[1] - s[0])]) / a
    p = np.sqrt(s + 0j)
    p = np.where(p.imag < 0, -p, p)
    ax = np.abs(np.asarray(x, dtype=float))[..., None]
    return np.sum(-kGA * d * 1j * p * np.exp(1j * p * ax) / 2, axis=-1)


def rod_green(x, omega, track):
    """u(x) of the free rod per unit longitudinal force at 0."""
    _, _, EA = _stiff(track, omega)
    r = track.rail
    p = np.sqrt(r.density * r.area * omega**2 / EA + 0j)
    p = p if p.imag >= 0 else -p
    return 1j * np.exp(1j * p * np.abs(np.asarray(x, dtype=float))) / (2 * p * EA)


def _support(track, omega):
    def k(k0, eta, c):
        return k0 * (1 + 1j * eta * np.sign(omega)) if track.damping == "hysteretic" else k0 + 1j * omega * c
    kp = k(track.pad.stiffness, track.pad.loss_factor, track.pad.viscous_damping)
    kb = k(track.ballast.stiffness, track.ballast.loss_factor, track.ballast.viscous_damping) - track.sleeper.mass * omega**2
    return kp * kb / (kp + kb)


def stationary_beam(x0, omega, track, n=200):
    """(psi/F, psi/M, w/M, dpsi/dx / F) at the load point x0 [m from a support] of the rail on 2n+1 supports."""
    xs = np.arange(-n, n + 1) * track.L
    Ks = _support(track, omega)
    G = beam_green(xs[:, None] - xs[None, :], omega, track)[0]
    Aeq = np.eye(xs.size) / Ks + G  # R_j / K + sum_l G(x_j - x_l) R_l = w_load(x_j)
    out = []
    for load in (0, 1):  # F, M
        rhs = beam_green(xs - x0, omega, track)[load]  # w at the supports from the load
        R = np.linalg.solve(Aeq, rhs)
        Gl = beam_green(np.array([0.0]), omega, track)
        Gs = beam_green(x0 - xs, omega, track)
        psi = Gl[2 + load][0] - Gs[2] @ R  # psi at x0: free + reactions (upwards)
        out.append(psi)
        if load == 1:
            out.append(Gl[1][0] - Gs[0] @ R)  # w at x0 from M
        else:
            dpsi = dpsi_green(0.0, omega, track) - dpsi_green(x0 - xs, omega, track) @ R
    return tuple(out) + (dpsi,)


def stationary_rod(x0, omega, track, kx, eta_x, n=400):
    """u at the load point x0 per unit longitudinal force, the rod on 2n+1 longitudinal springs."""
    xs = np.arange(-n, n + 1) * track.L
    K = kx * (1 + 1j * eta_x * np.sign(omega))
    Aeq = np.eye(xs.size) / K + rod_green(xs[:, None] - xs[None, :], omega, track)
    R = np.linalg.solve(Aeq, rod_green(xs - x0, omega, track))
    return rod_green(0.0, omega, track) - rod_green(x0 - xs, omega, track) @ R


# --------------------------------------------------------------------------------------------------
# uneven supports: a finite row of a track cell's attachments (issue 55, rail.creepage.rail_flexibility_cell)


def _spring(k0, eta, c, omega, damping):
    return k0 * (1 + 1j * eta * np.sign(omega)) if damping == "hysteretic" else k0 + 1j * omega * c


def cell_row(cell, omega, cells):
    """Positions [m] and dynamic stiffnesses [N/m] of the cell's attachments over 2 cells + 1 periods: the
    vertical ones (every support: pad in series with the sleeper on its ballast; every damper: its spring in
    series with its mass) and the longitudinal ones of rail.creepage.rail_flexibility_cell's model written out here again (each
    support's pad sheared, k_x scaled by the support's pad factor, the sleeper held; no damper)."""
    d = cell.track.damping
    vert_x, vert_k, sup_x, sup_f = [], [], [], []
    for m in range(-cells, cells + 1):
        for s in cell.supports:
            kp = _spring(s.pad.stiffness, s.pad.loss_factor, s.pad.viscous_damping, omega, d)
            kb = _spring(s.ballast.stiffness, s.ballast.loss_factor, s.ballast.viscous_damping, omega, d) - s.sleeper_mass * omega**2
            vert_x.append(s.position + m * cell.period)
            vert_k.append(kp * kb / (kp + kb))
            sup_x.append(s.position + m * cell.period)
            sup_f.append(s.pad.stiffness / cell.track.pad.stiffness)
        for dm in cell.dampers:
            kd = _spring(dm.stiffness, dm.loss_factor, dm.viscous_damping, omega, d)
            vert_x.append(dm.position + m * cell.period)
            vert_k.append(kd * (-dm.mass * omega**2) / (kd - dm.mass * omega**2))
    return np.array(vert_x), np.array(vert_k), np.array(sup_x), np.array(sup_f)


def stationary_beam_row(x0, omega, track, xs, Ks):
    """(psi/F, psi/M) at the load point x0 [m] of the rail on point attachments at xs of stiffnesses Ks."""
    G = beam_green(xs[:, None] - xs[None, :], omega, track)[0]
    Aeq = np.diag(1 / Ks) + G
    Gl = beam_green(np.array([0.0]), omega, track)
    Gs = beam_green(x0 - xs, omega, track)
    out = []
    for load in (0, 1):  # F, M
        R = np.linalg.solve(Aeq, beam_green(xs - x0, omega, track)[load])
        out.append(Gl[2 + load][0] - Gs[2] @ R)
    return tuple(out)


def stationary_rod_row(x0, omega, track, xs, Kx):
    """u at the load point x0 per unit longitudinal force, the rod on longitudinal springs Kx at xs."""
    Aeq = np.diag(1 / Kx) + rod_green(xs[:, None] - xs[None, :], omega, track)
    R = np.linalg.solve(Aeq, rod_green(xs - x0, omega, track))
    return rod_green(0.0, omega, track) - rod_green(x0 - xs, omega, track) @ R


def stationary_beam_rotational(x0, omega, track, k_theta, n=150):
    """(w/F, psi/F, psi/M) at the load point x0 [m from a support] of the rail on 2n+1 supports that each hold
    the rail by the vertical support K_s and by a moment spring k_theta (complex [N m/rad], on psi; the sleeper
    held in rotation): reactions R_j (force) and T_j (moment) from one dense system,
    R_i / K_s + sum_j (G_wF R_j + G_wM T_j)(x_i - x_j) = w_load(x_i), T_i / k_theta + sum_j (G_psiF R_j + G_psiM T_j) = psi_load(x_i)."""
    xs = np.arange(-n, n + 1) * track.L
    N = xs.size
    Ks = _support(track, omega)
    GwF, GwM, GpF, GpM = beam_green(xs[:, None] - xs[None, :], omega, track)
    Aeq = np.block([[np.eye(N) / Ks + GwF, GwM], [GpF, np.eye(N) / k_theta + GpM]])
    at_load = beam_green(np.array([0.0]), omega, track)
    from_load = beam_green(xs - x0, omega, track)  # at the supports, from the load at x0
    to_load = beam_green(x0 - xs, omega, track)  # at x0, from the supports
    out = []
    for load, resp in ((0, 0), (0, 2), (1, 3)):  # (F -> w), (F -> psi), (M -> psi)
        rhs = np.concatenate([from_load[load], from_load[2 + load]])
        RT = np.linalg.solve(Aeq, rhs)
        R, T = RT[:N], RT[N:]
        if resp == 0:
            out.append(at_load[load][0] - to_load[0] @ R - to_load[1] @ T)
        else:
            out.append(at_load[2 + load][0] - to_load[2] @ R - to_load[3] @ T)
    return tuple(out)


def stationary_beam_rows(x0s, omega, track, xs, Ks):
    """``stationary_beam_row`` at many load points x0s [m] at once (one system, a right-hand side per point):
    (psi/F, psi/M) arrays of x0s' shape. At an attachment (x0 in xs) psi/F takes the mean of its two sides."""
    x0s = np.asarray(x0s, dtype=float)
    G = beam_green(xs[:, None] - xs[None, :], omega, track)[0]
    lu = np.diag(1 / Ks) + G
    Gl = beam_green(np.array([0.0]), omega, track)
    Gs = beam_green(x0s[None, :] - xs[:, None], omega, track)  # (n, M): at x0 per unit force at xs
    out = []
    for load in (0, 1):  # F, M
        R = np.linalg.solve(lu, beam_green(xs[:, None] - x0s[None, :], omega, track)[load])  # (n, M)
        out.append(Gl[2 + load][0] - np.sum(Gs[2] * R, axis=0))
    return tuple(out)


def stationary_rod_rows(x0s, omega, track, xs, Kx):
    """``stationary_rod_row`` at many load points x0s [m] at once."""
    x0s = np.asarray(x0s, dtype=float)
    Aeq = np.diag(1 / Kx) + rod_green(xs[:, None] - xs[None, :], omega, track)
    R = np.linalg.solve(Aeq, rod_green(xs[:, None] - x0s[None, :], omega, track))
    return rod_green(0.0, omega, track) - np.sum(rod_green(x0s[None, :] - xs[:, None], omega, track) * R, axis=0)
