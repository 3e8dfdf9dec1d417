"""The tangent of the contact march about the smooth rail (method 'linear' of the growth-rate spectrum):
the march inputs' differences along each probe, the derivative of the wear along them
(rail.contact.tangent), a line's coefficient and a locked line's operator column from it; and the
uniform track's rates from one march over one bay (linear_rates).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .. import chain, wear
from ..creepage import coupling
from ..contact.tangent import work_tangent
from ..interaction import Roughness
from .creepage import REFERENCE_STEPS, REFERENCE_TOL, closed_loop_wear, creepage_reference, has_creepage
from .probes import GridMismatch, batches

__all__ = ["tangent_batches", "probe_roughness", "check_held_grid", "input_names", "column_chunk", "wear_tangent", "line_coefficient",
           "cos_sin_column", "linear_rates", "warm_train_wear", "bay_tangent"]


def tangent_batches(free, locked_probes, N: int):
    """Batches of probes for linear_rates: the free lines by batches (one per pair of classes), and
    the locked lines' cosine and sine probes, at most one of class 0 and one of class N/2 per batch.

    Parameters
    ----------
    free : sequence of int
        The free lines j [-].
    locked_probes : sequence of (int, str)
        The locked lines' probes (j [-], 'cos' or 'sin').
    N : int
        Bays of the roughness period [-]; line j is of the Bloch class j mod N.

    Returns
    -------
    list of list of (int, str)
        The batches of probes (j [-], kind), a free line as (j, 'free').
    """
    out = [[(j, "free") for j in b] for b in batches(free, N)]
    for r in (0, N // 2):
        probes = [pr for pr in locked_probes if pr[0] % N == r]
        for n, pr in enumerate(probes):
            while len(out) <= n:
                out.append([])
            out[n].append(pr)
    return out


def probe_roughness(Z0, j: int, kind: str, eps: float):
    """Z0 with a probe of amplitude eps [m] added at line j: a cosine (kind 'free' or 'cos') or a sine
    ('sin'); Z_j = (a - i b) / 2 for a cos + b sin.

    Parameters
    ----------
    Z0 : array-like, complex, (2 J + 1,)
        The roughness coefficients Z_j, j = -J..J [m].
    j : int
        The line [-], 1 <= j <= J.
    kind : str
        'free' or 'cos' (a cosine), 'sin' (a sine).
    eps : float
        The probe's amplitude [m].

    Returns
    -------
    ndarray, complex, (2 J + 1,)
        The probed coefficients [m] (a copy; Z0 is unchanged).
    """
    J = len(Z0) // 2
    c = -1j if kind == "sin" else 1.0
    Z = np.array(Z0, dtype=complex)
    Z[J + j] += c * eps / 2
    Z[J - j] += np.conj(c) * eps / 2
    return Z


def check_held_grid(mi, ref, bays: int):
    """GridMismatch unless the probe's march inputs mi lie on the reference's grid (ref: the smooth rail's
    inputs over one period; mi over ``bays`` of those periods) with its patch inside the grid.

    Parameters
    ----------
    mi : rail.wear.MarchInputs
        The probe's march inputs (grid spacing delta [m], half-length a [m], M and Nx [-]).
    ref : rail.wear.MarchInputs
        The smooth rail's, over one period.
    bays : int
        Periods of ref in mi's [-].

    Returns
    -------
    None
        Raises GridMismatch (naming both grids' M and Nx [-]) when the grids differ.
    """
    same = (mi.M == ref.M and mi.Nx == bays * ref.Nx and abs(mi.delta - ref.delta) <= 1e-12 * ref.delta
            and float(np.max(mi.a)) < (mi.M - 0.5) * mi.delta)
    if not same:
        raise GridMismatch(f"the probe's contact grid (M {mi.M}, Nx {mi.Nx}) differs from the smooth rail's (M {ref.M}, "
                           f"Nx {bays} x {ref.Nx}); use method='probe'.")


def input_names(ref):
    """The march inputs a probe changes: force and half-length, the pressure shape with the normal
    contact 'nonhertzian', the step times on the patch's true path.

    Parameters
    ----------
    ref : rail.wear.MarchInputs
        The reference inputs (its shape [-] and step times dt [s] None where the model has none).

    Returns
    -------
    tuple of str
        The names of the inputs: 'P' [N], 'a' [m], then 'shape' [-] and 'dt' [s] where ref has them.
    """
    return ("P", "a") + (("shape",) if ref.shape is not None else ()) + (("dt",) if ref.dt is not None else ())


def column_chunk(ref, ncol: int, max_columns=None) -> int:
    """Columns per tangent march: all, or with a pressure shape about 200 MB of its derivative.

    Parameters
    ----------
    ref : rail.wear.MarchInputs
        The reference inputs (steps and nodes 2 M + 1 [-] size the shape's derivative).
    ncol : int
        Number of columns [-], >= 1.
    max_columns : int, optional
        Most columns per march [-].

    Returns
    -------
    int
        Columns per march [-], in [1, ncol].
    """
    chunk = ncol if ref.shape is None else max(1, int(2e8 // (8 * ref.P.size * (2 * ref.M + 1))))
    return max(1, min(chunk, max_columns or chunk, ncol))


def wear_tangent(scn, wheel: int, ref, speed: float, d: dict):
    """The wear depth of one wheel's passage with the march inputs ``ref`` (the smooth rail's) and its
    derivative along input directions, by the tangent of the contact march (rail.contact.tangent).

    Parameters
    ----------
    scn : Scenario
    wheel : int
        Index of the wheel (its contact parameters, chain.wheel_material).
    ref : rail.wear.MarchInputs
        The reference passage.
    speed : float
        V [m/s].
    d : dict
        {'P': (steps, nc) [N], 'a': (steps, nc) [m], 'shape': (steps, 2M + 1, nc) [-], 'dt': (steps, nc) [s]}:
        the input directions of nc columns (shape and dt where ref has them).

    Returns
    -------
    depth : (Nx,) the reference's wear depth at the period's points x_k = k delta [m] (eq 49)
    ddepth : (Nx, nc) its derivative along each column [m per unit of the column]
    """
    nums = scn.contact_numerics
    work, dwork = work_tangent(ref.P, ref.a, chain.wheel_material(scn, wheel), speed, ref.delta, ref.M, d["P"], d["a"], d.get("shape"),
                               closure=nums.closure, closure_scale=nums.closure_scale, shape=ref.shape, dt=ref.dt, ddt=d.get("dt"))
    points = ref.spin + ref.M + np.arange(ref.Nx)
    kd = scn.wear_law.coefficient / scn.wear_law.density
    return scn.wear_law.depth(work[points]), kd * dwork[points]


def bay_tangent(scn, ref, speed: float, max_columns=None):
    """tangent(material, ubar, d, dubar) for rail.growth_spectrum.creepage.closed_loop_wear and cell_closed_loop_wear:
    the tangent march on the reference inputs ``ref`` with u_bar_0 given (ubar) and the directions d (as
    wear_tangent's) and dubar (of u_bar, or None), in chunks of columns.

    Parameters
    ----------
    scn : Scenario
        Its contact numerics (the closure).
    ref : rail.wear.MarchInputs
        The smooth rail's inputs over the period (one bay, or a track cell).
    speed : float
        V [m/s].
    max_columns : int, optional
        Most columns per march [-] (default: column_chunk's).

    Returns
    -------
    callable
        tangent(material, ubar, d, dubar) -> (dwork at the period's points x_k [J/m^2 per unit column],
        dQ at the period's steps [N per unit column]), each (N_x, nc).
    """
    nums = scn.contact_numerics
    points = ref.spin + ref.M + np.arange(ref.Nx)
    steps = ref.spin + np.arange(ref.Nx)

    def tangent(material, ubar, d, dubar):
        ncol = next(iter(d.values())).shape[-1]
        dW, dQ = np.zeros((ref.Nx, ncol)), np.zeros((ref.Nx, ncol))
        chunk = column_chunk(ref, ncol, max_columns) if "shape" in d else ncol
        for c0 in range(0, ncol, max(chunk, 1)):
            sl = slice(c0, min(c0 + chunk, ncol))
            _, dw, _, dq = work_tangent(ref.P, ref.a, material, speed, ref.delta, ref.M, d["P"][:, sl], d["a"][:, sl],
                                        d["shape"][..., sl] if "shape" in d else None, closure=nums.closure,
                                        closure_scale=nums.closure_scale, shape=ref.shape, dt=ref.dt,
                                        ddt=d["dt"][:, sl] if "dt" in d else None, ubar=ubar,
                                        dubar=None if dubar is None else dubar[:, sl], force=True)
            dW[:, sl], dQ[:, sl] = dw[points], dq[steps]
        return dW, dQ
    return tangent


def line_coefficient(gws: dict, c, jj: int, periods: int, imag=None):
    """Wear coefficient W_jj per unit probe (eq 53) from derivatives of the depth gws = {n: (n, ncol)}
    at the points x_k = k P / n of one period P (each wheel's grid size summed apart), over a roughness
    period of ``periods`` such periods (Bloch form: the derivative is e^{i 2 pi r x / (N L)} times a
    P-periodic function, so one period's points give the line); column c, plus i times column imag.

    Parameters
    ----------
    gws : dict
        {n: (n, ncol) ndarray}: the derivatives of the wear depth [m per unit probe amplitude, m/m] at
        the n points of one period, summed over the wheels on grids of n points.
    c : int
        The column [-] (the real part's with imag given).
    jj : int
        The line [-] whose coefficient is taken.
    periods : int
        Periods P in the roughness period [-] (N for the bays of a uniform track, 1 for a cell).
    imag : int, optional
        The column [-] of the imaginary part.

    Returns
    -------
    complex
        The wear coefficient per unit probe amplitude [-] (m of wear per m of probe, per train passage).
    """
    total = 0.0
    for n, gw in gws.items():
        k = np.arange(n)
        g = gw[:, c] if imag is None else gw[:, c] + 1j * gw[:, imag]
        total = total + np.sum(g * np.exp(-2j * np.pi * jj * k / (periods * n))) / n
    return total


def cos_sin_column(D):
    """The column (cosine, sine parts) of the 2 x 2 operator from the wear coefficient D per unit
    amplitude of a probe: D = (c - i d) / 2.

    Parameters
    ----------
    D : complex
        The wear coefficient per unit probe amplitude [-] (line_coefficient).

    Returns
    -------
    (float, float)
        The cosine and sine parts (c, d) of the wear per unit probe amplitude [-].
    """
    return 2 * D.real, -2 * D.imag


def linear_rates(scn, tabs, free, locked, eps, phase, max_columns=None, progress=None, details=None):
    """R_j at the free lines (and their sideband ratios) and the 2 x 2 operators M at the locked lines
    (line, kind), by the tangent of the contact march about the smooth rail (method 'linear').

    The smooth rail's state is periodic over one bay, so the derivative of the wear for roughness of
    the Bloch class r = j mod N is e^{i 2 pi r x / (N L)} times a bay-periodic function: one march of
    the smooth rail over one bay (with its spin-up), carrying the derivative along every probe at once
    (rail.contact.tangent), gives every line. The normal contact's inputs along each probe (force,
    half-length, pressure shape at every step) are the difference of the model's own inputs with
    and without a probe of amplitude eps over the N bays (one evaluation per batch of lines, as the
    probes of method 'probe' but without the march), split into the classes by a DFT over the bays.
    With several wheels, the wear of the wheels before a wheel is taken at the smooth rail's (its
    derivative, of relative size the wear per passage, ~1e-6, is left out). With dynamic creepage (the
    wheelset's modes or the rail's flexibility on a wheel's material) each wheel's derivative closes the
    loop of u_bar about the smooth rail's periodic state per Bloch class (rail.growth_spectrum.creepage.
    closed_loop_wear); falling friction alone is in the tangent march itself. ``progress(i, n)``, if
    given, is called before the first (i = 0) and after each of the n batches of probes, and
    ``progress(i, n, "tangent marches")`` before the first and after each wheel's tangent march (the
    longest part of a spectrum of few lines: issue 57, item 8, a log empty for 648 s).

    Parameters
    ----------
    scn : Scenario
        With roughness.bays = N; the lines j are those of the wavenumbers 2 pi j / (N L).
    tabs : tuple of MovingReceptance
        The receptance tables at the speed [m/N] (rail.chain.receptance_table).
    free : sequence of int
        The free lines j [-].
    locked : sequence of (int, str)
        The locked lines' probes (j [-], 'cos' or 'sin').
    eps : float
        The probes' amplitude [m] (the inputs' differences are taken with it).
    phase : float
        Contact grid phase [-], in [0, 1) (rail.wear.bay_wear).
    max_columns : int, optional
        Most probe columns per tangent march [-] (column_chunk).
    progress : callable, optional
        progress(i, n) [-] as above.
    details : dict, optional
        Filled, if given, with what the spectrum's other parts take from the smooth rail's march over one bay
        instead of marching it again: 'smooth_wear', the smooth rail's wear coefficients per train passage over
        one bay (rail.chain.train_wear's, 2 K + 1) [m]; 'wheels', per wheel in rolling order (index, one-bay march
        inputs, CreepageReference or None: its state with u_bar, converged to creepage.REFERENCE_TOL); and
        'ubar', {(j, kind): per wheel the closed loop's delta u_bar per unit amplitude of the probe's complex
        direction (closed_loop_wear's predictions) or None} (the probes' amplitude is eps; kind 'free': the direction
        is twice the class's part over eps).

    Returns
    -------
    R : dict
        {j: complex} the rate R_j at each free line [1 per train passage].
    side : dict
        {j: float} the largest sideband wear (j +- N) over the wear at j [-].
    M : dict
        {j: (2, 2) ndarray} the (cosine, sine) wear operator at each locked line [1 per train passage].
    """
    N = scn.roughness.bays
    K = scn.harmonics
    J = N * K
    probes = tangent_batches(free, locked, N)
    if progress is not None:
        progress(0, len(probes))  # the log says at once what is being done
    nums = scn.contact_numerics  # the contact parameters of each wheel: chain.wheel_material (its own creepage)
    s1 = dataclasses.replace(scn, roughness=dataclasses.replace(scn.roughness, bays=1))
    Z01 = np.zeros(2 * K + 1, dtype=complex)
    f1 = chain.solve_forces(s1, tabs[0], Roughness(Z01, 1))
    order = [int(l) for l in np.argsort(scn.wheels.positions)[::-1]]
    # the reference inputs of each wheel over one bay, and the smooth rail's wear before each wheel; with u_bar the
    # smooth rail's state converged once (creepage_reference), the tangent's reference and the smooth rail's wear
    ref, cur1, wear_before, creep = [], Roughness(Z01, 1), [], []
    W01 = np.zeros_like(Z01)
    for l in order:
        mat = chain.wheel_material(scn, l)
        mi = wear.march_inputs(f1, l, cur1, mat, nums, phase)
        ref.append(mi)
        if has_creepage(mat):
            cr = creepage_reference(mi, mat, tabs[0].speed, nums, K)
            depth = scn.wear_law.depth(cr.work)
            if not np.all(np.isfinite(depth)):
                raise FloatingPointError(f"the wear depth of wheel {l} is not finite (V = {tabs[0].speed:g} m/s).")
            wZ = wear.wear_spectrum(depth, K)
        else:
            cr, wZ = None, chain.passage_wear(s1, f1, cur1, l, phase).Z
        creep.append(cr)
        wear_before.append(cur1.Z.copy())
        W01 += wZ
        cur1 = wear.apply_wear(cur1, wZ)
    # the same on the N-bay period (the 1-bay coefficients k on the lines k N)
    def on_period(Z1):
        Z = np.zeros(2 * J + 1, dtype=complex)
        Z[J + N * np.arange(-K, K + 1)] = Z1
        return Z
    cols = []  # (probe, wheel) -> columns
    names = input_names(ref[0])
    dirs = [{name: [] for name in names} for _ in order]
    Z0N = np.zeros(2 * J + 1, dtype=complex)
    fN0 = chain.solve_forces(scn, tabs, Roughness(Z0N, N))
    base = []
    for w_i, l in enumerate(order):
        g1 = ref[w_i]
        base.append(wear.march_inputs(fN0, l, Roughness(on_period(wear_before[w_i]), N), chain.wheel_material(scn, l), nums, phase,
                                      grid=(g1.delta, g1.Nx, g1.M, g1.spin)))
    for i_batch, batch in enumerate(probes):
        if progress is not None and i_batch:
            progress(i_batch, len(probes))
        Z = Z0N
        for j, kind in batch:
            Z = probe_roughness(Z, j, kind, eps)
        fN = chain.solve_forces(scn, tabs, Roughness(Z, N))
        for w_i, l in enumerate(order):
            mi1, b0 = ref[w_i], base[w_i]
            mi = wear.march_inputs(fN, l, Roughness(Z + on_period(wear_before[w_i]), N), chain.wheel_material(scn, l), nums, phase,
                                   grid=(mi1.delta, mi1.Nx, mi1.M, mi1.spin))  # the smooth rail's grid
            # the same grid (the spin-up may differ by a step: positions are taken from each one's own)
            check_held_grid(mi, mi1, N)
            check_held_grid(b0, mi1, N)
            nx1, nxN = mi1.Nx, b0.Nx
            pos = (np.arange(mi1.spin + nx1 + 2 * mi1.M + 1) - mi1.spin)[None, :] + nx1 * np.arange(N)[:, None]
            F = {}
            for name in names:
                arr, arr0 = getattr(mi, name), getattr(b0, name)
                d = arr[mi.spin + pos % nxN] - arr0[b0.spin + pos % nxN]
                F[name] = np.fft.fft(d, axis=0) / N  # class r: F[r]
            for j, kind in batch:
                r = j % N
                scale = 2 / eps if kind == "free" else 1 / eps
                parts = (np.real, np.imag) if kind == "free" else (np.real,)
                for part in parts:
                    if w_i == 0:
                        cols.append((j, kind, part is np.imag))
                    for name in names:
                        dirs[w_i][name].append(part(F[name][r]) * scale)
    if progress is not None:
        progress(len(probes), len(probes))
    ncol = len(cols)
    # each wheel's derivative on its own grid: the wheels' patches differ (their forces do), so their
    # grids may hold a different number of points per bay (4131 and 4132 for two axles of one
    # locomotive at 40 m/s); wheels on grids of one size are summed there, each size transformed apart
    gws = {}
    ubar = {(j, kind): [None] * len(order) for j, kind, imag in cols if not imag}
    if progress is not None:
        progress(0, len(order), "tangent marches")
    for w_i, l in enumerate(order):
        if progress is not None and w_i:
            progress(w_i, len(order), "tangent marches")
        mi1 = ref[w_i]
        gw = gws.setdefault(mi1.Nx, np.zeros((mi1.Nx, ncol)))
        if has_creepage(chain.wheel_material(scn, l)):  # the loop of u_bar closed per class (rail.growth_spectrum.creepage)
            d = {name: np.moveaxis(np.array(dirs[w_i][name]), 0, -1) for name in names}
            groups = [(j % N, c, c + 1 if kind == "free" else None) for c, (j, kind, imag) in enumerate(cols) if not imag]
            kd = scn.wear_law.coefficient / scn.wear_law.density
            pred = {}
            gw += kd * closed_loop_wear(scn, l, mi1, tabs[0].speed, d, groups, bay_tangent(scn, mi1, tabs[0].speed, max_columns),
                                        ref=creep[w_i], predictions=pred)
            for c, (j, kind, imag) in enumerate(cols):
                if not imag:
                    ubar[(j, kind)][w_i] = pred[c]
            continue
        chunk = column_chunk(mi1, ncol, max_columns)
        for c0 in range(0, ncol, chunk):
            sl = slice(c0, min(c0 + chunk, ncol))
            d = {name: np.moveaxis(np.array(dirs[w_i][name][sl]), 0, -1) for name in names}
            gw[:, sl] += wear_tangent(scn, l, mi1, tabs[0].speed, d)[1]

    if progress is not None:
        progress(len(order), len(order), "tangent marches")
    R, side, Ms = {}, {}, {}
    c = 0
    while c < ncol:
        j, kind, _ = cols[c]
        if kind == "free":
            R[j] = line_coefficient(gws, c, j, N, c + 1)
            near = [j + m for m in (-N, N) if abs(j + m) <= J]
            side[j] = max(abs(line_coefficient(gws, c, jj, N, c + 1)) for jj in near) / max(abs(R[j]), 1e-300) if near else 0.0
            c += 2
        else:
            Ms.setdefault(j, {})[kind] = cos_sin_column(line_coefficient(gws, c, j, N))
            c += 1
    Mout = {j: np.array([v["cos"], v["sin"]]).T for j, v in Ms.items()}
    if details is not None:
        details.update(smooth_wear=W01, wheels=[(l, ref[w_i], creep[w_i]) for w_i, l in enumerate(order)], ubar=ubar)
    return R, side, Mout


def warm_train_wear(scn, tabs, Z, grid_phase: float, refs, starts, periods: int | None = None):
    """The wear of one train passage over the roughness Z (as rail.chain.train_wear: the wheels in turn, each on the
    profile the one before left), each wheel's march on its smooth rail's grid held and, with u_bar, its Newton
    steps (march_with_creepage to REFERENCE_TOL) started from the smooth rail's u_bar_0 plus a given change (the
    linear method's prediction): the linearity check of the linear method with dynamic creepage
    (rail.growth_spectrum.spectrum). From the prediction the Newton steps have only the probe's nonlinear part
    of u_bar left to find (one march where it is below REFERENCE_TOL; more where it is not), against five to ten
    marches from u_bar = 0; the state reached is the same periodic state to REFERENCE_TOL.

    Parameters
    ----------
    scn : Scenario
        With roughness.bays = B, the period of Z [bays].
    tabs : MovingReceptance or tuple of MovingReceptance
        The receptance table(s) of the B-bay period at the speed [m/N].
    Z : ndarray, complex, (2 B K + 1,)
        The roughness coefficients [m].
    grid_phase : float
        Contact grid phase [-], in [0, 1).
    refs : list of (int, rail.wear.MarchInputs, CreepageReference or None)
        Per wheel in rolling order (leading first): its index, its smooth rail's one-bay march inputs (whose
        grid is held) and its smooth rail's state with u_bar (None: the wheel has no u_bar).
    starts : list of (ndarray, complex) or None
        Per wheel: the change of u_bar's periodic part at the B N_x steps of the period from the bay's first
        [m] (its real part is taken) and of v_bar [m/s] where the Newton steps start (None: at u_bar_0).
    periods : int, optional
        The reference inputs' periods in Z's [-] (default B, the bays: one-bay references; 1 on a track cell,
        whose references are over the cell).

    Returns
    -------
    ndarray, complex, (2 B K + 1,)
        The wear coefficients summed over the wheels per train passage [m].

    Raises
    ------
    GridMismatch
        Where the roughness moves a wheel's contact grid off its smooth rail's.
    """
    B = scn.roughness.bays
    reps = B if periods is None else int(periods)
    rough = Roughness(np.asarray(Z, dtype=complex), B)
    forces = chain.solve_forces(scn, tabs, rough)
    nums = scn.contact_numerics
    dZ = np.zeros_like(rough.Z, dtype=complex)
    current = rough
    for (l, mi1, cr), st in zip(refs, starts):
        mat = chain.wheel_material(scn, l)
        mi = wear.march_inputs(forces, l, current, mat, nums, grid_phase, grid=(mi1.delta, mi1.Nx * reps // B, mi1.M, mi1.spin))
        check_held_grid(mi, mi1, reps)
        if cr is None:
            sol, _ = coupling.march_with_creepage(mi, mat, forces.speed, nums, harmonics=forces.harmonics)
        else:
            dtp = (np.full(mi.Nx, mi.delta / forces.speed) if mi.dt is None else np.asarray(mi.dt, dtype=float)[mi.spin:mi.spin + mi.Nx])
            phase = (np.cumsum(dtp) - dtp[0]) / float(np.sum(dtp))  # as march_with_creepage's: start.at(phase) is p
            du, dv = (np.zeros(mi.Nx), 0.0) if st is None else st
            start = coupling.CreepageState(phase, np.tile(cr.p, reps) + np.real(du), cr.vbar + float(np.real(dv)), grid=mi.Nx)
            sol, _ = coupling.march_with_creepage(mi, mat, forces.speed, nums, tol=REFERENCE_TOL, max_iter=REFERENCE_STEPS,
                                         harmonics=forces.harmonics, start=start)
        depth = scn.wear_law.depth(sol.work[mi.spin + mi.M + np.arange(mi.Nx)])
        if not np.all(np.isfinite(depth)):
            raise FloatingPointError(f"the wear depth of wheel {l} is not finite (V = {forces.speed:g} m/s).")
        w = wear.wear_spectrum(depth, rough.harmonics)
        dZ += w
        current = wear.apply_wear(current, w)
    return dZ
