"""Independent reference for the transfer receptances (d != 0): the moving-load integrals with the
oscillating factor exp(-i beta d) resolved node by node by the adaptive Gauss rule itself (the
method rail.moving used before the Filon weights; slow and memory-hungry for far offsets, which is
why it is only a test reference)."""

import numpy as np
from scipy import special

from rail import moving
from rail.quadrature import adaptive_panels
from rail.track import free_receptance, periodic_sum, rail_stiffnesses, support_stiffness


# The uniform track's node tables as rail.moving computed them before the cell of N bays (kept here
# unchanged, so that the reference does not share the production code's node tables).
def _static_tail(beta, omega, track, M):
    """sum over |m| > M of the quasi-static H_0(beta + m beta0) = 1/(EI b^4) + 1/(kGA b^2), via polygamma."""
    EI, kGA = rail_stiffnesses(track, omega)
    b0 = track.beta0
    a = beta / b0
    s2 = (special.polygamma(1, M + 1 + a) + special.polygamma(1, M + 1 - a)) / b0**2
    s4 = (special.polygamma(3, M + 1 + a) + special.polygamma(3, M + 1 - a)) / (6 * b0**4)
    return s4 / EI + s2 / kGA


def _sum_excluding(beta, omega, m_star, track, M=40):
    """sum over m != m_star of H(beta + m beta0, omega), by explicit summation and a static tail.

    Used near the static point, where the closed-form periodic sum would lose every digit
    to the cancellation with the m_star term, which diverges like 1/(EI beta^4).
    """
    b0 = track.beta0
    out = _static_tail(beta + m_star * b0, omega, track, M)
    for m in range(-M, M + 1):
        if m != 0:
            out = out + free_receptance(beta + (m_star + m) * b0, omega, track)
    return out


def _node_tables(beta, Omega, V, js, track, static_j):
    """Columns g_j = H(beta - j beta0, Omega + beta V), support weight parts, and the combined
    diagonal factor at the wavenumber nodes ``beta``.  ``static_j``: index j whose column
    diverges at the static point (None if there is none)."""
    b0, L = track.beta0, track.L
    omega = Omega + beta * V
    G = free_receptance(beta[:, None] - js[None, :] * b0, omega[:, None], track)
    Ks = support_stiffness(track, omega)
    S = np.empty(beta.shape, dtype=complex)
    near = np.zeros(beta.shape, dtype=bool)
    if static_j is not None:
        near = np.abs(beta - static_j * b0) < b0 / 2
    far = ~near
    if far.any():
        S[far] = periodic_sum(beta[far], omega[far], track)
    S_excl = None
    if near.any():
        S_excl = _sum_excluding(beta[near], omega[near], -static_j, track)
        S[near] = S_excl + free_receptance(beta[near] - static_j * b0, omega[near], track)
    denom = L + Ks * S
    # combined diagonal factor (L + K_s (S - g_j)) / (L + K_s S), stable at the static point
    diag_factor = (L + Ks[:, None] * (S[:, None] - G)) / denom[:, None]
    if near.any():
        col = int(np.where(js == static_j)[0][0])
        diag_factor[near, col] = (L + Ks[near] * S_excl) / denom[near]
    w = L * Ks / denom
    return G, w, diag_factor




def transfer_entries(track, V, K, d, columns, rtol=1e-7, order=16, max_panels=100000):
    """The diagonal A_d[k, k] and the columns A_d[:, k] (k in ``columns``, harmonic indices) for
    Bloch fraction 0 and one offset d != 0, with the same cos^2 window as
    rail.moving.receptance_table's default (cut (K + 12) beta0); every entry to rtol of its
    column's scale (the diagonal at d = 0).

    Returns (diag (2K + 1,), cols (2K + 1, len(columns))) [m/N]."""
    b0, L = track.beta0, track.L
    js = np.arange(-K, K + 1)
    n = len(js)
    ci = np.asarray(columns, dtype=int) + K
    cut = (K + 12) * b0
    Bmap = (K + 4) * b0

    def integrand(th):
        out = []
        for lo in range(0, len(th), 8192):
            t = th[lo : lo + 8192]
            beta = Bmap * np.tan(t)
            jac = Bmap / np.cos(t) ** 2
            G, w, dfac = _node_tables(beta, 0.0, V, js, track, 0)
            ph = np.exp(-1j * beta * d) * moving._taper(beta, cut) * jac
            gram = (w * ph)[:, None, None] * G[:, ci][:, :, None] * G[:, None, :]  # (node, k, p)
            gram[:, np.arange(len(ci)), ci] = 0.0  # the diagonal is the combined form (above)
            out.append(np.concatenate([G * dfac * ph[:, None], gram.reshape(len(t), -1)], axis=1))
        return np.concatenate(out)

    # tolerance per entry on the scale of its column k: |A_0[k, k]| (a tight d = 0 table)
    column = np.abs(np.diag(moving.receptance_table(track, V, K, rtol=1e-7).A[0]))
    scale = np.concatenate([2 * np.pi * column, np.repeat(2 * np.pi * L * column[ci], n)])
    edges = moving._edges_theta(Bmap, [0.0], cut)
    q = adaptive_panels(integrand, edges, rtol=rtol, order=order, max_panels=max_panels, scale=scale)
    assert q.converged
    phase = np.exp(1j * js * b0 * d)  # row factor exp(i p beta0 d)
    diag = q.integral[:n] / (2 * np.pi) * phase
    cols = -q.integral[n:].reshape(len(ci), n).T / (2 * np.pi * L) * phase[:, None]
    cols[ci, np.arange(len(ci))] = diag[ci]
    return diag, cols
