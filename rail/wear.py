"""Frictional-work wear of the rail over one sleeper bay (report section 5, eqs 49-54).

One wheel rolls over the bay with the force history of rail.interaction and the rail-head
profile of the current roughness. rail.contact gives the traction and slip of every rail point
as it crosses the patch. The wear depth is the frictional work done on that point times K / rho
(eq 49). Its discrete Fourier transform over the bay, with Delta Z_0 = 0, gives the new profile
Z_k - Delta Z_k (eq 54).

Positions: rail points x_k = k Delta (k = 0..N_x - 1, x = 0 above a sleeper). The contact is
solved from zero traction over a spin-up of SPIN_UP_TRANSITS patch transits (at most one bay)
and then over the bay, whose points' work is used. A perturbation of the traction decays by a
factor of 0.1 (default closure) to 0.5 (closure_scale 4, 41 nodes) per transit
(docs/contact.md), so what is left of the start after 20 transits is at most about 1e-6 of the
traction (0.51^20 = 1.4e-6 in the slowest case).
The change of the traction state over the bay is returned as a measure of periodicity.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .contact import ContactMaterial, ContactNumerics
from .contact.models import roughness_slope
from .contact.passage import SPIN_UP_TRANSITS, MarchInputs, march_inputs
from .creepage import coupling
from .creepage.coupling import LAGGED_STEP, CreepageState, dynamic_creepage
from .interaction import ForceResult, Roughness

__all__ = ["WearLaw", "WearResult", "MarchInputs", "march_inputs", "bay_wear", "wear_spectrum", "apply_wear", "roughness_slope",
           "SPIN_UP_TRANSITS"]



@dataclass(frozen=True)
class WearLaw:
    """Frictional-work wear law (eq 49): removed depth = (K / rho) x frictional work per unit area.

    density     : rho, rail density [kg/m^3], > 0
    coefficient : K, wear coefficient [kg/(N m)], >= 0
    """

    density: float
    coefficient: float

    def __post_init__(self):
        if not (np.isfinite(self.density) and self.density > 0):
            raise ValueError(f"material.density = {self.density!r} kg/m^3 is not allowed: it must be > 0.")
        if not (np.isfinite(self.coefficient) and self.coefficient >= 0):
            raise ValueError(f"wear.coefficient = {self.coefficient!r} kg/(N m) is not allowed: it must be >= 0.")

    def depth(self, work):
        """Removed depth [m] for the frictional work per unit area ``work`` [J/m^2], finite and >= 0 (eq 49)."""
        work = np.asarray(work)
        bad = ~(np.isfinite(work) & (work >= 0))
        if np.any(bad):
            raise ValueError(f"frictional work = {float(work[bad].flat[0])!r} J/m^2 is not allowed in the wear law (eq 49): it "
                             "must be a finite number >= 0.")
        return self.coefficient / self.density * work


@dataclass(frozen=True)
class WearResult:
    """Wear of one wheel passage over a bay.

    Attributes
    ----------
    x : (N_x,) rail positions in the bay, m
    depth : (N_x,) removed height Delta z(x_k), m (eq 51)
    Z : (2K+1,) Fourier coefficients Delta Z_k of the depth over the bay, Delta Z_0 = 0, m
    P, a : (N_x,) normal force (N) and half-length (m) with the wheel centre at x_k
    Q : (N_x,) tangential force with the wheel centre at x_k, N
    q, s, xi : traction (Pa) and slip velocity (m/s) at the patch nodes xi (m) with the wheel at x_k
    periodicity : max change of the traction state between the starts of the two bays, relative
                  to max abs(q)
    full_slip : fraction of the bay's positions with no stick zone in the loaded patch (0 in
                  the report's regime; 1 with saturated creepage). Reported, not an error: the
                  traction is then mu_d p everywhere, which the model handles.
    min_shape : smallest pressure shape factor over the bay (normal contact 'nonhertzian'; 1 for
                  Hertz): the roughness's share of the pressure at its worst, rail.contact.normal.patch_contact
    shift : largest abs(c) / a over the bay, the neglected move of the contact centre relative to
                  the wheel (normal contact 'nonhertzian'; 0 for the report's model) [-]
    creepage_dynamic : rms over the bay of the dynamic creepage (d u_bar / dt) / V of the wheelset's
                  rotation (rail.creepage.modes; 0 for the report's fixed creepage) [-]
    creepage_state : the periodic u_bar reached (CreepageState; None for the report's fixed creepage), to
                  start the next passage from
    """

    x: np.ndarray
    depth: np.ndarray
    Z: np.ndarray
    P: np.ndarray
    a: np.ndarray
    Q: np.ndarray
    q: np.ndarray
    s: np.ndarray
    xi: np.ndarray
    periodicity: float
    full_slip: float = 0.0
    min_shape: float = 1.0
    shift: float = 0.0
    creepage_dynamic: float = 0.0
    creepage_state: "CreepageState | None" = None


def wear_spectrum(depth, K: int):
    """Fourier coefficients of the wear depth over the bay (eq 53), with Delta Z_0 = 0.

    Parameters
    ----------
    depth : ndarray, shape (N_x,)
        Removed height at x_k = k L / N_x [m].
    K : int
        Highest harmonic [-].

    Returns
    -------
    ndarray, shape (2K + 1,)
        Delta Z_k = (1/N_x) sum_k depth e^{-i k beta0 x_k}, k = -K..K [m].
    """
    N = len(depth)
    F = np.fft.fft(depth) / N
    k = np.arange(-K, K + 1)
    Z = F[k % N]
    Z[K] = 0.0
    return Z


def apply_wear(roughness: Roughness, dZ, passages: float = 1.0) -> Roughness:
    """New roughness Z_k - passages * Delta Z_k (eq 54).

    Parameters
    ----------
    roughness : Roughness
        [m].
    dZ : ndarray
        Wear coefficients of one passage [m].
    passages : float
        Passages whose wear is removed [-].

    Returns
    -------
    Roughness
        Over the same period of N bays as ``roughness``.
    """
    return Roughness(roughness.Z - passages * np.asarray(dZ), roughness.bays)


def bay_wear(forces: ForceResult, wheel_index: int, roughness: Roughness, material: ContactMaterial, wear_law: WearLaw,
             numerics: ContactNumerics, grid_phase: float = 0.0, a_max: float | None = None,
             creepage_start: "CreepageState | None" = None, creepage_lag: float | None = LAGGED_STEP) -> WearResult:
    """Wear of one passage of wheel ``wheel_index`` over the bay (eqs 22-24, 26-52).

    Parameters
    ----------
    forces : ForceResult
        Normal force harmonics [N] (their histories include the 1/p^2 tail); forces.period = N L is
        the period over which the wear is computed [m] (N = 1: the bay).
    wheel_index : int
        Which wheel of ``forces`` rolls.
    roughness : Roughness
        Current profile [m] (curvature kappa = -z'', eq 20; multiple contact is an error).
    material : ContactMaterial
        Contact parameters (eqs 22-30).
    wear_law : WearLaw
        rho [kg/m^3] and K [kg/(N m)] of eq 49.
    numerics : ContactNumerics
        Grid nodes across the largest patch (the spacing Delta = L / N_x divides the bay) and closure.
    grid_phase : float
        In [0, 1): refines the grid from N_x to N_x + round(grid_phase L / a_mean) per bay, so that a / Delta
        grows by grid_phase units at the bay's mean half-length a_mean. The discretisation's small
        remaining error that depends on where the patch edges fall between nodes is periodic in
        a / Delta with period 1; growth.run_growth varies the phase between updates with a
        low-discrepancy sequence, so that this error averages out instead of building up as false
        roughness (docs/contact.md). Shifting the grid against the supports would not: it leaves
        a / Delta unchanged.
    a_max : float, optional
        Largest half-length the grid must hold [m] (default: 1.02 x the bay's largest).
    creepage_start : CreepageState, optional
        Where the dynamic creepage's Newton steps start (march_with_creepage's ``start``; ignored
        without u_bar).
    creepage_lag : float, optional
        With ``creepage_start``: march_with_creepage's ``lagged`` (the lagged coupling of a growth run, one
        march per update while the first Newton step stays below it, of abs(gamma) V); None: Newton steps to
        the tolerance. Without a start (a cold passage, a probe of the growth-rate spectrum) the Newton steps
        always go to the tolerance; a growth run's first update starts from REST_STATE (u_bar = 0) to take the lag.

    Returns
    -------
    WearResult
    """
    if not 0.0 <= grid_phase < 1.0:
        raise ValueError(f"grid_phase = {grid_phase!r} is not allowed: it must lie in [0, 1).")
    if not 0 <= wheel_index < len(forces.positions):
        raise ValueError(f"wheel_index = {wheel_index!r} is not allowed: it must lie in [0, {len(forces.positions) - 1}].")
    K = roughness.harmonics
    if roughness.bays != forces.bays:
        raise ValueError(f"the roughness is periodic over {roughness.bays} bays, the forces over {forces.bays}.")
    if roughness.harmonics != forces.harmonics:
        raise ValueError(f"the roughness has {roughness.harmonics} harmonics and the forces {forces.harmonics}: the wear would "
                         f"be computed for the roughness's harmonics only; give both the receptance table's K.")
    speed = forces.speed
    mi = march_inputs(forces, wheel_index, roughness, material, numerics, grid_phase, a_max)
    P, a, delta, Nx, M, spin = mi.P, mi.a, mi.delta, mi.Nx, mi.M, mi.spin
    min_shape, shift = mi.min_shape, mi.shift
    sol, info = coupling.march_with_creepage(mi, material, speed, numerics, harmonics=forces.harmonics, start=creepage_start,
                                    lagged=None if creepage_start is None else creepage_lag)
    # particle j is at x = (j - M - spin) Delta; the bay's points x_k = k Delta are j = spin + M + k
    j = spin + M + np.arange(Nx)
    depth = wear_law.depth(sol.work[j])
    x = np.arange(Nx) * delta
    # states with the wheel centre at x_k: step i = spin + k
    i = spin + np.arange(Nx)
    qscale = max(np.abs(sol.q).max(), 1e-300)
    periodicity = float(np.abs(sol.q[spin + Nx] - sol.q[spin]).max() / qscale)
    if not np.all(np.isfinite(depth)):
        raise FloatingPointError(f"the wear depth of wheel {wheel_index} is not finite (V = {speed:g} m/s).")
    loaded = P[i] > 0
    full_slip = float(np.mean((sol.stick_nodes[i] == 0) & loaded))
    return WearResult(
        x=x,
        depth=depth,
        Z=wear_spectrum(depth, K),
        P=P[i],
        a=a[i],
        Q=sol.Q[i],
        q=sol.q[i],
        s=sol.s[i],
        xi=sol.xi,
        periodicity=periodicity,
        full_slip=full_slip,
        min_shape=min_shape,
        shift=shift,
        creepage_dynamic=dynamic_creepage(sol, i, speed, delta, mi.dt),
        creepage_state=None if info is None else info["state"],
    )


