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

import dataclasses
from dataclasses import dataclass

import numpy as np

from . import chain, wear
from .contact.tangent import work_tangent
from .interaction import Roughness
from .moving import MovingReceptance
from .scenario import Scenario

__all__ = ["wear_rates", "linear_unsupported", "RateSpectrum", "spectrum_lines", "rate_spectrum", "locked_operator", "class_operator",
           "FleetRateSpectrum", "fleet_rate_spectrum", "combine_spectra"]


class GridMismatch(RuntimeError):
    """The contact grid of a probe differs from the smooth rail's (method 'linear' needs one grid);
    rate_spectrum then takes the probes for that grid phase."""


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
    return _probe(scn, table, lines, eps, Z0, W0, grid_phase)


def _probe(scn, table, lines, eps, Z0, W0, grid_phase, sidebands=False):
    """R_j at the lines about the reference Z0, whose wear W0 on the same grid is given; with
    sidebands, also the largest |wear at j +- N| / |wear at j| (the same class, probed by j alone)."""
    J = len(Z0) // 2
    N = scn.roughness.bays
    rates, side = {}, {}
    for batch in _batches(lines, N):
        Z = Z0.copy()
        for j in batch:
            Z[J + j] += eps / 2
            Z[J - j] += eps / 2
        W, _ = chain.train_wear(scn, table, Z, grid_phase)
        for j in batch:
            rates[j] = (W[J + j] - W0[J + j]) / (eps / 2)
            near = [J + j + m for m in (-N, N) if abs(j + m) <= J]
            side[j] = max(abs(W[i] - W0[i]) for i in near) / max(abs(W[J + j] - W0[J + j]), 1e-300) if near else 0.0
    R = np.array([rates[j] for j in lines])
    return (R, np.array([side[j] for j in lines])) if sidebands else R


def _tangent_batches(free, locked_probes, N: int):
    """Batches of probes for _linear_rates: the free lines by _batches (one per pair of classes), and
    the locked lines' cosine and sine probes, at most one of class 0 and one of class N/2 per batch."""
    out = [[(j, "free") for j in b] for b in _batches(free, N)]
    for r in (0, N // 2):
        probes = [pr for pr in locked_probes if pr[0] % N == r]
        for n, pr in enumerate(probes):
            while len(out) <= n:
                out.append([])
            out[n].append(pr)
    return out


def _probe_roughness(Z0, j: int, kind: str, eps: float):
    """Z0 with a probe of amplitude eps [m] added at line j: a cosine (kind 'free' or 'cos') or a sine
    ('sin'); Z_j = (a - i b) / 2 for a cos + b sin."""
    J = len(Z0) // 2
    c = -1j if kind == "sin" else 1.0
    Z = np.array(Z0, dtype=complex)
    Z[J + j] += c * eps / 2
    Z[J - j] += np.conj(c) * eps / 2
    return Z


def _held_grid(mi, ref, bays: int):
    """GridMismatch unless the probe's march inputs mi lie on the reference's grid (ref: the smooth rail's
    inputs over one period; mi over ``bays`` of those periods) with its patch inside the grid."""
    same = (mi.M == ref.M and mi.Nx == bays * ref.Nx and abs(mi.delta - ref.delta) <= 1e-12 * ref.delta
            and float(np.max(mi.a)) < (mi.M - 0.5) * mi.delta)
    if not same:
        raise GridMismatch(f"the probe's contact grid (M {mi.M}, Nx {mi.Nx}) differs from the smooth rail's (M {ref.M}, "
                           f"Nx {bays} x {ref.Nx}); use method='probe'.")


def _input_names(ref):
    """The march inputs a probe changes: force and half-length, the pressure shape with the normal
    contact 'nonhertzian', the step times on the patch's true path."""
    return ("P", "a") + (("shape",) if ref.shape is not None else ()) + (("dt",) if ref.dt is not None else ())


def _column_chunk(ref, ncol: int, max_columns=None) -> int:
    """Columns per tangent march: all, or with a pressure shape about 200 MB of its derivative."""
    chunk = ncol if ref.shape is None else max(1, int(2e8 // (8 * ref.P.size * (2 * ref.M + 1))))
    return max(1, min(chunk, max_columns or chunk, ncol))


def _wear_tangent(scn, wheel: int, ref, speed: float, d: dict):
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


def _line_coefficient(gws: dict, c, jj: int, periods: int, imag=None):
    """Wear coefficient W_jj per unit probe (eq 53) from derivatives of the depth gws = {n: (n, ncol)}
    at the points x_k = k P / n of one period P (each wheel's grid size summed apart), over a roughness
    period of ``periods`` such periods (Bloch form: the derivative is e^{i 2 pi r x / (N L)} times a
    P-periodic function, so one period's points give the line); column c, plus i times column imag."""
    total = 0.0
    for n, gw in gws.items():
        k = np.arange(n)
        g = gw[:, c] if imag is None else gw[:, c] + 1j * gw[:, imag]
        total = total + np.sum(g * np.exp(-2j * np.pi * jj * k / (periods * n))) / n
    return total


def _cos_sin_column(D):
    """The column (cosine, sine parts) of the 2 x 2 operator from the wear coefficient D per unit
    amplitude of a probe: D = (c - i d) / 2."""
    return 2 * D.real, -2 * D.imag


def _linear_rates(scn, tabs, free, locked, eps, phase, max_columns=None, progress=None):
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
    derivative, of relative size the wear per passage, ~1e-6, is left out). ``progress(i, n)``, if
    given, is called after each of the n batches of probes."""
    N = scn.roughness.bays
    K = scn.harmonics
    J = N * K
    nums = scn.contact_numerics  # the contact parameters of each wheel: chain.wheel_material (its own creepage)
    s1 = dataclasses.replace(scn, roughness=dataclasses.replace(scn.roughness, bays=1))
    Z01 = np.zeros(2 * K + 1, dtype=complex)
    f1 = chain.solve_forces(s1, tabs[0], Roughness(Z01, 1))
    order = [int(l) for l in np.argsort(scn.wheels.positions)[::-1]]
    # the reference inputs of each wheel over one bay, and the smooth rail's wear before each wheel
    ref, cur1, wear_before = [], Roughness(Z01, 1), []
    for l in order:
        mi = wear.march_inputs(f1, l, cur1, chain.wheel_material(scn, l), nums, phase)
        ref.append(mi)
        w = chain.passage_wear(s1, f1, cur1, l, phase)
        wear_before.append(cur1.Z.copy())
        cur1 = wear.apply_wear(cur1, w.Z)
    # the same on the N-bay period (the 1-bay coefficients k on the lines k N)
    def on_period(Z1):
        Z = np.zeros(2 * J + 1, dtype=complex)
        Z[J + N * np.arange(-K, K + 1)] = Z1
        return Z
    probes = _tangent_batches(free, locked, N)
    cols = []  # (probe, wheel) -> columns
    names = _input_names(ref[0])
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
            Z = _probe_roughness(Z, j, kind, eps)
        fN = chain.solve_forces(scn, tabs, Roughness(Z, N))
        for w_i, l in enumerate(order):
            mi1, b0 = ref[w_i], base[w_i]
            mi = wear.march_inputs(fN, l, Roughness(Z + on_period(wear_before[w_i]), N), chain.wheel_material(scn, l), nums, phase,
                                   grid=(mi1.delta, mi1.Nx, mi1.M, mi1.spin))  # the smooth rail's grid
            # the same grid (the spin-up may differ by a step: positions are taken from each one's own)
            _held_grid(mi, mi1, N)
            _held_grid(b0, mi1, N)
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
    for w_i, l in enumerate(order):
        mi1 = ref[w_i]
        gw = gws.setdefault(mi1.Nx, np.zeros((mi1.Nx, ncol)))
        chunk = _column_chunk(mi1, ncol, max_columns)
        for c0 in range(0, ncol, chunk):
            sl = slice(c0, min(c0 + chunk, ncol))
            d = {name: np.moveaxis(np.array(dirs[w_i][name][sl]), 0, -1) for name in names}
            gw[:, sl] += _wear_tangent(scn, l, mi1, tabs[0].speed, d)[1]

    R, side, Ms = {}, {}, {}
    c = 0
    while c < ncol:
        j, kind, _ = cols[c]
        if kind == "free":
            R[j] = _line_coefficient(gws, c, j, N, c + 1)
            near = [j + m for m in (-N, N) if abs(j + m) <= J]
            side[j] = max(abs(_line_coefficient(gws, c, jj, N, c + 1)) for jj in near) / max(abs(R[j]), 1e-300) if near else 0.0
            c += 2
        else:
            Ms.setdefault(j, {})[kind] = _cos_sin_column(_line_coefficient(gws, c, j, N))
            c += 1
    Mout = {j: np.array([v["cos"], v["sin"]]).T for j, v in Ms.items()}
    return R, side, Mout


def _cell_linear_operators(scn, table, lines, eps, phase, max_columns=None, progress=None):
    """The 2 x 2 (cosine, sine) wear operators M at every line of a track cell, and the smooth rail's
    wear over the cell, by the tangent of the contact march about the smooth rail (method 'linear' of
    _cell_rate_spectrum).

    On a cell of N bays whose supports differ, the smooth rail's state is periodic over the cell, and
    the derivative of the wear for a roughness at line j is a general function over the cell: one
    march of the smooth rail over the cell (with its spin-up), carrying the derivative along a cosine
    and a sine probe of every line at once (rail.contact.tangent), gives every operator; the line's
    column is the derivative's Fourier coefficient at j (as a locked line of _linear_rates). Each
    column's inputs (force, half-length, pressure shape, step times at every step) are the difference
    of the model's own march inputs with and without a probe of amplitude eps (one force solve and
    one march_inputs per probe, no march), on the smooth rail's grid. With several wheels, each rolls
    on the smooth rail's wear of the wheels before it (from the tangent's own reference march); the
    derivative of that wear is left out, as in _linear_rates.

    Returns
    -------
    M : (n, 2, 2) [1 per train passage]; W0 : (2 N K + 1,) the smooth rail's wear of one train passage [m]
    """
    N = scn.roughness.bays
    Z0 = _smooth(scn)
    J = len(Z0) // 2
    probes = [(int(j), kind) for j in lines for kind in ("cos", "sin")]
    ncol = len(probes)
    f0 = chain.solve_forces(scn, table, Roughness(Z0, N))
    forces = [chain.solve_forces(scn, table, Roughness(_probe_roughness(Z0, j, kind, eps), N)) for j, kind in probes]
    order = [int(l) for l in np.argsort(scn.wheels.positions)[::-1]]
    nums = scn.contact_numerics
    cur, W0, gws, done = Roughness(Z0, N), np.zeros_like(Z0), {}, 0
    for l in order:
        mat = chain.wheel_material(scn, l)
        ref = wear.march_inputs(f0, l, cur, mat, nums, phase)
        grid = (ref.delta, ref.Nx // N, ref.M, ref.spin)
        names = _input_names(ref)
        gw = gws.setdefault(ref.Nx, np.zeros((ref.Nx, ncol)))
        chunk = _column_chunk(ref, ncol, max_columns)
        depth = None
        for c0 in range(0, ncol, chunk):
            cs = range(c0, min(c0 + chunk, ncol))
            d = {name: [] for name in names}
            for c in cs:
                j, kind = probes[c]
                mi = wear.march_inputs(forces[c], l, Roughness(cur.Z + _probe_roughness(Z0, j, kind, eps), N), mat, nums, phase, grid=grid)
                _held_grid(mi, ref, 1)
                for name in names:
                    d[name].append((getattr(mi, name) - getattr(ref, name)) / eps)
                done += 1
                if progress is not None:
                    progress(done, ncol * len(order))
            depth, dd = _wear_tangent(scn, l, ref, table.speed, {k: np.moveaxis(np.array(v), 0, -1) for k, v in d.items()})
            gw[:, c0:cs.stop] += dd
        Wl = wear.wear_spectrum(depth, J)
        W0 += Wl
        cur = wear.apply_wear(cur, Wl)
    M = np.zeros((len(lines), 2, 2))
    for n, j in enumerate(lines):
        for k in range(2):
            M[n, :, k] = _cos_sin_column(_line_coefficient(gws, 2 * n + k, int(j), 1))
    return M, W0


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


def _whole_number(name: str, value) -> int:
    """value as an int if it is a whole number >= 1 (2 and 2.0, not True, 2.5 or nan); else a ValueError naming it."""
    ok = (not isinstance(value, (bool, np.bool_)) and isinstance(value, (int, np.integer, float, np.floating))
          and np.isfinite(value) and value >= 1 and value == int(value))
    if not ok:
        raise ValueError(f"{name} = {value!r} is not allowed: it must be an integer >= 1.")
    return int(value)


def spectrum_lines(L: float, bays: int, harmonics: int, shortest: float, longest: float, per_octave: int):
    """The lines j of an N-bay period nearest to wavelengths spaced evenly in log over [shortest, longest].

    Parameters
    ----------
    L : float
        Sleeper spacing [m].
    bays : int
        Roughness period N [bays]; the lines are the wavenumbers 2 pi j / (N L), 1 <= j <= N K.
    harmonics : int
        K of the receptance tables [-]: the shortest wavelength represented is L / K.
    shortest, longest : float
        Wavelength range [m], 0 < shortest < longest; shortest = 0 means L / K, the shortest
        wavelength the receptance tables represent.
    per_octave : int
        Wavelengths per octave asked for [-], 1 to 1e9 (30: a tenth of a one-third octave).

    Returns
    -------
    ndarray of int
        Distinct lines, increasing (wavelength decreasing).

    Raises
    ------
    ValueError
        If L, bays, harmonics or per_octave is out of range, the wavelength range is empty or reaches
        below L / K, or the period is too short for the resolution: the lines' relative spacing 1 / j
        at the first line (the one at or just beyond the longest wavelength) must not exceed
        2^(1 / per_octave) - 1.
    """
    bays, harmonics, per_octave = (_whole_number(name, value) for name, value in
                                   (("bays", bays), ("harmonics", harmonics), ("per_octave", per_octave)))
    if per_octave > 10**9:  # 2^(1 / per_octave) - 1 would drown in rounding
        raise ValueError(f"per_octave = {per_octave!r} is not allowed: it must be an integer from 1 to 1e9.")
    if not (np.isfinite(L) and L > 0):
        raise ValueError(f"L = {L!r} m is not allowed: the sleeper spacing must be finite and > 0.")
    if shortest == 0:
        shortest = L / harmonics
    if not (np.isfinite(shortest) and np.isfinite(longest) and 0 < shortest < longest):
        raise ValueError(f"wavelengths shortest = {shortest!r} m, longest = {longest!r} m are not allowed: they must be finite "
                         "with 0 < shortest < longest (shortest 0: down to L / K).")
    if shortest < L / harmonics * (1 - 1e-12):
        raise ValueError(f"shortest = {shortest:g} m is not allowed: it must be >= L / K = {L / harmonics:.4g} m, the shortest "
                         f"wavelength the receptance tables represent (raise numerics.track.harmonics).")
    # The first line is the one at or just beyond the longest wavelength: the floor of N L / longest,
    # with the rounding of the division forgiven (0.6 / 0.1 = 5.999...: line 6, 0.1 m, not line 5)
    ratio = 2 ** (1 / per_octave)
    step = ratio - 1
    # The walk below moves on from line j only if a line lies within a step, floor(j 2^(1/per_octave)) > j;
    # as that holds at the first line, it holds at every later one (j step grows with j).
    j = int(np.floor(bays * L / longest * (1 + 1e-9)))
    if j < 1 or int(np.floor(j * ratio)) <= j:
        first = int(np.ceil(1 / step))  # the lowest line whose relative spacing 1 / j is within a step
        while int(np.floor(first * ratio)) <= first:
            first += 1
        need = int(np.ceil(first * longest / L / (1 + 1e-9)))
        if j < 1:
            raise ValueError(f"a roughness period of {bays} bays ({bays * L:g} m) is shorter than longest = {longest:g} m: "
                             f"use at least {need} bays.")
        raise ValueError(f"a roughness period of {bays} bays spaces the lines by {100 / j:.2g} % at "
                         f"{bays * L / j:g} m, coarser than 1/{per_octave} octave ({100 * step:.2g} %): use at least {need} bays.")
    # From the longest wavelength on, each next line lies between half a step and a step beyond the
    # last (so that neighbours are never further apart than 2^(1 / per_octave)); among those, the one
    # whose pair of classes {r, N - r} holds the fewest lines so far: rate_spectrum probes one line
    # per pair of classes per wear evaluation, so balanced classes need fewer evaluations.
    j_last = bays * harmonics
    chosen, count = [j], {}
    count[min(j % bays, -j % bays)] = 1
    while bays * L / j > shortest and j < j_last:
        lo, hi = int(np.ceil(j * np.sqrt(ratio))), min(int(np.floor(j * ratio)), j_last)
        if hi <= j:  # cannot happen after the check above; a guard so that the walk always ends
            raise ValueError(f"spectrum_lines: no line within 1/{per_octave} octave beyond line {j} of {bays} bays.")
        cands = range(min(max(lo, j + 1), hi), hi + 1)
        j = min(cands, key=lambda c: (count.get(min(c % bays, -c % bays), 0), -c))
        chosen.append(j)
        key = min(j % bays, -j % bays)
        count[key] = count.get(key, 0) + 1
    return np.array(chosen)


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
    Z0 = _smooth(scn)
    W0, _ = chain.train_wear(scn, table, Z0, grid_phase)
    return _locked(scn, table, j, eps, grid_phase, Z0, W0), W0


def _locked(scn, table, j, eps, grid_phase, Z0, W0):
    """M of locked_operator, with the smooth rail's wear W0 on the same grid given."""
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


def _smooth(scn: Scenario):
    return np.zeros(2 * scn.roughness.bays * scn.harmonics + 1, dtype=complex)


def _sorted_eigenvalues(M):
    """Eigenvalues of M, the faster-growing (smaller real part) first."""
    ev = np.linalg.eigvals(M).astype(complex)
    return ev[np.argsort(ev.real)]


def linear_unsupported(material) -> str:
    """What of the contact the tangent march (rail.contact.tangent, method 'linear') does not have, or ''.

    The tangent march differentiates the report's march: a fixed creepage (no u_bar) and the step
    friction law. The wheelset's modes, the rail's longitudinal flexibility and falling friction make
    rate_spectrum fall back to the probes.

    Parameters
    ----------
    material : rail.contact.ContactMaterial

    Returns
    -------
    str
        The missing mechanisms as text [-] ('' when the tangent march applies).
    """
    parts = []
    if material.longitudinal is not None:
        parts.append("dynamic creepage from the wheelset")
    if material.rail_flexibility is not None:
        parts.append("dynamic creepage from the rail's longitudinal flexibility")
    if material.friction_decay > 0:
        parts.append("falling friction")
    return " or ".join(parts)


def rate_spectrum(scn: Scenario, table, lines, eps: float = 1e-9, grid_phases: int = 2,
                  check_lines: int = 4, method: str = "linear", progress=None) -> RateSpectrum:
    """Growth-rate spectrum about the smooth rail at the given lines.

    Free lines by wear_rates (one probing cosine per pair of classes per wear evaluation over the N
    bays; on a track cell, scn.cell, every line as a locked line: _cell_rate_spectrum). Lines whose class is its own conjugate (the comb, j = k N, and for even N the half-comb,
    j = (k + 1/2) N) couple the roughness at +j and -j through the supports: there the cosine and the
    sine are probed separately on the shortest period that holds the line (1 bay for the comb,
    2 for the half-comb; the same classes of the same tables) and the eigenvalues of the 2 x 2
    operator are given.

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
    method : str
        'linear' (default): every line from one march of the smooth rail over one bay carrying the
        derivative of the contact along every probe (_linear_rates, rail.contact.tangent); the
        linearity is then the change of the rate from the derivative to probes of 2 eps. On a track
        cell (scn.cell), one march of the smooth rail over the cell carrying a cosine and a sine
        column for every line (_cell_linear_operators).
        'probe': the previous path, each line from the difference of two nonlinear marches over the
        N bays (one line per pair of classes per march, _batches; on a cell a cosine and a sine
        march per line), the reference of the tests; about seven times the cost at the default
        resolution (four times on the irregular_voided cell). With the wheelset's dynamic creepage or falling
        friction or the rail's longitudinal flexibility (scn.material.longitudinal, friction_decay,
        rail_flexibility) 'linear' falls back to 'probe', and the method says so.
    progress : callable, optional
        Called with one line of text as the work proceeds ("<i> of <n> probe batches, grid phase
        <p> of <P>"; method 'linear'; on a cell "<i> of <n> probe inputs ..." or, for 'probe',
        "<i> of <n> lines ..."); default None, silent.

    Returns
    -------
    RateSpectrum
    """
    N = scn.roughness.bays
    J = N * scn.harmonics
    lines = np.asarray(lines, dtype=int)
    if lines.size == 0 or np.any(lines < 1) or np.any(lines > J):
        raise ValueError(f"lines must be a non-empty set in [1, {J}] (N K).")
    if not (np.isfinite(eps) and eps > 0):
        raise ValueError(f"eps = {eps!r} m is not allowed: it must be a finite number > 0.")
    if not (isinstance(grid_phases, (int, np.integer)) and grid_phases >= 1):
        raise ValueError(f"grid_phases = {grid_phases!r} is not allowed: it must be an integer >= 1.")
    if method not in ("linear", "probe"):
        raise ValueError(f"method = {method!r} is not allowed: it must be 'linear' or 'probe'.")
    forced = ""
    if method == "linear" and (why := linear_unsupported(scn.material)):
        method, forced = "probe", f" (the tangent march has no {why})"
    if getattr(scn, "cell", None) is not None:
        sp = _cell_rate_spectrum(scn, table, lines, eps, grid_phases, method, progress=progress)
        return dataclasses.replace(sp, method=sp.method + forced)
    tabs = (table,) if isinstance(table, MovingReceptance) else tuple(table)
    locked = np.where(lines % N == 0, 1, np.where((N % 2 == 0) & (lines % N == N // 2) & (N > 1), 2, 0))
    if N == 1:
        locked[:] = 1
    free = np.flatnonzero(locked == 0)
    held = np.flatnonzero(locked)
    R = np.zeros((grid_phases, free.size), dtype=complex)
    Ms = np.zeros((grid_phases, held.size, 2, 2))
    source = np.zeros(lines.size)
    sideband = np.zeros(lines.size)
    changes = []
    fallbacks = []  # grid phases where method 'linear' fell back to the probes (GridMismatch)
    for p, phase in enumerate(np.arange(grid_phases) / grid_phases):
        linear = method == "linear"
        if linear:
            s_1 = dataclasses.replace(scn, roughness=dataclasses.replace(scn.roughness, bays=1))
            Z01 = _smooth(s_1)
            W01 = chain.train_wear(s_1, tabs[0], Z01, phase)[0]
            kinds = {int(lines[idx]): int(locked[idx]) for idx in held}
            probes = [(j, kind) for j in kinds for kind in ("cos", "sin")]
            step = None
            if progress is not None:
                def step(i, n, p=p):
                    progress(f"{p * n + i} of {grid_phases * n} probe batches (grid phase {p + 1} of {grid_phases}, "
                             f"{lines.size} lines)")
                    if i == n:
                        progress(f"grid phase {p + 1} of {grid_phases}: the tangent of the contact march over one bay, every probe at once")
            try:
                R_l, side_l, M_l = _linear_rates(scn, tabs, [int(j) for j in lines[free]], probes, eps, phase, progress=step)
            except GridMismatch as err:  # the probes of the nonlinear march for this grid phase
                fallbacks.append(f"grid phase {phase:g}: {err}")
                linear = False
        if linear:
            R[p] = [R_l[int(j)] for j in lines[free]]
            sideband[free] = np.maximum(sideband[free], [side_l[int(j)] for j in lines[free]])
            for n, idx in enumerate(held):
                Ms[p, n] = M_l[int(lines[idx])]
                if locked[idx] == 1:
                    source[idx] += 2 * abs(W01[len(W01) // 2 + int(lines[idx]) // N]) / grid_phases
            if p == 0:  # the linear range: probes of 2 eps against the derivative
                if progress is not None:
                    progress(f"linearity check: probes of 2 eps at {min(check_lines, free.size)} lines by the nonlinear march")
                if free.size:
                    Z0 = _smooth(scn)
                    W0 = np.zeros(Z0.size, dtype=complex)  # the smooth rail's wear is bay-periodic: on the lines k N
                    W0[len(Z0) // 2 + N * np.arange(-scn.harmonics, scn.harmonics + 1)] = W01
                    pick = np.unique(np.linspace(0, free.size - 1, min(check_lines, free.size)).round().astype(int))
                    R2 = _probe(scn, tabs, lines[free[pick]], 2 * eps, Z0, W0, phase)
                    changes += list(np.abs(R2.real / R[0, pick].real - 1))
                if held.size:
                    kind = int(locked[held[0]])
                    s_n = dataclasses.replace(scn, roughness=dataclasses.replace(scn.roughness, bays=kind))
                    t_n = tabs[0] if kind == 1 else (tabs[0], tabs[N // 2])
                    Z0n = _smooth(s_n)
                    W0n = chain.train_wear(s_n, t_n, Z0n, phase)[0]
                    M2 = _locked(s_n, t_n, int(lines[held[0]] * kind // N), 2 * eps, phase, Z0n, W0n)
                    changes.append(abs(_sorted_eigenvalues(M2)[0].real / _sorted_eigenvalues(Ms[0, 0])[0].real - 1))
            continue
        if free.size:
            Z0 = _smooth(scn)
            W0, _ = chain.train_wear(scn, tabs, Z0, phase)
            R[p], side_p = _probe(scn, tabs, lines[free], eps, Z0, W0, phase, sidebands=True)
            sideband[free] = np.maximum(sideband[free], side_p)
            if p == 0:
                pick = np.unique(np.linspace(0, free.size - 1, min(check_lines, free.size)).round().astype(int))
                R2 = _probe(scn, tabs, lines[free[pick]], 2 * eps, Z0, W0, phase)
                changes += list(np.abs(R2.real / R[0, pick].real - 1))
        periods = {}  # the 1- and 2-bay periods: scenario, tables, smooth rail and its wear
        for kind in sorted(set(locked[held].tolist())):
            s_n = dataclasses.replace(scn, roughness=dataclasses.replace(scn.roughness, bays=kind))
            t_n = tabs[0] if kind == 1 else (tabs[0], tabs[N // 2])
            Z0n = _smooth(s_n)
            periods[kind] = (s_n, t_n, Z0n, chain.train_wear(s_n, t_n, Z0n, phase)[0])
        for n, idx in enumerate(held):
            kind = int(locked[idx])
            s_n, t_n, Z0n, W0n = periods[kind]
            jn = int(lines[idx] * kind // N)  # the line in the 1- or 2-bay period
            Ms[p, n] = _locked(s_n, t_n, jn, eps, phase, Z0n, W0n)
            if kind == 1:
                source[idx] += 2 * abs(W0n[len(W0n) // 2 + jn]) / grid_phases
            if p == 0 and n == 0:
                M2 = _locked(s_n, t_n, jn, 2 * eps, phase, Z0n, W0n)
                changes.append(abs(_sorted_eigenvalues(M2)[0].real / _sorted_eigenvalues(Ms[0, 0])[0].real - 1))
    rate = np.zeros(lines.size, dtype=complex)
    other = np.zeros(lines.size, dtype=complex)
    spread = np.zeros(lines.size)
    rate[free] = R.mean(axis=0)
    other[free] = np.conj(rate[free])
    spread[free] = np.ptp(R.real, axis=0) / 2
    operator = np.zeros((lines.size, 2, 2))
    for n, idx in enumerate(held):
        operator[idx] = Ms[:, n].mean(axis=0)
        rate[idx], other[idx] = _sorted_eigenvalues(operator[idx])
        g = [_sorted_eigenvalues(M)[0].real for M in Ms[:, n]]
        spread[idx] = np.ptp(g) / 2
    return RateSpectrum(wavelength=N * scn.L / lines, line=lines, locked=locked, rate=rate, rate_other=other,
                        source=source, grid_spread=spread, sideband=sideband, linearity=float(max(changes)), eps=float(eps), bays=N,
                        grid_phases=int(grid_phases),
                        method=(method + forced) if not fallbacks else f"{method}, probes at " + "; ".join(fallbacks), operator=operator)


def _cell_rate_spectrum(scn: Scenario, table: MovingReceptance, lines, eps: float, grid_phases: int, method: str = "linear",
                        progress=None, max_columns=None) -> RateSpectrum:
    """rate_spectrum on a track periodic over a cell of N bays whose supports differ (rail.cell).

    The smooth rail's state is periodic over the cell, not over one bay, so the Bloch classes that
    keep the lines of the uniform track apart are coupled by the supports, and the cosine and the
    sine of every line couple through the cell harmonic 2 j: every line is treated as the comb of
    the uniform track is, by the 2 x 2 operator of a probing cosine and sine over the cell, its
    eigenvalues the rate and the other rate, and the smooth rail's wear at the line its parametric
    source. Method 'linear': every operator from one march of the smooth rail over the cell carrying
    the derivative along every probe (_cell_linear_operators); 'probe': two nonlinear marches over the
    cell per line and grid phase (_locked), the reference. The coupling of a line to the others (its
    sidebands j + m, every m) is not in the diagonal rate; growth runs (rail.chain.grow) carry it.
    ``progress(text)``, if given, is told as the work proceeds (after every line for 'probe', after
    every probe's inputs for 'linear').
    """
    N = scn.roughness.bays
    lines = np.asarray(lines, dtype=int)
    if not (isinstance(table, MovingReceptance) and table.supports is not None and table.bays == N):
        raise ValueError(f"a track cell of {N} bays needs its one table over the cell's harmonics (rail.moving.cell_receptance_table).")
    J = len(_smooth(scn)) // 2
    Ms = np.zeros((grid_phases, lines.size, 2, 2))
    source = np.zeros(lines.size)
    changes, fallbacks = [], []
    for p, phase in enumerate(np.arange(grid_phases) / grid_phases):
        Z0 = _smooth(scn)
        W0 = None
        if method == "linear":
            step = None
            if progress is not None:
                def step(i, n, p=p):
                    progress(f"{p * n + i} of {grid_phases * n} probe inputs (grid phase {p + 1} of {grid_phases}, {lines.size} lines, "
                             f"a cosine and a sine each over the cell of {N} bays)")
                    if i == n:
                        progress(f"grid phase {p + 1} of {grid_phases}: the tangent of the contact march over the cell, every probe at once")
            try:
                Ms[p], W0 = _cell_linear_operators(scn, table, lines, eps, phase, max_columns=max_columns, progress=step)
            except GridMismatch as err:  # the probes of the nonlinear march for this grid phase
                fallbacks.append(f"grid phase {phase:g}: {err}")
        if W0 is None:
            W0, _ = chain.train_wear(scn, table, Z0, phase)
            for n, j in enumerate(lines):
                Ms[p, n] = _locked(scn, table, int(j), eps, phase, Z0, W0)
                if progress is not None:
                    progress(f"{p * lines.size + n + 1} of {grid_phases * lines.size} lines (grid phase {p + 1} of {grid_phases}; "
                             f"a cosine and a sine probe each, marched over the cell of {N} bays)")
        source += 2 * np.abs(W0[J + lines]) / grid_phases
        if p == 0:
            if progress is not None:
                progress("linearity check: a probe of 2 eps at the first line by the nonlinear march")
            M2 = _locked(scn, table, int(lines[0]), 2 * eps, phase, Z0, W0)
            changes.append(abs(_sorted_eigenvalues(M2)[0].real / _sorted_eigenvalues(Ms[0, 0])[0].real - 1))
    rate = np.zeros(lines.size, dtype=complex)
    other = np.zeros(lines.size, dtype=complex)
    spread = np.zeros(lines.size)
    for n in range(lines.size):
        rate[n], other[n] = _sorted_eigenvalues(Ms[:, n].mean(axis=0))
        spread[n] = np.ptp([_sorted_eigenvalues(M)[0].real for M in Ms[:, n]]) / 2
    how = {"linear": "the tangent of the contact march over the cell at every line",
           "probe": "cosine and sine probes at every line (nonlinear march)"}[method]
    if fallbacks:
        how += "; probes at " + "; ".join(fallbacks)
    return RateSpectrum(wavelength=N * scn.L / lines, line=lines, locked=np.ones(lines.size, dtype=int), rate=rate, rate_other=other,
                        source=source, grid_spread=spread, sideband=np.zeros(lines.size), linearity=float(max(changes)), eps=float(eps),
                        bays=N, grid_phases=int(grid_phases), method=f"cell of {N} bays: {how}", operator=Ms.mean(axis=0))


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
    Z0 = _smooth(scn)
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
    return C, _sorted_eigenvalues(C)


@dataclass(frozen=True)
class FleetRateSpectrum:
    """The growth-rate spectrum under a fleet (fleet_rate_spectrum).

    total   : the traffic-weighted spectrum, rates per fleet passage (one train drawn from the traffic)
    classes : the spectrum of each (vehicle, speed) class, rates per passage of that class's train
    weights : (c,) the classes' weights w_c [-], summing to 1
    labels  : (c,) '<vehicle> at <speed> m/s'
    speeds  : (c,) the classes' speeds [m/s]
    """

    total: RateSpectrum
    classes: tuple
    weights: np.ndarray
    labels: tuple
    speeds: np.ndarray


def combine_spectra(spectra, weights) -> RateSpectrum:
    """The weighted sum of growth-rate spectra on the same lines (the wear is linear about the smooth rail).

    At a free line the rate is sum_c w_c R_c; at a locked line the 2 x 2 operators are summed and the
    rates are the eigenvalues of sum_c w_c M_c (not the sum of the eigenvalues, unless the classes'
    operators commute). The smooth rail's source and the grid spread are summed with the weights: an
    upper bound, since the classes' smooth-rail wear and grid errors need not be in phase. The sideband
    ratio and the linearity are the largest over the classes.

    Parameters
    ----------
    spectra : sequence of RateSpectrum
        On the same lines and period.
    weights : sequence of float
        w_c [-].

    Returns
    -------
    RateSpectrum
    """
    first = spectra[0]
    w = np.asarray(weights, dtype=float)
    if any(not np.array_equal(s.line, first.line) or s.bays != first.bays for s in spectra):
        raise ValueError("the classes' spectra must share their lines and period (one spectrum_lines call).")
    rate = sum(wc * s.rate for wc, s in zip(w, spectra))
    other = np.conj(rate)
    held = np.flatnonzero(first.locked)
    operator = None
    if held.size:
        if any(s.operator is None for s in spectra):
            raise ValueError("a locked line needs the classes' 2 x 2 operators (RateSpectrum.operator).")
        operator = sum(wc * s.operator for wc, s in zip(w, spectra))
        for idx in held:
            rate[idx], other[idx] = _sorted_eigenvalues(operator[idx])
    methods = sorted({s.method for s in spectra})
    return RateSpectrum(wavelength=first.wavelength, line=first.line, locked=first.locked, rate=rate, rate_other=other,
                        source=sum(wc * s.source for wc, s in zip(w, spectra)),
                        grid_spread=sum(wc * s.grid_spread for wc, s in zip(w, spectra)),
                        sideband=np.max([s.sideband for s in spectra], axis=0), linearity=max(s.linearity for s in spectra),
                        eps=first.eps, bays=first.bays, grid_phases=first.grid_phases, method="; ".join(methods), operator=operator)


def fleet_rate_spectrum(classes, tables: dict, lines, **kwargs) -> FleetRateSpectrum:
    """Growth-rate spectrum about the smooth rail under a fleet: the traffic-weighted rate per
    wavelength, sum_c w_c R_c per fleet passage (combine_spectra), with each class's spectrum kept.

    Parameters
    ----------
    classes : sequence of rail.fleet.FleetClass
        Each with roughness.bays = N (the lines' period).
    tables : dict
        {speed: the N-bay period's receptance tables} (rail.chain.fleet_tables), shared by the
        vehicles at a speed.
    lines : sequence of int
        Lines j, 1 <= j <= N K [-] (wavenumbers 2 pi j / (N L)).
    **kwargs
        Passed to rate_spectrum (eps, grid_phases, check_lines, method).

    Returns
    -------
    FleetRateSpectrum
    """
    return fleet_spectrum_of(classes, [rate_spectrum(c.scenario, tables[c.speed], lines, **kwargs) for c in classes])


def fleet_spectrum_of(classes, spectra) -> FleetRateSpectrum:
    """The fleet's spectrum from its classes' spectra computed apart (each a job of the workflow, shared
    by the fleets that hold the class): combine_spectra with the classes' weights.

    Parameters
    ----------
    classes : sequence of rail.fleet.FleetClass
    spectra : sequence of RateSpectrum
        rate_spectrum of each class on the same lines, in the order of classes (rates per passage of
        the class's train [-]).

    Returns
    -------
    FleetRateSpectrum
        Rates per fleet passage [-].
    """
    spectra = tuple(spectra)
    if len(spectra) != len(classes):
        raise ValueError(f"{len(spectra)} spectra for {len(classes)} classes: give one spectrum per class.")
    w = np.array([c.weight for c in classes])
    return FleetRateSpectrum(combine_spectra(spectra, w), spectra, w, tuple(c.label for c in classes),
                             np.array([c.speed for c in classes]))
