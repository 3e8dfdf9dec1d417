"""Normal wheel/rail forces for wheels moving over a rail with bay-periodic roughness (report sec. 4.2).

Conventions
-----------
* Time factor exp(+i p Omega_0 t), Omega_0 = 2 pi V / L.  Wheel l is at x = a_l + V t; x = 0 is a
  support.
* Roughness z(x) = sum_k Z_k exp(i k beta0 x) is the rail-head height, positive upwards (eq 18).
* Rail displacement u and wheel displacement z_w positive downwards; the contact force P is the
  compression of the contact (positive when pressing), acting downwards on the rail.
* Contact spring: P = k_H (1 + i eta_H(omega)) (z_w - u + z) for the dynamic part; the
  mean force of every wheel equals its static load.

Harmonic balance (eq 21), for every wheel l and harmonic p != 0::

    (1 / k_H(omega_p) - 1 / (M omega_p^2)) P_lp + sum_j sum_k A^{lj}[p, k] P_jk = Z_lp,
    A^{lj}[p, k] = A_{a_l - a_j}[p, k] exp(i (p - k) beta0 a_j),   Z_lp = Z_p exp(i p beta0 a_l),

where A_d is the moving-load receptance table (rail.moving) and the k = 0 terms, with
P_j0 = the static load, are the parametric excitation by the supports.  The wheel is a rigid mass
(receptance -1/(M omega^2)).
"""

from __future__ import annotations

import dataclasses
import functools
from dataclasses import dataclass

import numpy as np

from .csvinput import data_rows
from .moving import MovingReceptance

__all__ = [
    "Wheels",
    "ContactSpring",
    "Roughness",
    "ContactLossError",
    "ForceResult",
    "allowed_wavelengths",
    "read_roughness_coefficients",
    "solve_forces",
    "force_history",
    "force_on_grid",
    "tail_coefficients",
    "force_tail",
]


@dataclass(frozen=True)
class Wheels:
    """Rigid wheels of one train (section 6).

    Attributes
    ----------
    mass : kg, > 0 (each wheel)
    radius : m, > 0
    static_load : N, > 0 (each wheel; the mean contact force)
    positions : m, positions a_l along the train (the first wheel passes a support at t = 0)
    creepage : -, one signed creepage per wheel (eq 25; rail.fleet), or None for the contact's
                  creepage on every wheel (rail.contact.ContactMaterial.creepage)
    wheelsets : one wheelset's modes per wheel (rail.creepage.modes.LongitudinalModes, or None for the
                  report's fixed creepage; rail.creepage.wheelset.wheelset_modes, rail.fleet), or None for the
                  contact's on every wheel (rail.contact.ContactMaterial.longitudinal); read only by the
                  contact of each wheel (rail.chain.wheel_material), not by the vertical forces
    """

    mass: float
    radius: float
    static_load: float
    positions: tuple
    creepage: tuple | None = None
    wheelsets: tuple | None = None

    def __post_init__(self):
        for name in ("mass", "radius", "static_load"):
            v = getattr(self, name)
            if not (np.isfinite(v) and v > 0):
                raise ValueError(f"wheels.{name} = {v!r} is not allowed: it must be > 0.")
        if len(self.positions) < 1:
            raise ValueError("wheels.positions = [] is not allowed: give at least one wheel position.")
        if len(set(self.positions)) != len(self.positions):
            raise ValueError(f"wheels.positions = {list(self.positions)} is not allowed: two wheels at one position.")
        if self.creepage is not None and len(self.creepage) != len(self.positions):
            raise ValueError(f"wheels.creepage has {len(self.creepage)} values: it needs one per wheel ({len(self.positions)}).")
        if self.wheelsets is not None and len(self.wheelsets) != len(self.positions):
            raise ValueError(f"wheels.wheelsets has {len(self.wheelsets)} entries: it needs one per wheel ({len(self.positions)}).")

    def __repr__(self):
        # the dataclass's own form, with ``wheelsets`` only where the wheels carry their own: wheels without them
        # keep the text they had before it existed, and with it the class keys hashed from that text
        # (rail.setup.study_files.class_key; issue 55: old fleet files plan identically)
        shown = [f for f in dataclasses.fields(self) if f.name != "wheelsets" or self.wheelsets is not None]
        return f"{type(self).__qualname__}({', '.join(f'{f.name}={getattr(self, f.name)!r}' for f in shown)})"

    def receptance(self, omega):
        """The wheel's vertical point receptance at the contact alpha_W(omega) [m/N] at omega != 0 [rad/s]: the
        rigid wheel's -1 / (m omega^2) (eq 21). The force path (solve_forces) reads the wheel only through
        this method, so a flexible (modal) wheel is a subclass that returns its own receptance in the same
        convention (displacement of the wheel towards the rail per unit contact force)."""
        w = np.asarray(omega, dtype=float)
        return -1.0 / (self.mass * w**2)


@dataclass(frozen=True)
class ContactSpring:
    """Linearised Hertz contact spring k_H (1 + i eta_H(omega)), N/m.

    Attributes
    ----------
    hertz_stiffness : k_H, N/m, > 0
    loss_slope : s/rad; eta_H = loss_slope * omega (the half-space model, Fig. 6, is exactly
                      proportional to frequency, i.e. a dashpot k_H * loss_slope)
    loss_factor : constant eta_H (hysteretic, sign(omega)), used when loss_slope is 0
    """

    hertz_stiffness: float
    loss_slope: float = 0.0
    loss_factor: float = 0.0

    def __post_init__(self):
        if not (np.isfinite(self.hertz_stiffness) and self.hertz_stiffness > 0):
            raise ValueError(f"contact.hertz_stiffness = {self.hertz_stiffness!r} N/m is not allowed: it must be a finite number > 0.")
        for name in ("loss_slope", "loss_factor"):
            v = getattr(self, name)
            if not (np.isfinite(v) and v >= 0):
                raise ValueError(f"contact spring {name} = {v!r} is not allowed: it must be a finite number >= 0.")

    def stiffness(self, omega):
        omega = np.asarray(omega, dtype=float)
        eta = self.loss_slope * omega + self.loss_factor * np.sign(omega)
        return self.hertz_stiffness * (1 + 1j * eta)


@dataclass(frozen=True)
class Roughness:
    """Rail-head roughness periodic over N bays (eqs 18-19 with the period N L).

    Attributes
    ----------
    Z : coefficients Z_j [m], j = -J..J, of z(x) = sum_j Z_j exp(i j beta0 x / N), Z_0 = 0;
           J = N K for K harmonics of the sleeper-passing frequency
    bays : N [-], the period in sleeper bays (1: today's bay-periodic roughness, j = k)
    """

    Z: np.ndarray
    bays: int = 1

    @property
    def harmonics(self) -> int:
        """J, the highest index j of Z (N K) [-]."""
        return (len(self.Z) - 1) // 2

    @staticmethod
    def smooth(K: int, bays: int = 1) -> "Roughness":
        return Roughness(np.zeros(2 * K * bays + 1, dtype=complex), bays)

    @staticmethod
    def harmonic(amplitude: float, wavelength: float, L: float, K: int, bays: int = 1) -> "Roughness":
        """z(x) = amplitude cos(2 pi x / wavelength), x = 0 at a sleeper (section 6); the wavelength
        must divide the period N L."""
        m = bay_harmonic(wavelength, bays * L)
        if m > K * bays:
            raise ValueError(
                f"roughness wavelength {wavelength} m is harmonic {m} of the {bays}-bay period: it needs "
                f"numerics.track.harmonics >= {int(np.ceil(m / bays))} (now {K})."
            )
        J = K * bays
        Z = np.zeros(2 * J + 1, dtype=complex)
        Z[J + m] = Z[J - m] = amplitude / 2
        return Roughness(Z, bays)

    @staticmethod
    def from_coefficients(k, A, B, K: int, bays: int = 1) -> "Roughness":
        """z(x) = sum_k A_k cos(k beta0 x) + B_k sin(k beta0 x), k >= 1 harmonics of the bay (eqs 18-19)."""
        J = K * bays
        Z = np.zeros(2 * J + 1, dtype=complex)
        for kk, a, b in zip(k, A, B):
            kk = int(kk)
            if kk < 1 or kk > K:
                raise ValueError(f"roughness harmonic k = {kk} is not allowed: it must lie in [1, {K}].")
            Z[J + kk * bays] = 0.5 * (a - 1j * b)
            Z[J - kk * bays] = 0.5 * (a + 1j * b)
        return Roughness(Z, bays)

    def profile(self, x, L: float):
        """z(x) (eq 18) [m] at the positions x [m]; L [m] is the sleeper spacing (beta0 = 2 pi / L)."""
        J = self.harmonics
        j = np.arange(-J, J + 1)
        return np.real(np.exp(1j * np.outer(np.asarray(x), j * (2 * np.pi / (L * self.bays)))) @ self.Z)


def allowed_wavelengths(wavelength: float, L: float) -> tuple[float, float]:
    """The two wavelengths L / m nearest to ``wavelength`` that fit a whole number of times in the bay.

    Parameters
    ----------
    wavelength : float
        Roughness wavelength [m].
    L : float
        Bay length [m].

    Returns
    -------
    tuple of float
        The shorter and the longer allowed wavelength [m].
    """
    m = L / wavelength
    lo, hi = max(int(np.floor(m)), 1), max(int(np.ceil(m)), 1)
    return L / hi, L / lo


def bay_harmonic(wavelength: float, L: float, rtol: float = 1e-6) -> int:
    """Harmonic number m = L / wavelength of the bay (eq 18).

    Parameters
    ----------
    wavelength : float
        Roughness wavelength [m].
    L : float
        Bay length [m].
    rtol : float
        Relative tolerance on m being whole [-].

    Returns
    -------
    int
        m [-].

    Raises
    ------
    ValueError
        If the wavelength is not positive or does not divide the bay; the message names the nearest
        allowed wavelengths.
    """
    if not (np.isfinite(wavelength) and wavelength > 0):
        raise ValueError(f"roughness wavelength = {wavelength!r} m is not allowed: it must be > 0.")
    m = L / wavelength
    if abs(m - round(m)) > rtol * m or round(m) < 1:
        a, b = allowed_wavelengths(wavelength, L)
        raise ValueError(
            f"roughness wavelength = {wavelength:.6g} m does not fit a whole number of times into the "
            f"sleeper bay L = {L} m (L / wavelength = {m:.4f}); the nearest allowed wavelengths are "
            f"{a:.6g} m and {b:.6g} m (L / {round(L / a)} and L / {round(L / b)})."
        )
    return int(round(m))


COEFFICIENT_MAX_M = 0.01  # m: a plausible roughness amplitude A_k, B_k (as rail.roughness.PROFILE_MAX_HEIGHT_M)


def read_roughness_coefficients(path):
    """Read eq (18) roughness coefficients from a CSV file with the header ``k,A_m,B_m``.

    Parameters
    ----------
    path : str or Path
        CSV file: harmonic k >= 1 of the bay, and the cosine and sine amplitudes A_k, B_k [m].

    Returns
    -------
    k : list of int
    A, B : list of float
        [m].

    Raises
    ------
    ValueError
        Naming the file and the line of a wrong header, row or harmonic, or an amplitude beyond
        COEFFICIENT_MAX_M = 10 mm either way.
    """
    ks, A, B = [], [], []
    rows_k = {}
    for n, row in data_rows(path, ("k", "A_m", "B_m")):
        if len(row) != 3:
            raise ValueError(f"{path}, line {n}: expected 3 values k,A_m,B_m, got {len(row)}.")
        try:
            k, a, b = int(row[0]), float(row[1]), float(row[2])
        except ValueError:
            raise ValueError(f"{path}, line {n}: {','.join(row)!r} is not an integer k and two numbers in m.") from None
        if k < 1:
            raise ValueError(f"{path}, line {n}: harmonic k = {k} is not allowed: it must be >= 1.")
        if not (np.isfinite(a) and np.isfinite(b)):
            raise ValueError(f"{path}, line {n}: the amplitudes {','.join(row[1:])} are not finite.")
        if not (abs(a) <= COEFFICIENT_MAX_M and abs(b) <= COEFFICIENT_MAX_M):
            raise ValueError(f"{path}, line {n}: the amplitudes {','.join(c.strip() for c in row[1:])} m are not allowed: a rail "
                             f"roughness amplitude lies within ±{COEFFICIENT_MAX_M * 1000:g} mm (valid range [-{COEFFICIENT_MAX_M:g}, "
                             f"{COEFFICIENT_MAX_M:g}] m); write A_m and B_m in metres.")
        if k in ks:
            raise ValueError(f"{path}, line {n}: harmonic k = {k} is given twice (first at line {rows_k[k]}).")
        rows_k[k] = n
        ks.append(k)
        A.append(a)
        B.append(b)
    if not ks:
        raise ValueError(f"{path}: has a header but no harmonic: give at least one line k,A_m,B_m (a smooth rail is roughness.kind: smooth).")
    return ks, A, B


class ContactLossError(RuntimeError):
    """The contact force falls to zero or below: the linear wheel/rail model no longer holds."""


@dataclass(frozen=True)
class ForceResult:
    """Force harmonics P[l, j] [N] of every wheel at the frequencies j Omega_0 / N, j = -J..J
    (P[l, 0] = static load); N = bays, J = N K.  ``supports``: for a track periodic over a cell of
    N bays (rail.cell), the positions of its point attachments in the period [m], where the force
    has its kinks (tail_coefficients); None for the uniform track."""

    P: np.ndarray
    speed: float
    L: float
    positions: np.ndarray
    bays: int = 1
    supports: np.ndarray | None = None

    @property
    def harmonics(self) -> int:
        """J, the highest index j [-]."""
        return (self.P.shape[1] - 1) // 2

    @property
    def period(self) -> float:
        """N L, the period of the force history in wheel position [m]."""
        return self.bays * self.L

    @property
    def beta0(self) -> float:
        """Bay wavenumber 2 pi / L [rad/m]."""
        return 2 * np.pi / self.L


def _coupling(tab: MovingReceptance, positions, L: float):
    """A^{lj}[p, k] = A_{a_l - a_j}[p, k] exp(i (p - k) beta0 a_j), beta0 = 2 pi / L, shape (l, j, p, k)."""
    beta0 = 2 * np.pi / L
    h = tab.indices
    n = len(positions)
    out = np.empty((n, n, len(h), len(h)), dtype=complex)
    for l, al in enumerate(positions):
        for j, aj in enumerate(positions):
            d = al - aj
            idx = np.where(np.isclose(tab.offsets, d, atol=1e-9))[0]
            if len(idx) == 0:
                raise ValueError(f"the receptance table holds no offset d = {d} m (wheels {l} and {j}); it has {list(tab.offsets)}.")
            phase = np.exp(1j * np.subtract.outer(h, h) * beta0 * aj)
            out[l, j] = tab.A[idx[0]] * phase
    return out


def _solve_class(tab: MovingReceptance, wheels: Wheels, contact: ContactSpring, Zc, L: float, bays: int):
    """Force harmonics of one Bloch class (frequencies (m + nu) Omega_0, nu = tab.fraction) for
    roughness coefficients Zc at those frequencies (index m): the linear system of eq 21."""
    beta0 = 2 * np.pi / L
    K = tab.harmonics
    m = tab.indices
    f = m + tab.fraction  # frequency in units of Omega_0
    pos = np.asarray(wheels.positions, dtype=float)
    n = len(pos)
    A = _coupling(tab, pos, L)
    dyn = f != 0
    om = f[dyn] * tab.speed * beta0
    self_term = 1.0 / contact.stiffness(om) + wheels.receptance(om)  # the contact spring's and the wheel's receptance
    nd = int(dyn.sum())
    M = np.zeros((n * nd, n * nd), dtype=complex)
    rhs = np.zeros(n * nd, dtype=complex)
    for l in range(n):
        rows = slice(l * nd, (l + 1) * nd)
        rhs[rows] = Zc[dyn] * np.exp(1j * f[dyn] * beta0 * pos[l])
        for j in range(n):
            cols = slice(j * nd, (j + 1) * nd)
            M[rows, cols] = A[l, j][np.ix_(dyn, dyn)]
            if tab.fraction == 0:
                rhs[rows] -= A[l, j][dyn, K] * wheels.static_load
        M[rows, rows] += np.diag(self_term)
    sol = np.linalg.solve(M, rhs)
    if not np.all(np.isfinite(sol)):
        raise FloatingPointError(
            f"the force harmonics are not finite at V = {tab.speed:g} m/s (the coupled wheel/track system is singular: "
            f"an undamped resonance at a multiple of the sleeper-passing frequency); check the damping of the track and contact."
        )
    P = np.zeros((n, len(m)), dtype=complex)
    if tab.fraction == 0:
        P[:, K] = wheels.static_load
    P[:, dyn] = sol.reshape(n, nd)
    return P


def solve_forces(
    tab, wheels: Wheels, contact: ContactSpring, roughness: Roughness, L: float, check_contact: bool = True
) -> ForceResult:
    """Solve the coupled harmonic balance for the force harmonics of every wheel (eq 21).

    For a roughness periodic over N bays (Sheng, Jones & Thompson 2007) the force is a Fourier
    series in Omega_0 / N, and the harmonics j = r + m N of each class r couple only among
    themselves: N independent systems with the receptance tables of the Bloch fractions nu = r / N.
    The classes r > N/2 are the complex conjugates of N - r (a real load), so only r <= N/2 are
    solved. N = 1 is the report's bay-periodic problem.

    Parameters
    ----------
    tab : MovingReceptance or sequence of MovingReceptance
        Receptance table(s) at the train's speed with every wheel offset [m/N]: one table (N = 1),
        or the tables of the fractions r / N, r = 0..floor(N/2) (rail.moving.bloch_tables).
    wheels : Wheels
        The train's wheels.
    contact : ContactSpring
        Linearised Hertz spring [N/m].
    roughness : Roughness
        Roughness periodic over N = roughness.bays bays [m]; its harmonics are truncated or
        zero-padded to the tables' K.
    L : float
        Sleeper spacing [m] (beta0 = 2 pi / L).
    check_contact : bool
        Refuse a force that falls to zero or below (default); False gives the linear model's force as
        it is, to record the state a stopped growth run broke at.

    Returns
    -------
    ForceResult
        Force harmonics P[l, j] of every wheel [N], j = -N K..N K.

    Raises
    ------
    ContactLossError
        Where any wheel's force P_l(x) falls to zero or below (check_contact).
    """
    N = int(roughness.bays)
    if not np.all(np.isfinite(roughness.Z)):
        raise ValueError("the roughness coefficients are not finite (NaN or inf): check the roughness input.")
    if isinstance(tab, MovingReceptance) and tab.supports is not None:
        return _solve_cell(tab, wheels, contact, roughness, L, check_contact)
    tabs = (tab,) if isinstance(tab, MovingReceptance) else tuple(tab)
    if len(tabs) != N // 2 + 1 or any(not np.isclose(t.fraction, r / N) for r, t in enumerate(tabs)):
        raise ValueError(f"a roughness periodic over {N} bays needs the receptance tables of the fractions r / {N}, "
                         f"r = 0..{N // 2}; got fractions {[t.fraction for t in tabs]}.")
    K = tabs[0].harmonics
    J = N * K
    Z = _roughness_to(roughness, J, K)
    n = len(wheels.positions)
    P = np.zeros((n, 2 * J + 1), dtype=complex)
    for r, t in enumerate(tabs):
        j = r + N * t.indices  # the harmonics of class r
        Pc = _solve_class(t, wheels, contact, Z[J + j], L, N)
        P[:, J + j] = Pc
        if 0 < r and 2 * r != N:  # class N - r: the conjugates of -j
            P[:, J - j] = np.conj(Pc)
    result = ForceResult(P, tabs[0].speed, L, np.asarray(wheels.positions, dtype=float), N)
    if check_contact:
        _check_contact(result)
    return result


def _roughness_to(roughness: Roughness, J: int, K: int):
    """The roughness coefficients truncated or zero-padded to |j| <= J (a table's harmonics); an
    error naming K if a dropped harmonic is not zero."""
    Z = np.zeros(2 * J + 1, dtype=complex)
    Jr = roughness.harmonics
    c = min(J, Jr)
    Z[J - c : J + c + 1] = roughness.Z[Jr - c : Jr + c + 1]
    if Jr > J and np.any(roughness.Z[: Jr - J] != 0):
        raise ValueError(f"the roughness has harmonics above K = {K}; raise numerics.track.harmonics.")
    return Z


def _solve_cell(tab: MovingReceptance, wheels: Wheels, contact: ContactSpring, roughness: Roughness, L: float,
                check_contact: bool = True) -> ForceResult:
    """solve_forces with the table of a track periodic over a cell of N bays (rail.moving.cell_receptance_table):
    one system over every harmonic j Omega_0 / N of the cell, |j| <= N K (the irregular supports
    couple what the Bloch classes of the uniform track keep apart)."""
    N = int(roughness.bays)
    if tab.bays != N:
        raise ValueError(f"the receptance table is of a track cell of {tab.bays} bays, the roughness is periodic over "
                         f"{N}: roughness.bays must equal the cell's bays ({tab.bays}).")
    J = tab.harmonics
    Z = _roughness_to(roughness, J, J // N)
    P = _solve_class(tab, wheels, contact, Z, N * L, 1)
    sup = None if tab.supports is None else np.asarray(tab.supports, dtype=float)
    result = ForceResult(P, tab.speed, L, np.asarray(wheels.positions, dtype=float), N, sup)
    if check_contact:
        _check_contact(result)
    return result


def tail_coefficients(result: ForceResult):
    """Tail of every wheel's force harmonics beyond K, modelled as C_l / p^2 (p > 0; conjugate for p < 0).

    Parameters
    ----------
    result : ForceResult

    Returns
    -------
    ndarray, shape (wheels,)
        C_l = K^2 P_lK exp(-i K beta0 a_l) [N], in each wheel's own bay frame.

    Notes
    -----
    The rail deflection under a moving wheel has a slope discontinuity at every support, so the
    force harmonics fall like 1/p^2 and a plain truncation at K errs by O(1/K) at the sleeper
    (review notes).  p^2 P_p settles to a constant within a few per cent beyond p ~ 30 (tested).
    For a track periodic over a cell the kinks differ from support to support: see force_tail.
    """
    N = result.bays
    K = result.harmonics // N
    return K**2 * result.P[:, result.harmonics + K * N] * np.exp(-1j * K * result.beta0 * result.positions)


def force_tail(result: ForceResult, tail_harmonics: int | None = None):
    """The harmonics beyond J that the 1/q^2 kink model adds to every wheel's force.

    The force has a kink wherever the wheel passes a support (or another point attachment of a
    cell, ``result.supports``; the uniform track's N supports s_j = j L of the period otherwise), of
    a strength of its own: the wheel's force there differs from bay to bay under a roughness periodic
    over N bays, and so does each support's reaction on an irregular track.  The tail is
    sum_j C_lj exp(-i q beta_P s_j) / q^2 over every harmonic q > J of the period, beta_P = 2 pi / (N L);
    the Q strengths C_lj are those that reproduce the top Q harmonics q = J - Q + 1..J of the wheel's
    force (an exact Q x Q solve).  For one support (N = 1) this is tail_coefficients' C_l / p^2.
    Measured against K = 96 for a roughness over three bays (K = 24): the tail harmonics outside the
    multiples of N, which a tail on the multiples alone leaves out (0.06-0.09 N), are predicted
    within 0.003-0.005 N; the force history is then within 0.45 % of the fluctuation of K = 96
    (0.48 % with the multiples alone, 4.3 % without a tail).

    Parameters
    ----------
    result : ForceResult
    tail_harmonics : int, optional
        Tail length in bay harmonics (default 16 K).

    Returns
    -------
    q : ndarray of int
        Cell harmonics q > J of the tail (frequencies q Omega_0 / N) [-].
    T : complex ndarray, shape (wheels, len(q))
        Their coefficients [N] in the track's frame (the wheel at x: sum_q T_q e^{i q beta0 x / N} + c.c.).
    """
    N = result.bays
    J = result.harmonics
    K = J // N
    M = tail_harmonics if tail_harmonics is not None else 16 * K
    s = np.arange(N) * result.L if result.supports is None else np.asarray(result.supports, dtype=float)
    Q = len(s)
    bP = result.beta0 / N
    qfit = np.arange(J - Q + 1, J + 1)
    E = np.exp(-1j * bP * np.outer(qfit, s))  # (fit harmonic, attachment)
    rhs = (qfit[None, :] ** 2 * result.P[:, J + qfit] * np.exp(-1j * bP * np.outer(result.positions, qfit))).T
    C = np.linalg.lstsq(E, rhs, rcond=1e-12)[0].T  # (wheel, attachment); exact unless two attachments nearly coincide
    q = np.arange(J + 1, J + M * N + 1)
    T = (C @ _tail_phases(float(bP), tuple(s.tolist()), J + 1, J + M * N)) / q[None, :] ** 2
    return q, T


@functools.lru_cache(maxsize=4)
def _tail_phases(bP: float, s: tuple, q_first: int, q_last: int):
    """exp(-i q beta_P s_j) of force_tail, kept for the next call on the same track (it does not depend on the force).

    Parameters
    ----------
    bP : float
        beta_P = 2 pi / (N L) [rad/m].
    s : tuple of float
        The attachments s_j [m].
    q_first, q_last : int
        The tail's harmonics q = q_first..q_last [-].

    Returns
    -------
    ndarray, shape (len(s), q_last - q_first + 1), complex, read-only
        The phase factors [-] (48 supports x 49,152 harmonics: 38 MB).
    """
    q = np.arange(q_first, q_last + 1)
    E = np.exp(-1j * bP * np.outer(np.asarray(s, dtype=float), q))
    E.flags.writeable = False
    return E


def force_history(result: ForceResult, x, tail: bool = True, tail_harmonics: int | None = None):
    """P_l(x): force of every wheel when it is at position x in the bay (eq 21 summed).

    Parameters
    ----------
    result : ForceResult
        Force harmonics [N].
    x : array_like
        Wheel positions in the bay [m], 0 above a support.
    tail : bool
        Add the harmonics K < p <= K + tail_harmonics (default 16 K) from the 1/p^2 model of
        tail_coefficients; the remaining truncation is O(1/(17 K)) instead of O(1/K).

    Returns
    -------
    ndarray, shape (wheels, len(x))
        Contact force [N], positive in compression.
    """
    beta0 = result.beta0
    J = result.harmonics
    K = J // result.bays
    h = np.arange(-J, J + 1) / result.bays
    x = np.asarray(x, dtype=float)
    out = np.empty((len(result.positions), len(x)))
    for l, a in enumerate(result.positions):
        out[l] = np.real(np.exp(1j * np.outer(x - a, h * beta0)) @ result.P[l])
    if tail and K > 0:
        q, T = force_tail(result, tail_harmonics)
        for start in range(0, len(x), 512):
            xs = x[start : start + 512]
            E = np.exp(1j * np.outer(xs, q * beta0 / result.bays))  # (x, q)
            out[:, start : start + 512] += 2 * np.real(T @ E.T)
    return out


def force_on_grid(result: ForceResult, n: int, tail: bool = True, tail_harmonics: int | None = None, derivative: int = 0):
    """force_history at the n uniform positions x_k = k N L / n of the period, by one FFT per wheel
    (or its derivative d^m P / dx^m along the rail, m = ``derivative``).

    At these points every harmonic e^{i j beta0 x / N} equals e^{i 2 pi (j mod n) k / n}, so the
    coefficients (with the 1/p^2 tail) are folded into n bins and summed exactly by an inverse FFT:
    O(n log n) instead of the O(n J) of the direct sum, the same values to rounding.

    Parameters
    ----------
    result : ForceResult
        Force harmonics [N].
    n : int
        Number of positions over the period [-].
    tail, tail_harmonics
        As force_history.
    derivative : int
        m >= 0: the m-th derivative in the wheel's position (each harmonic times (i p beta0 / N)^m; at a
        support, where the slope of the force jumps, the series gives the mean of the two sides).

    Returns
    -------
    ndarray, shape (wheels, n)
        Contact force [N] (its m-th derivative [N/m^m]) with the wheel at x_k = k N L / n.
    """
    J, N = result.harmonics, result.bays
    K = J // N
    j = np.arange(-J, J + 1)
    out = np.empty((len(result.positions), n))
    q, T = force_tail(result, tail_harmonics) if tail and K > 0 else (None, None)
    for l, a in enumerate(result.positions):
        acc = np.zeros(n, dtype=complex)
        if derivative:
            dj, dq = (1j * j * result.beta0 / N) ** derivative, (1j * q * result.beta0 / N) ** derivative if q is not None else None
            np.add.at(acc, j % n, dj * result.P[l] * np.exp(-1j * j * result.beta0 / N * a))
            if q is not None:
                np.add.at(acc, q % n, dq * T[l])
                np.add.at(acc, (-q) % n, np.conj(dq * T[l]))
        else:
            np.add.at(acc, j % n, result.P[l] * np.exp(-1j * j * result.beta0 / N * a))
            if q is not None:
                np.add.at(acc, q % n, T[l])
                np.add.at(acc, (-q) % n, np.conj(T[l]))
        out[l] = np.real(np.fft.ifft(acc)) * n
    return out


def _check_contact(result: ForceResult, points: int = 2048):
    x = np.linspace(0, result.period, points * result.bays, endpoint=False)
    Pl = force_on_grid(result, points * result.bays)
    for l, row in enumerate(Pl):
        i = int(np.argmin(row))
        if row[i] <= 0:
            raise ContactLossError(
                f"contact lost: wheel {l} at x = {x[i]:.4f} m in the bay, minimum force {row[i] / 1e3:.2f} kN; "
                f"the linear wheel/rail model needs a positive force - reduce the roughness amplitude."
            )
