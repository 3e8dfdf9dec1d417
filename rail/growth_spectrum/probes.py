"""The probes of the growth-rate spectrum (method 'probe', the reference): a line's wear rate from
nonlinear marches with and without a small roughness, the 2 x 2 operator of a line locked to the
supports, the operator within a Bloch class; and the spectrum's result, RateSpectrum.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import chain
from ..scenario import Scenario

__all__ = ["GridMismatch", "batches", "wear_rates", "probe_rates", "RateSpectrum", "locked_operator", "locked_matrix", "smooth_roughness",
           "sorted_eigenvalues", "class_operator"]


class GridMismatch(RuntimeError):
    """The contact grid of a probe differs from the smooth rail's (method 'linear' needs one grid);
    rate_spectrum then takes the probes for that grid phase."""


def batches(lines, N: int):
    """Split lines into batches with at most one line per pair of classes {r, N - r}.

    Parameters
    ----------
    lines : sequence of int
        The lines j [-] (repeats dropped).
    N : int
        Bays of the roughness period [-]; line j is of the class j mod N.

    Returns
    -------
    list of list of int
        The batches of lines [-], in the lines' order.
    """
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
    return probe_rates(scn, table, lines, eps, Z0, W0, grid_phase)


def probe_rates(scn, table, lines, eps, Z0, W0, grid_phase, sidebands=False, progress=None):
    """R_j at the lines about the reference Z0, whose wear W0 on the same grid is given; with
    sidebands, also the largest abs(wear at j +- N) / abs(wear at j) (the same class, probed by j alone).

    Parameters
    ----------
    scn : Scenario
        With roughness.bays = N.
    table : MovingReceptance or tuple of MovingReceptance
        The receptance table(s) at the speed [m/N].
    lines : sequence of int
        The lines j [-], 1 <= j <= N K.
    eps : float
        Amplitude of the probing cosine [m].
    Z0 : ndarray, complex, (2 N K + 1,)
        The reference roughness coefficients [m].
    W0 : ndarray, complex, (2 N K + 1,)
        The reference's wear coefficients per train passage [m] on the same grid.
    grid_phase : float
        Contact grid phase [-], in [0, 1).
    sidebands : bool
        Also return the sideband ratios.
    progress : callable, optional
        progress(), if given, is called after each batch's march.

    Returns
    -------
    R : ndarray, complex, (len(lines),)
        R_j [1 per train passage]: Delta W_j / (eps / 2).
    side : ndarray, (len(lines),)
        With sidebands only: the largest sideband wear over the wear at j [-].
    """
    J = len(Z0) // 2
    N = scn.roughness.bays
    rates, side = {}, {}
    for batch in batches(lines, N):
        Z = Z0.copy()
        for j in batch:
            Z[J + j] += eps / 2
            Z[J - j] += eps / 2
        W, _ = chain.train_wear(scn, table, Z, grid_phase)
        for j in batch:
            rates[j] = (W[J + j] - W0[J + j]) / (eps / 2)
            near = [J + j + m for m in (-N, N) if abs(j + m) <= J]
            side[j] = max(abs(W[i] - W0[i]) for i in near) / max(abs(W[J + j] - W0[J + j]), 1e-300) if near else 0.0
        if progress is not None:
            progress()
    R = np.array([rates[j] for j in lines])
    return (R, np.array([side[j] for j in lines])) if sidebands else R


@dataclass(frozen=True)
class RateSpectrum:
    """The linearised growth-rate spectrum of one train at one speed about the smooth rail (rate_spectrum).

    Attributes
    ----------
    wavelength : (n,) wavelengths N L / j of the lines [m], decreasing
    line : (n,) the lines j (wavenumbers 2 pi j / (N L)) [-]
    locked : (n,) 0 for a free line; 1 on the one-bay comb L / k and 2 on the half-comb
                 2 L / (2k + 1), where the wavelength is locked to the supports: a cosine and a sine
                 (peaks over the sleepers or between) grow at different rates
    rate : (n,) complex rate per train passage [-]: at a free line R_j (module docstring), the
                 roughness grows like exp(-R_j n); at a locked line the eigenvalue of the 2 x 2
                 (cosine, sine) wear operator with the faster growth
    rate_other : (n,) the other eigenvalue (at a free line the conjugate of R_j: the same growth)
    source : (n,) wear of the smooth rail at the line, 2 abs(Delta W0_k) per train passage [m]:
                 the supports' parametric source, non-zero only on the comb
    sideband : (n,) at a free line, the largest wear at the sidebands j +- N over the wear at j [-]:
                 the coupling within the class through the supports that the diagonal leaves out
                 (class_operator gives the class's matrix and eigenvalues); 0 at a locked line
    grid_spread : (n,) half the spread of the growth rate -Re(rate) over the contact grids averaged
                 [-]: the size of the grid-tied error of one grid (the mean's is smaller)
    linearity : largest change of the growth rate with the probe doubled (2 eps against eps),
                 relative to the rate, over the lines checked [-]
    eps : amplitude of the probing cosines [m]
    bays : N [-]
    grid_phases : contact grids averaged over [-]
    method : 'linear' (the tangent march) or 'probe'; 'linear, probes at ...' names the grid
                 phases where the probes' contact grid differed from the smooth rail's and the
                 probes of the nonlinear march were taken instead; on a track cell 'cell of N bays: '
                 and the path taken (the tangent, or the cosine and sine probes)
    operator : (n, 2, 2) the (cosine, sine) wear operator per train passage averaged over the grids
                 at the locked lines (its eigenvalues are rate and rate_other), zero at free lines;
                 kept so that operators of several trains can be summed (fleet_rate_spectrum)
    """

    wavelength: np.ndarray
    line: np.ndarray
    locked: np.ndarray
    rate: np.ndarray
    rate_other: np.ndarray
    source: np.ndarray
    grid_spread: np.ndarray
    sideband: np.ndarray
    linearity: float
    eps: float
    bays: int
    grid_phases: int
    method: str = "linear"
    operator: np.ndarray | None = None

    @property
    def growth_rate(self) -> np.ndarray:
        """Relative growth rate of the roughness amplitude per train passage, -Re of the rate [-]
        (> 0: grows; at a locked line that of the faster-growing phase)."""
        return -self.rate.real

    @property
    def drift(self) -> np.ndarray:
        """Phase drift of the roughness per train passage, -Im of the rate [rad]: the profile at the
        line moves along the rail by drift / (2 pi / wavelength) per passage."""
        return -self.rate.imag


def locked_operator(scn: Scenario, table, j: int, eps: float = 1e-9, grid_phase: float = 0.0):
    """The 2 x 2 real wear operator M on (a, b) of a roughness a cos + b sin at line j of an n-bay
    period whose class is its own conjugate (n = 1: the comb; n = 2, j odd: the half-comb), about the
    smooth rail: d(a, b)/dn = -M (a, b) per train passage.

    Parameters
    ----------
    scn : Scenario
        With roughness.bays = n, 1 or 2.
    table : MovingReceptance or tuple of MovingReceptance
        Its tables (fraction 0, and 1/2 for n = 2).
    j : int
        The line: k (n = 1) or 2k + 1 (n = 2) [-].
    eps : float
        Probing amplitude [m].
    grid_phase : float
        Contact grid phase of every evaluation.

    Returns
    -------
    M : ndarray, shape (2, 2)
        [1 per train passage]; column 0: the wear (cosine, sine parts) of a unit cosine, column 1 of
        a unit sine.
    W0 : ndarray
        Wear coefficients of the smooth rail per train passage [m] (the parametric source).
    """
    Z0 = smooth_roughness(scn)
    W0, _ = chain.train_wear(scn, table, Z0, grid_phase)
    return locked_matrix(scn, table, j, eps, grid_phase, Z0, W0), W0


def locked_matrix(scn, table, j, eps, grid_phase, Z0, W0):
    """M of locked_operator, with the smooth rail's wear W0 on the same grid given.

    Parameters
    ----------
    scn : Scenario
    table : MovingReceptance or tuple of MovingReceptance
        The receptance table(s) at the speed [m/N].
    j : int
        The line [-].
    eps : float
        Amplitude of the probing cosine and sine [m].
    grid_phase : float
        Contact grid phase [-], in [0, 1).
    Z0 : ndarray, complex
        The smooth rail's roughness coefficients [m] (smooth_roughness).
    W0 : ndarray, complex
        Its wear coefficients per train passage [m] on the same grid.

    Returns
    -------
    ndarray, (2, 2)
        M [1 per train passage]; column 0: the wear (cosine, sine parts) of a unit cosine, column 1 of
        a unit sine.
    """
    J = len(Z0) // 2
    cols = []
    for c in (1.0, -1j):  # cosine, sine: Z_j = (a - i b) / 2
        Z = Z0.copy()
        Z[J + j] += c * eps / 2
        Z[J - j] += np.conj(c) * eps / 2
        W, _ = chain.train_wear(scn, table, Z, grid_phase)
        D = (W[J + j] - W0[J + j]) / eps  # wear coefficient per unit amplitude: (c - i d) / 2
        cols.append((2 * D.real, -2 * D.imag))
    return np.array(cols).T


def smooth_roughness(scn: Scenario):
    """The smooth rail's roughness coefficients Z_j = 0, j = -N K..N K, over the scenario's period [m].

    Parameters
    ----------
    scn : Scenario
        Its roughness.bays N and harmonics K per bay [-].

    Returns
    -------
    ndarray, complex, (2 N K + 1,)
        Zeros [m].
    """
    return np.zeros(2 * scn.roughness.bays * scn.harmonics + 1, dtype=complex)


def sorted_eigenvalues(M):
    """Eigenvalues of M, the faster-growing (smaller real part) first.

    Parameters
    ----------
    M : array-like, (2, 2)
        A wear operator [1 per train passage] (locked_matrix).

    Returns
    -------
    ndarray, complex, (2,)
        Its eigenvalues [1 per train passage], by increasing real part.
    """
    ev = np.linalg.eigvals(M).astype(complex)
    return ev[np.argsort(ev.real)]


def class_operator(scn: Scenario, table, lines, eps: float = 1e-9, grid_phases: int = 2):
    """The wear operator restricted to lines of one free Bloch class, and its eigenvalues.

    About the smooth rail the classes r = j mod N do not couple, but within a class the supports
    couple each line j to its sidebands j + m N (the wear of a roughness at j has components there:
    up to about 20 % of the line's own near the pinned-pinned frequency, docs/growth-spectrum.md).
    C[i, k] is the wear at lines[i] per unit complex amplitude at lines[k], per train passage, so that
    the class's amplitudes evolve as dZ/dn = -C Z; the diagonal is wear_rates.

    Parameters
    ----------
    scn : Scenario
        With roughness.bays = N.
    table : tuple of MovingReceptance
        The tables of the N-bay period at the speed.
    lines : sequence of int
        Lines of one class r (j = r mod N, r neither 0 nor N/2), of either sign (a negative line is
        the conjugate of a line of the class N - r), abs(j) <= N K.
    eps : float
        Probing amplitude [m].
    grid_phases : int
        Contact grids averaged over (as rate_spectrum: the sideband entries are a few percent of the
        diagonal, so the grid-tied error of one grid, 0.1-0.4 % of abs(R), is several percent of them).

    Returns
    -------
    C : ndarray, shape (n, n), complex
        [1 per train passage].
    eigenvalues : ndarray, shape (n,), complex
        Of C, the faster-growing (smaller real part) first: growth rates -Re, drifts -Im.
    """
    N = scn.roughness.bays
    J = N * scn.harmonics
    lines = [int(j) for j in lines]
    r = {j % N for j in lines}
    if len(r) != 1 or r & {0, N / 2}:
        raise ValueError(f"lines must share one class j mod {N} other than 0 and {N}/2 (those are locked to the "
                         f"supports: locked_operator); got classes {sorted(r)}.")
    if any(j == 0 or abs(j) > J for j in lines):
        raise ValueError(f"lines must lie in [-{J}, {J}] without 0 (N K).")
    if not (np.isfinite(eps) and eps > 0):
        raise ValueError(f"eps = {eps!r} m is not allowed: it must be a finite number > 0.")
    if not (isinstance(grid_phases, (int, np.integer)) and grid_phases >= 1):
        raise ValueError(f"grid_phases = {grid_phases!r} is not allowed: it must be an integer >= 1.")
    Z0 = smooth_roughness(scn)
    idx = J + np.array(lines)
    C = np.zeros((len(lines), len(lines)), dtype=complex)
    for phase in np.arange(grid_phases) / grid_phases:
        W0, _ = chain.train_wear(scn, table, Z0, phase)
        for k, j in enumerate(lines):
            Z = Z0.copy()
            Z[J + j] += eps / 2
            Z[J - j] += eps / 2  # the conjugate, in the class N - r: no effect on this class
            W, _ = chain.train_wear(scn, table, Z, phase)
            C[:, k] += (W[idx] - W0[idx]) / (eps / 2) / grid_phases
    return C, sorted_eigenvalues(C)
