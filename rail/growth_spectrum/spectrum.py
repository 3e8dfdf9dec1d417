"""The growth-rate spectrum about the smooth rail (rate_spectrum): free lines, the lines locked to the
supports, grid phases, the linear range; a track cell goes to rail.growth_spectrum.cell."""

from __future__ import annotations

import dataclasses

import numpy as np

from .. import chain
from ..moving import MovingReceptance
from ..scenario import Scenario
from .cell import cell_rate_spectrum
from .linear import linear_rates, probe_roughness, warm_train_wear
from .probes import GridMismatch, RateSpectrum, batches, locked_matrix, probe_rates, smooth_roughness, sorted_eigenvalues

__all__ = ["rate_spectrum", "locked_kinds"]


def rate_spectrum(scn: Scenario, table, lines, eps: float = 1e-9, grid_phases: int = 2,
                  check_lines: int = 4, method: str = "linear", progress=None) -> RateSpectrum:
    """Growth-rate spectrum about the smooth rail at the given lines.

    Free lines by wear_rates (one probing cosine per pair of classes per wear evaluation over the N
    bays; on a track cell, scn.cell, every line as a locked line: cell_rate_spectrum). Lines whose
    class is its own conjugate (the comb, j = k N, and for even N the half-comb, j = (k + 1/2) N)
    couple the roughness at +j and -j through the supports: there the cosine and the sine are probed
    separately on the shortest period that holds the line (1 bay for the comb, 2 for the half-comb;
    the same classes of the same tables) and the eigenvalues of the 2 x 2 operator are given.

    The smooth rail's wear on the same contact grid is subtracted, which removes the grid-tied bias
    of the wear but not that of its derivative: the rate of one grid carries an error that is
    periodic in a / Delta (about 0.1-0.4 % of abs(R) at 61 nodes, docs/growth-spectrum.md). The rates
    are therefore averaged over ``grid_phases`` grids whose a / Delta differ by 1 / grid_phases
    (rail.wear.bay_wear's grid_phase; two phases half a unit apart cancel the fundamental of that
    error), and half the spread between the phases is returned as its estimate.

    Parameters
    ----------
    scn : Scenario
        With roughness.bays = N (the lines' period) and the train's wheels.
    table : tuple of MovingReceptance
        The receptance tables of the N-bay period at the speed (rail.chain.receptance_table).
    lines : sequence of int
        Lines j, 1 <= j <= N K (spectrum_lines).
    eps : float
        Amplitude of the probing cosines [m].
    grid_phases : int
        Contact grids averaged over, >= 1 [-]; the cost is proportional.
    check_lines : int
        Free lines (spread over the range), and the first locked line, probed again with 2 eps to
        measure the linearity [-] (on the first grid).
        None: no check (the result's linearity NaN; rail.growth_spectrum.band.class_pair_spectrum checks
        its first call only).
    method : str
        'linear' (default): every line from one march of the smooth rail over one bay carrying the
        derivative of the contact along every probe (linear_rates, rail.contact.tangent); the
        linearity is then the change of the rate from the derivative to probes of 2 eps. On a track
        cell (scn.cell), one march of the smooth rail over the cell carrying a cosine and a sine
        column for every line (cell_linear_operators).
        'probe': the previous path, each line from the difference of two nonlinear marches over the
        N bays (one line per pair of classes per march, batches; on a cell a cosine and a sine
        march per line), the reference of the tests; about seven times the cost at the default
        resolution (four times on the irregular_voided cell). With the wheelset's dynamic creepage, the
        rail's longitudinal flexibility or falling friction (scn.material.longitudinal, rail_flexibility,
        friction_decay) 'linear' linearises the periodic state with u_bar too (rail.growth_spectrum.creepage:
        per Bloch class on the uniform track, over the cell's harmonics on a track cell).
    progress : callable, optional
        Called with one line of text as the work proceeds ("<i> of <n> probe batches, grid phase
        <p> of <P>"; method 'linear'; on a cell "<i> of <n> probe inputs ..." or, for 'probe',
        "<i> of <n> lines ..."); default None, silent.

    Returns
    -------
    RateSpectrum
    """
    lines, method = _checked_arguments(scn, lines, eps, grid_phases, method)
    if getattr(scn, "cell", None) is not None:
        sp = cell_rate_spectrum(scn, table, lines, eps, grid_phases, method, progress=progress)
        return sp
    N = scn.roughness.bays
    tabs = (table,) if isinstance(table, MovingReceptance) else tuple(table)
    locked = locked_kinds(lines, N)
    free = np.flatnonzero(locked == 0)
    held = np.flatnonzero(locked)
    R = np.zeros((grid_phases, free.size), dtype=complex)
    Ms = np.zeros((grid_phases, held.size, 2, 2))
    source = np.zeros(lines.size)
    sideband = np.zeros(lines.size)
    changes = []
    fallbacks = []  # grid phases where method 'linear' fell back to the probes (GridMismatch)
    for p, phase in enumerate(np.arange(grid_phases) / grid_phases):
        check = None if p else check_lines  # the linear range is measured on the first grid
        found = None
        if method == "linear":
            try:
                found = _linear_phase(scn, tabs, lines, locked, eps, phase, check, _phase_progress(progress, p, grid_phases, lines.size),
                                      progress)
            except GridMismatch as err:  # the probes of the nonlinear march for this grid phase
                fallbacks.append(f"grid phase {phase:g}: {err}")
        if found is None:
            found = _probe_phase(scn, tabs, lines, locked, eps, phase, check, _probe_progress(progress, p, grid_phases, lines.size))
        R[p], side_p, Ms[p], source_p, changes_p = found
        sideband[free] = np.maximum(sideband[free], side_p)
        source += source_p / grid_phases
        changes += changes_p
    rate = np.zeros(lines.size, dtype=complex)
    other = np.zeros(lines.size, dtype=complex)
    spread = np.zeros(lines.size)
    rate[free] = R.mean(axis=0)
    other[free] = np.conj(rate[free])
    spread[free] = np.ptp(R.real, axis=0) / 2
    operator = np.zeros((lines.size, 2, 2))
    for n, idx in enumerate(held):
        operator[idx] = Ms[:, n].mean(axis=0)
        rate[idx], other[idx] = sorted_eigenvalues(operator[idx])
        g = [sorted_eigenvalues(M)[0].real for M in Ms[:, n]]
        spread[idx] = np.ptp(g) / 2
    return RateSpectrum(wavelength=N * scn.L / lines, line=lines, locked=locked, rate=rate, rate_other=other,
                        source=source, grid_spread=spread, sideband=sideband, linearity=float(max(changes)) if changes else float("nan"),
                        eps=float(eps), bays=N,
                        grid_phases=int(grid_phases),
                        method=method if not fallbacks else f"{method}, probes at " + "; ".join(fallbacks), operator=operator)


def _checked_arguments(scn: Scenario, lines, eps: float, grid_phases: int, method: str):
    """rate_spectrum's arguments checked: the lines as an int array, the method to take ('probe' where
    the tangent march lacks a mechanism of the contact) and the text saying so."""
    J = scn.roughness.bays * scn.harmonics
    lines = np.asarray(lines, dtype=int)
    if lines.size == 0 or np.any(lines < 1) or np.any(lines > J):
        raise ValueError(f"lines must be a non-empty set in [1, {J}] (N K).")
    if not (np.isfinite(eps) and eps > 0):
        raise ValueError(f"eps = {eps!r} m is not allowed: it must be a finite number > 0.")
    if not (isinstance(grid_phases, (int, np.integer)) and grid_phases >= 1):
        raise ValueError(f"grid_phases = {grid_phases!r} is not allowed: it must be an integer >= 1.")
    if method not in ("linear", "probe"):
        raise ValueError(f"method = {method!r} is not allowed: it must be 'linear' or 'probe'.")
    return lines, method


def locked_kinds(lines, N: int):
    """Which lines of an N-bay period are locked to the supports.

    Parameters
    ----------
    lines : ndarray of int
        Lines j [-] (wavenumbers 2 pi j / (N L)).
    N : int
        The period [bays].

    Returns
    -------
    ndarray of int
        Per line [-]: 1 on the one-bay comb (j = k N; every line when N = 1), 2 on the half-comb
        (even N, j = (k + 1/2) N), 0 for a free line.
    """
    locked = np.where(lines % N == 0, 1, np.where((N % 2 == 0) & (lines % N == N // 2) & (N > 1), 2, 0))
    if N == 1:
        locked[:] = 1
    return locked


def _phase_progress(progress, p: int, grid_phases: int, n_lines: int):
    """linear_rates' progress(i, n) for grid phase p as rate_spectrum's lines of text (None if silent)."""
    if progress is None:
        return None

    def step(i, n, what="probe batches"):
        if i == 0 and p > 0:  # the previous phase's end: told already
            return
        if what != "probe batches":  # the tangent marches, one per wheel, after the batches
            progress(f"{p * n + i} of {grid_phases * n} {what} (grid phase {p + 1} of {grid_phases}: over one bay, every probe at once, "
                     "one march per wheel)")
            return
        progress(f"{p * n + i} of {grid_phases * n} probe batches (grid phase {p + 1} of {grid_phases}, {n_lines} lines)")
        if i == n:
            progress(f"grid phase {p + 1} of {grid_phases}: the tangent of the contact march over one bay, every probe at once")
    return step


def _period(scn: Scenario, tabs, kind: int):
    """The 1-bay (kind 1) or 2-bay (kind 2) period of a locked line: its scenario and tables."""
    s_n = dataclasses.replace(scn, roughness=dataclasses.replace(scn.roughness, bays=kind))
    return s_n, (tabs[0] if kind == 1 else (tabs[0], tabs[scn.roughness.bays // 2]))


def _linear_phase(scn: Scenario, tabs, lines, locked, eps: float, phase: float, check_lines, step=None, say=None):
    """One grid phase of rate_spectrum by the tangent march (linear_rates): the free lines' rates and
    sideband ratios, the locked lines' operators, the comb's source (2 abs(W0), not yet averaged over
    the phases; the smooth rail's wear of linear_rates' own march over one bay) and, with check_lines given,
    the linear range (probes of 2 eps by the nonlinear march against the derivative; with u_bar their Newton
    steps start from the linear prediction, _warm_check). GridMismatch where a probe moves the contact grid.
    ``step(i, n)`` is linear_rates' progress; ``say(text)`` is told of the linearity check."""
    N = scn.roughness.bays
    free, held = np.flatnonzero(locked == 0), np.flatnonzero(locked)
    kinds = {int(lines[idx]): int(locked[idx]) for idx in held}
    probes = [(j, kind) for j in kinds for kind in ("cos", "sin")]
    details = {}
    R_l, side_l, M_l = linear_rates(scn, tabs, [int(j) for j in lines[free]], probes, eps, phase, progress=step, details=details)
    W01 = details["smooth_wear"]  # chain.train_wear's of the smooth rail over one bay, from linear_rates' march
    R = np.array([R_l[int(j)] for j in lines[free]], dtype=complex)
    side = np.array([side_l[int(j)] for j in lines[free]])
    Ms = np.zeros((held.size, 2, 2))
    source = np.zeros(lines.size)
    for n, idx in enumerate(held):
        Ms[n] = M_l[int(lines[idx])]
        if locked[idx] == 1:
            source[idx] = 2 * abs(W01[len(W01) // 2 + int(lines[idx]) // N])
    changes = []
    if check_lines is not None:  # the linear range: probes of 2 eps against the derivative
        if say is not None:
            say(f"linearity check: probes of 2 eps at {min(check_lines, free.size)} lines by the nonlinear march")
        pick = np.unique(np.linspace(0, free.size - 1, min(check_lines, free.size)).round().astype(int)) if free.size else None
        warm = None
        if any(cr is not None for _, _, cr in details["wheels"]):
            try:
                warm = _warm_check(scn, tabs, lines, locked, eps, phase, details, pick)
            except GridMismatch:  # a probe of 2 eps moves the grid: the cold probes on their own grids
                warm = None
        if warm is not None:
            R2, M2 = warm
            if free.size:
                changes += list(np.abs(R2.real / R[pick].real - 1))
            if held.size:
                changes.append(abs(sorted_eigenvalues(M2)[0].real / sorted_eigenvalues(Ms[0])[0].real - 1))
            return R, side, Ms, source, changes
        if free.size:
            Z0 = smooth_roughness(scn)
            W0 = np.zeros(Z0.size, dtype=complex)  # the smooth rail's wear is bay-periodic: on the lines k N
            W0[len(Z0) // 2 + N * np.arange(-scn.harmonics, scn.harmonics + 1)] = W01
            R2 = probe_rates(scn, tabs, lines[free[pick]], 2 * eps, Z0, W0, phase)
            changes += list(np.abs(R2.real / R[pick].real - 1))
        if held.size:
            kind = int(locked[held[0]])
            s_n, t_n = _period(scn, tabs, kind)
            Z0n = smooth_roughness(s_n)
            W0n = W01 if kind == 1 else chain.train_wear(s_n, t_n, Z0n, phase)[0]  # one bay: the march of W01
            M2 = locked_matrix(s_n, t_n, int(lines[held[0]] * kind // N), 2 * eps, phase, Z0n, W0n)
            changes.append(abs(sorted_eigenvalues(M2)[0].real / sorted_eigenvalues(Ms[0])[0].real - 1))
    return R, side, Ms, source, changes


def _warm_check(scn: Scenario, tabs, lines, locked, eps: float, phase: float, details: dict, pick):
    """The linearity check of _linear_phase with u_bar: the probes of 2 eps by the nonlinear march (as probe_rates
    at the free lines lines[free[pick]] and locked_matrix at the first locked line), each wheel's Newton steps on
    u_bar started from the smooth rail's u_bar_0 plus the closed loop's linear prediction for the probe
    (linear.warm_train_wear, to creepage.REFERENCE_TOL, on the smooth rail's grid) instead of from u_bar = 0 to
    march_with_creepage's 1e-5. What is left to the Newton steps, and to the check, is the probe's nonlinear
    part, of the contact and of the loop; the smooth rail's wear is taken on the same footing (its converged
    state over the probes' period). Returns the free lines' rates (None without) and the locked line's 2 x 2
    operator (None without); GridMismatch where a probe moves the grid."""
    N = scn.roughness.bays
    free, held = np.flatnonzero(locked == 0), np.flatnonzero(locked)
    wheels, pred, W01 = details["wheels"], details["ubar"], details["smooth_wear"]

    def starts(probes, B, amp):
        """Per wheel the sum of the probes' predicted delta u_bar at amplitude amp over the first B bays."""
        out = []
        for w_i, (_, mi1, cr) in enumerate(wheels):
            if cr is None:
                out.append(None)
                continue
            u = sum(amp * pred[pr][w_i][0][:B * mi1.Nx] for pr in probes)
            v = sum(amp * pred[pr][w_i][1] for pr in probes)
            out.append((u, v))
        return out

    def smooth(s_b, t_b, B):
        """The smooth rail's wear over B bays: linear_rates' own over one bay, its converged state marched over B."""
        Z0 = smooth_roughness(s_b)
        if B == 1:
            return Z0, W01
        return Z0, warm_train_wear(s_b, t_b, Z0, phase, wheels, [None] * len(wheels))

    R2 = M2 = None
    if free.size:
        Z0, W0 = smooth(scn, tabs, N)
        J = len(Z0) // 2
        rates = {}
        for batch in batches(lines[free[pick]], N):
            Z = Z0
            for j in batch:
                Z = probe_roughness(Z, int(j), "free", 2 * eps)
            W = warm_train_wear(scn, tabs, Z, phase, wheels, starts([(int(j), "free") for j in batch], N, 2 * eps))
            for j in batch:
                rates[int(j)] = (W[J + j] - W0[J + j]) / eps
        R2 = np.array([rates[int(j)] for j in lines[free[pick]]])
    if held.size:
        kind = int(locked[held[0]])
        j = int(lines[held[0]])
        s_n, t_n = _period(scn, tabs, kind)
        Z0n, W0n = smooth(s_n, t_n, kind)
        Jn, jj = len(Z0n) // 2, j * kind // N
        cols = []
        for name in ("cos", "sin"):
            W = warm_train_wear(s_n, t_n, probe_roughness(Z0n, jj, name, 2 * eps), phase, wheels, starts([(j, name)], kind, 2 * eps))
            D = (W[Jn + jj] - W0n[Jn + jj]) / (2 * eps)
            cols.append((2 * D.real, -2 * D.imag))
        M2 = np.array(cols).T
    return R2, M2


def _probe_progress(progress, p: int, grid_phases: int, n_lines: int):
    """_probe_phase's progress(i, n) for grid phase p as rate_spectrum's lines of text (None if silent)."""
    if progress is None:
        return None

    def step(i, n):
        if i == 0 and p > 0:  # the previous phase's end: told already
            return
        progress(f"{p * n + i} of {grid_phases * n} probe steps (grid phase {p + 1} of {grid_phases}, {n_lines} lines; a step: "
                 "the smooth rail's march, a batch of free lines' or a locked line's cosine and sine)")
    return step


def _probe_phase(scn: Scenario, tabs, lines, locked, eps: float, phase: float, check_lines, step=None):
    """One grid phase of rate_spectrum by the probes of the nonlinear march (method 'probe'): as
    _linear_phase returns them. ``step(i, n)``, if given, is told before the first and after each of
    the n steps (the smooth rail's marches, a batch of free lines, a locked line's cosine and sine; the
    linearity check's apart)."""
    N = scn.roughness.bays
    free, held = np.flatnonzero(locked == 0), np.flatnonzero(locked)
    kinds = sorted(set(locked[held].tolist()))
    total = (1 + len(batches(lines[free], N)) if free.size else 0) + len(kinds) + held.size
    done = [0]

    def tick(k=1):
        done[0] += k
        if step is not None:
            step(min(done[0], total), total)

    if step is not None:
        step(0, total)
    R, side = np.zeros(free.size, dtype=complex), np.zeros(free.size)
    Ms = np.zeros((held.size, 2, 2))
    source = np.zeros(lines.size)
    changes = []
    if free.size:
        Z0 = smooth_roughness(scn)
        W0, _ = chain.train_wear(scn, tabs, Z0, phase)
        tick()
        R, side = probe_rates(scn, tabs, lines[free], eps, Z0, W0, phase, sidebands=True, progress=tick)
        if check_lines is not None:
            pick = np.unique(np.linspace(0, free.size - 1, min(check_lines, free.size)).round().astype(int))
            R2 = probe_rates(scn, tabs, lines[free[pick]], 2 * eps, Z0, W0, phase)
            changes += list(np.abs(R2.real / R[pick].real - 1))
    periods = {}  # the 1- and 2-bay periods: scenario, tables, smooth rail and its wear
    for kind in sorted(set(locked[held].tolist())):
        s_n, t_n = _period(scn, tabs, kind)
        Z0n = smooth_roughness(s_n)
        periods[kind] = (s_n, t_n, Z0n, chain.train_wear(s_n, t_n, Z0n, phase)[0])
        tick()
    for n, idx in enumerate(held):
        kind = int(locked[idx])
        s_n, t_n, Z0n, W0n = periods[kind]
        jn = int(lines[idx] * kind // N)  # the line in the 1- or 2-bay period
        Ms[n] = locked_matrix(s_n, t_n, jn, eps, phase, Z0n, W0n)
        tick()
        if kind == 1:
            source[idx] = 2 * abs(W0n[len(W0n) // 2 + jn])
        if check_lines is not None and n == 0:
            M2 = locked_matrix(s_n, t_n, jn, 2 * eps, phase, Z0n, W0n)
            changes.append(abs(sorted_eigenvalues(M2)[0].real / sorted_eigenvalues(Ms[0])[0].real - 1))
    return R, side, Ms, source, changes
