"""The growth-rate spectrum on a track periodic over a cell of N bays whose supports differ (rail.cell):
every line a 2 x 2 (cosine, sine) operator over the cell, by the tangent of the contact march over
the cell (method 'linear') or by nonlinear probes (method 'probe').
"""

from __future__ import annotations

import numpy as np

from .. import chain, wear
from ..interaction import Roughness
from ..moving import MovingReceptance
from ..scenario import Scenario
from .creepage import cell_closed_loop_wear, creepage_reference, has_creepage
from .linear import (bay_tangent, check_held_grid, column_chunk, cos_sin_column, input_names, line_coefficient, probe_roughness, warm_train_wear,
                     wear_tangent)
from .probes import GridMismatch, RateSpectrum, locked_matrix, smooth_roughness, sorted_eigenvalues

__all__ = ["cell_linear_operators", "cell_rate_spectrum"]


def cell_linear_operators(scn, table, lines, eps, phase, max_columns=None, progress=None, details=None):
    """The 2 x 2 (cosine, sine) wear operators M at every line of a track cell, and the smooth rail's
    wear over the cell, by the tangent of the contact march about the smooth rail (method 'linear' of
    cell_rate_spectrum).

    On a cell of N bays whose supports differ, the smooth rail's state is periodic over the cell, and
    the derivative of the wear for a roughness at line j is a general function over the cell: one
    march of the smooth rail over the cell (with its spin-up), carrying the derivative along a cosine
    and a sine probe of every line at once (rail.contact.tangent), gives every operator; the line's
    column is the derivative's Fourier coefficient at j (as a locked line of linear_rates). Each
    column's inputs (force, half-length, pressure shape, step times at every step) are the difference
    of the model's own march inputs with and without a probe of amplitude eps (one force solve and
    one march_inputs per probe, no march), on the smooth rail's grid. With several wheels, each rolls
    on the smooth rail's wear of the wheels before it (from the tangent's own reference march); the
    derivative of that wear is left out, as in linear_rates. With dynamic creepage (the wheelset's modes,
    the rail head's flexibility on the cell) the reference is the smooth rail's periodic state with u_bar
    over the cell (creepage_reference, its wear the source) and the loop of u_bar is closed over the cell's
    harmonics (rail.growth_spectrum.creepage.cell_closed_loop_wear); falling friction is in the tangent march.

    Parameters
    ----------
    scn : Scenario
        With scn.cell and roughness.bays = N (the cell's bays).
    table : MovingReceptance
        The cell's one table at the speed (rail.moving.cell_receptance_table).
    lines : sequence of int
        Lines j, 1 <= j <= N K [-] (wavenumbers 2 pi j / (N L)).
    eps : float
        Amplitude of the probing cosine and sine [m].
    phase : float
        Contact grid phase in [0, 1) [-] (rail.wear.bay_wear).
    max_columns : int, optional
        The most columns per tangent march [-] (default: about 200 MB of the pressure shape's derivative).
    progress : callable, optional
        progress(i, n) after each of the n probes' march inputs (per wheel).
    details : list, optional
        Filled with (wheel, march inputs, CreepageReference or None) per wheel in rolling order (the smooth
        rail's over the cell: the linearity check's warm_train_wear).

    Returns
    -------
    M : ndarray, shape (n, 2, 2)
        Per line, the operator on (a, b) of a cos + b sin [1 per train passage]: column 0 the wear
        (cosine, sine parts) of a unit cosine, column 1 of a unit sine.
    W0 : ndarray, shape (2 N K + 1,)
        The smooth rail's wear of one train passage [m] (the parametric source).

    Raises
    ------
    GridMismatch
        Where a probe's patch outgrows the smooth rail's contact grid.
    """
    N = scn.roughness.bays
    Z0 = smooth_roughness(scn)
    J = len(Z0) // 2
    probes = [(int(j), kind) for j in lines for kind in ("cos", "sin")]
    ncol = len(probes)
    f0 = chain.solve_forces(scn, table, Roughness(Z0, N))
    forces = [chain.solve_forces(scn, table, Roughness(probe_roughness(Z0, j, kind, eps), N)) for j, kind in probes]
    order = [int(l) for l in np.argsort(scn.wheels.positions)[::-1]]
    nums = scn.contact_numerics
    cur, W0, gws, done = Roughness(Z0, N), np.zeros_like(Z0), {}, 0
    kd = scn.wear_law.coefficient / scn.wear_law.density
    for l in order:
        mat = chain.wheel_material(scn, l)
        ref = wear.march_inputs(f0, l, cur, mat, nums, phase)
        grid = (ref.delta, ref.Nx // N, ref.M, ref.spin)
        names = input_names(ref)
        gw = gws.setdefault(ref.Nx, np.zeros((ref.Nx, ncol)))
        loop = has_creepage(mat)  # the loop of u_bar closed over the cell, its basis's tangent once per wheel (cache)
        cr = creepage_reference(ref, mat, table.speed, nums, J) if loop else None
        cache = {}
        chunk = column_chunk(ref, ncol, max_columns)
        depth = scn.wear_law.depth(cr.work) if loop else None
        for c0 in range(0, ncol, chunk):
            cs = range(c0, min(c0 + chunk, ncol))
            d = {name: [] for name in names}
            for c in cs:
                j, kind = probes[c]
                mi = wear.march_inputs(forces[c], l, Roughness(cur.Z + probe_roughness(Z0, j, kind, eps), N), mat, nums, phase, grid=grid)
                check_held_grid(mi, ref, 1)
                for name in names:
                    d[name].append((getattr(mi, name) - getattr(ref, name)) / eps)
                done += 1
                if progress is not None:
                    progress(done, ncol * len(order))
            d = {k: np.moveaxis(np.array(v), 0, -1) for k, v in d.items()}
            if loop:
                gw[:, c0:cs.stop] += kd * cell_closed_loop_wear(scn, l, ref, table.speed, d, bay_tangent(scn, ref, table.speed, max_columns),
                                                                cr, cache)
            else:
                depth, dd = wear_tangent(scn, l, ref, table.speed, d)
                gw[:, c0:cs.stop] += dd
        if not np.all(np.isfinite(depth)):
            raise FloatingPointError(f"the wear depth of wheel {l} is not finite (V = {table.speed:g} m/s).")
        if details is not None:
            details.append((l, ref, cr))
        Wl = wear.wear_spectrum(depth, J)
        W0 += Wl
        cur = wear.apply_wear(cur, Wl)
    M = np.zeros((len(lines), 2, 2))
    for n, j in enumerate(lines):
        for k in range(2):
            M[n, :, k] = cos_sin_column(line_coefficient(gws, 2 * n + k, int(j), 1))
    return M, W0


def cell_rate_spectrum(scn: Scenario, table: MovingReceptance, lines, eps: float, grid_phases: int, method: str = "linear",
                        progress=None, max_columns=None) -> RateSpectrum:
    """rate_spectrum on a track periodic over a cell of N bays whose supports differ (rail.cell).

    The smooth rail's state is periodic over the cell, not over one bay, so the Bloch classes that
    keep the lines of the uniform track apart are coupled by the supports, and the cosine and the
    sine of every line couple through the cell harmonic 2 j: every line is treated as the comb of
    the uniform track is, by the 2 x 2 operator of a probing cosine and sine over the cell, its
    eigenvalues the rate and the other rate, and the smooth rail's wear at the line its parametric
    source. Method 'linear': every operator from one march of the smooth rail over the cell carrying
    the derivative along every probe (cell_linear_operators); 'probe': two nonlinear marches over the
    cell per line and grid phase (locked_matrix), the reference. The coupling of a line to the others (its
    sidebands j + m, every m) is not in the diagonal rate; growth runs (rail.chain.grow) carry it.
    ``progress(text)``, if given, is told as the work proceeds (after every line for 'probe', after
    every probe's inputs for 'linear').

    Parameters
    ----------
    scn : Scenario
        On a track cell of N = roughness.bays bays; the lines j are those of the wavenumbers 2 pi j / (N L).
    table : MovingReceptance
        The cell's one table over the cell's harmonics (rail.moving.cell_receptance_table).
    lines : sequence of int
        The lines j [-], 1 <= j <= N K.
    eps : float
        Amplitude of the probing cosine and sine [m], small enough for the linear range.
    grid_phases : int
        Number of contact grid phases averaged over [-], >= 1.
    method : str
        'linear' (the tangent march) or 'probe' (the nonlinear march), as above.
    progress : callable, optional
        Told a line of text as the work proceeds.
    max_columns : int, optional
        Most probe columns per tangent march [-] (default: column_chunk's).

    Returns
    -------
    RateSpectrum
        Every line locked: rate and rate_other the 2 x 2 operator's eigenvalues [1 per train passage],
        source the smooth rail's wear at the line [m per train passage], wavelength N L / j [m].
    """
    N = scn.roughness.bays
    lines = np.asarray(lines, dtype=int)
    refs = []
    if not (isinstance(table, MovingReceptance) and table.supports is not None and table.bays == N):
        raise ValueError(f"a track cell of {N} bays needs its one table over the cell's harmonics (rail.moving.cell_receptance_table).")
    J = len(smooth_roughness(scn)) // 2
    chain.cell_head_ready(scn, table.speed, progress)
    Ms = np.zeros((grid_phases, lines.size, 2, 2))
    source = np.zeros(lines.size)
    changes, fallbacks = [], []
    for p, phase in enumerate(np.arange(grid_phases) / grid_phases):
        Z0 = smooth_roughness(scn)
        W0 = None
        if method == "linear":
            step = None
            if progress is not None:
                def step(i, n, p=p):
                    progress(f"{p * n + i} of {grid_phases * n} probe inputs (grid phase {p + 1} of {grid_phases}, {lines.size} lines, "
                             f"a cosine and a sine each over the cell of {N} bays)")
                    if i == n:
                        progress(f"grid phase {p + 1} of {grid_phases}: the tangent of the contact march over the cell, every probe at once")
            refs = []
            try:
                Ms[p], W0 = cell_linear_operators(scn, table, lines, eps, phase, max_columns=max_columns, progress=step, details=refs)
            except GridMismatch as err:  # the probes of the nonlinear march for this grid phase
                fallbacks.append(f"grid phase {phase:g}: {err}")
                refs = []  # the wheels done before the mismatch: not a reference for the check's warm start
        if W0 is None:
            W0, _ = chain.train_wear(scn, table, Z0, phase)
            for n, j in enumerate(lines):
                Ms[p, n] = locked_matrix(scn, table, int(j), eps, phase, Z0, W0)
                if progress is not None:
                    progress(f"{p * lines.size + n + 1} of {grid_phases * lines.size} lines (grid phase {p + 1} of {grid_phases}; "
                             f"a cosine and a sine probe each, marched over the cell of {N} bays)")
        source += 2 * np.abs(W0[J + lines]) / grid_phases
        if p == 0:
            if progress is not None:
                progress("linearity check: a probe of 2 eps at the first line by the nonlinear march")
            if any(cr is not None for _, _, cr in refs):
                M2 = _warm_locked_matrix(scn, table, int(lines[0]), 2 * eps, phase, refs)
            else:
                M2 = locked_matrix(scn, table, int(lines[0]), 2 * eps, phase, Z0, W0)
            changes.append(abs(sorted_eigenvalues(M2)[0].real / sorted_eigenvalues(Ms[0, 0])[0].real - 1))
    rate = np.zeros(lines.size, dtype=complex)
    other = np.zeros(lines.size, dtype=complex)
    spread = np.zeros(lines.size)
    for n in range(lines.size):
        rate[n], other[n] = sorted_eigenvalues(Ms[:, n].mean(axis=0))
        spread[n] = np.ptp([sorted_eigenvalues(M)[0].real for M in Ms[:, n]]) / 2
    how = {"linear": "the tangent of the contact march over the cell at every line",
           "probe": "cosine and sine probes at every line (nonlinear march)"}[method]
    if fallbacks:
        how += "; probes at " + "; ".join(fallbacks)
    return RateSpectrum(wavelength=N * scn.L / lines, line=lines, locked=np.ones(lines.size, dtype=int), rate=rate, rate_other=other,
                        source=source, grid_spread=spread, sideband=np.zeros(lines.size), linearity=float(max(changes)), eps=float(eps),
                        bays=N, grid_phases=int(grid_phases), method=f"cell of {N} bays: {how}", operator=Ms.mean(axis=0))


def _warm_locked_matrix(scn, table, j: int, eps: float, phase: float, refs):
    """locked_matrix with the Newton steps of u_bar from the smooth rail's state to REFERENCE_TOL (warm_train_wear over
    the cell): the linearity check of method 'linear' with dynamic creepage, whose probes' own small change of u_bar
    march_with_creepage's default tolerance (1e-5 of the creep velocity) would leave unresolved (a few percent of the
    rate, tests/test_linear_creepage.py)."""
    Z0 = smooth_roughness(scn)
    J = len(Z0) // 2
    starts = [None] * len(refs)
    W0 = warm_train_wear(scn, table, Z0, phase, refs, starts, periods=1)
    cols = []
    for kind in ("cos", "sin"):
        W = warm_train_wear(scn, table, probe_roughness(Z0, j, kind, eps), phase, refs, starts, periods=1)
        cols.append(cos_sin_column((W[J + j] - W0[J + j]) / eps))
    return np.array(cols).T
