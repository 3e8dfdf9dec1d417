"""Independent reference for the transfer receptances (d != 0): the moving-load integrals with the
oscillating factor exp(-i beta d) resolved node by node by the adaptive Gauss rule itself (the
method rail.moving used before the Filon weights; slow and memory-hungry for far offsets, which is
why it is only a test reference)."""

import numpy as np

from rail import moving
from rail.quadrature import adaptive_panels


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
            G, w, dfac = moving._node_tables(beta, 0.0, V, js, track, 0)
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
