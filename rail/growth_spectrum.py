"""The diagonal of the linearised wear feedback: wear of one train passage per unit roughness at a
wavenumber, about a reference roughness (first part of the growth-rate spectrum).

For a roughness periodic over N bays about a reference that is periodic over one bay (the smooth
rail, or any bay-periodic roughness), the linearised wear operator does not couple the Bloch classes
j mod N (the forces split into the classes, rail.interaction.solve_forces, and so does the contact
about a bay-periodic state). A small cosine of amplitude eps at the line j gives the wear
Delta W_j = R_j (eps / 2) + O(eps^2) at that line, with the complex wear rate R_j [per train passage]:

    relative growth rate per train passage   g_j = -Re R_j      (growth where g_j > 0)
    phase drift per train passage            -Im R_j            (the profile moves along the rail)

so that Z_j grows like exp(-R_j n) over n train passages. One wear evaluation over the N bays gives
R_j for one line of every class at once (the classes do not couple); the reference wear is
evaluated on the same contact grid and subtracted, so the grid-tied error cancels. Lines that are
multiples of N (the one-bay comb) also carry the parametric wear of the reference itself; their
R_j is the feedback part only.
"""

from __future__ import annotations

import numpy as np

from . import chain
from .scenario import Scenario

__all__ = ["wear_rates"]


def _batches(lines, N: int):
    """Split lines into batches with at most one line per pair of classes {r, N - r}."""
    pending = list(dict.fromkeys(int(j) for j in lines))
    out = []
    while pending:
        used, batch, rest = set(), [], []
        for j in pending:
            key = min(j % N, (N - j % N) % N)
            if key in used:
                rest.append(j)
            else:
                used.add(key)
                batch.append(j)
        out.append(batch)
        pending = rest
    return out


def wear_rates(scn: Scenario, table, lines, eps: float = 1e-8, reference=None, grid_phase: float = 0.0):
    """Complex wear rate R_j per train passage at the given lines (module docstring).

    Parameters
    ----------
    scn : Scenario
        With roughness.bays = N; the lines j are those of the wavenumbers 2 pi j / (N L).
    table : MovingReceptance or tuple of MovingReceptance
        The scenario's receptance table(s) at the speed (rail.chain.receptance_table).
    lines : sequence of int
        1 <= j <= N K.
    eps : float
        Amplitude of the probing cosine [m]; small enough for the linear range (the test checks
        that eps and 2 eps agree).
    reference : ndarray, optional
        Reference roughness coefficients [m] (default: the smooth rail).
    grid_phase : float
        Contact grid phase (rail.wear.bay_wear) of both evaluations.

    Returns
    -------
    ndarray of complex, shape (len(lines),)
        R_j [1 per train passage]: Delta W_j / (eps / 2).
    """
    N = scn.roughness.bays
    J = N * scn.harmonics
    lines = [int(j) for j in lines]
    if any(not 1 <= j <= J for j in lines):
        raise ValueError(f"lines must lie in [1, {J}] (N K), got {min(lines)}..{max(lines)}.")
    if not (np.isfinite(eps) and eps > 0):
        raise ValueError(f"eps = {eps!r} m is not allowed: it must be a finite number > 0.")
    Z0 = np.zeros(2 * J + 1, dtype=complex) if reference is None else np.asarray(reference, dtype=complex)
    W0, _ = chain.train_wear(scn, table, Z0, grid_phase)
    rates = {}
    for batch in _batches(lines, N):
        Z = Z0.copy()
        for j in batch:
            Z[J + j] += eps / 2
            Z[J - j] += eps / 2
        W, _ = chain.train_wear(scn, table, Z, grid_phase)
        for j in batch:
            rates[j] = (W[J + j] - W0[J + j]) / (eps / 2)
    return np.array([rates[j] for j in lines])
