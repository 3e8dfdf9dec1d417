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

import dataclasses
from dataclasses import dataclass

import numpy as np

from .cell_head import CellHead, cell_head_operator
from .contact import ContactMaterial, ContactNumerics, carter, solve_tangential
from .contact.creep import carter_creep_slope, periodic_response, precondition
from .contact.hertz import ContactError
from .contact.models import roughness_slope
from .contact.passage import SPIN_UP_TRANSITS, MarchInputs, march_inputs
from .interaction import ForceResult, Roughness
from .longitudinal import head_operator

__all__ = ["WearLaw", "WearResult", "CreepageState", "march_with_creepage", "steady_material", "MarchInputs",
           "march_inputs", "bay_wear", "LAGGED_STEP", "REST_STATE", "wear_spectrum", "apply_wear", "roughness_slope", "SPIN_UP_TRANSITS"]



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
                  rotation (rail.contact.creep; 0 for the report's fixed creepage) [-]
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


# the lagged coupling's threshold (march_with_creepage's ``lagged``, bay_wear's creepage_lag): a growth update
# whose first Newton step from the last update's (extrapolated) state is below this, of abs(gamma) V, takes that
# one march; a larger step (a sudden change of the roughness, a new speed) runs more Newton steps, until one is
# below it; the first update, from rest (REST_STATE), too. Measured (docs/dynamic-creepage.md, "The lagged
# coupling"): the first steps of the default growth with the trailer and the rail's flexibility are 0.4-2.4e-4,
# and the worst wear harmonic within 40 dB is 1.2 % (40 m/s) and 0.45 % (60 m/s) off the loop converged to 1e-8
# (0.84 % and 0.58 % with the first update's Newton steps to 1e-5, two marches more)
LAGGED_STEP = 3e-4


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
    sol, info = march_with_creepage(mi, material, speed, numerics, harmonics=forces.harmonics, start=creepage_start,
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
        creepage_dynamic=_dynamic_creepage(sol, i, speed, delta, mi.dt),
        creepage_state=None if info is None else info["state"],
    )


# the most Newton steps with the rail's flexibility: its loop gain near the pinned-pinned frequency is
# larger than the wheelset's (the contact's stiffness against the head's compliance)
RAIL_NEWTON_STEPS = 30


@dataclass(frozen=True)
class CreepageState:
    """The periodic u_bar of a passage (march_with_creepage), to start the next passage's Newton steps from.

    Attributes
    ----------
    phase : (N_x,) time over the period at the bay's steps, as a fraction of the period [-], increasing in [0, 1)
    p : (N_x,) periodic part of u_bar at those times [m]
    vbar : mean slip rate of the rotation [m/s]
    drift : (N_x,) or None, the change of p from one update to the next at those times [m] (march_with_creepage's
        ``lagged`` coupling: the secant of two successive states on one contact grid; None: not known)
    vdrift : the change of vbar from one update to the next [m/s]
    grid : the contact grid's steps per period N_x the state was reached on (0: not known)
    """

    phase: np.ndarray
    p: np.ndarray
    vbar: float
    drift: np.ndarray | None = None
    vdrift: float = 0.0
    grid: int = 0

    def at(self, phase) -> np.ndarray:
        """p at other phases (periodic linear interpolation) [m]."""
        return np.interp(np.asarray(phase, dtype=float), self.phase, self.p, period=1.0)

    def drift_at(self, phase) -> np.ndarray:
        """drift at other phases (periodic linear interpolation; zeros without one) [m]."""
        if self.drift is None:
            return np.zeros(np.shape(phase))
        return np.interp(np.asarray(phase, dtype=float), self.phase, self.drift, period=1.0)


# u_bar = 0 as a start (CreepageState over the whole period, no drift, no grid): march_with_creepage's Newton steps
# from it are those from no start, but a start takes bay_wear's creepage_lag. rail.chain.train_wear hands it to a
# growth run's first update, which then stops at the lagged threshold too (3 marches from rest, not 5 to 1e-5;
# docs/dynamic-creepage.md, "The lagged coupling")
REST_STATE = CreepageState(np.zeros(1), np.zeros(1), 0.0)


def march_with_creepage(mi: MarchInputs, material: ContactMaterial, speed: float, numerics: ContactNumerics,
                        tol: float = 1e-5, max_iter: int = 12, harmonics: int | None = None,
                        start: CreepageState | None = None, lagged: float | None = None):
    """The tangential march of a passage with the dynamic creepage u_bar of eq 26 in its periodic steady
    state over the period: the wheelset's (material.longitudinal, rail.contact.creep) and the rail's
    (material.rail_flexibility, rail.longitudinal: u_bar_rail = A_Q Q - A_P P, from the contact's
    tangential force Q and normal force P over the period); without either, the march as it is.

    u_bar over the period (its periodic part p and a mean slip rate v_bar: the torque balance) is found by
    Newton steps: march with u_bar given (rail.contact.solve_tangential's ubar), the modes' periodic
    response to the march's Q - Q_ref (creep.periodic_response) plus the rail's, the residual
    preconditioned by the quasi-steady contact (creep.precondition; Carter's creep slope, with the
    modes' receptance and the rail's time-invariant part) and v_bar from the mean traction,
    until the step is below ``tol`` of the creep velocity abs(gamma) V. A lightly damped torsion near the
    sleeper-passing frequency would ring for tens of bays in a time march from rest; the periodic form
    has no such transient. Q_ref is the modes' own, or Carter's steady traction at the period's mean load.

    Parameters
    ----------
    mi : MarchInputs
        The passage's inputs (march_inputs): force [N], half-length [m], grid, step times [s].
    material : ContactMaterial
        With ``longitudinal`` (rail.contact.creep.LongitudinalModes) or None, and ``rail_flexibility``
        (rail.longitudinal.RailHead, or rail.cell_head.CellHead on a track cell) or None.
    speed : float
        V [m/s].
    numerics : ContactNumerics
        The closure.
    tol : float
        The Newton step at which to stop, relative to the creep velocity abs(gamma) V [-].
    max_iter : int
        The most Newton steps (marches) [-].
    harmonics : int, optional
        K [-], the harmonics per bay of the rail's moving receptances (the force table's); needed with
        material.rail_flexibility.
    start : CreepageState, optional
        Where the Newton steps start (default: u_bar = 0): the state of an earlier passage over a
        roughness a little different, for example the last update's in a growth run. The answer is the
        same periodic state to within ``tol``, in fewer marches.
    lagged : float, optional
        The lagged coupling of a growth run (docs/dynamic-creepage.md, "The lagged coupling"): the Newton
        steps stop at the first step below ``lagged`` of abs(gamma) V instead of ``tol``, and the state
        handed on (info 'state') is the one that step reaches, p + dp, not the one marched. From the last
        update's state that is one march per update: the wear of the update is that of u_bar lagged by
        one Newton step (its error about the step, ``lagged`` at most), and the Newton iteration goes on
        across the updates instead of inside each. None (default): Newton steps to ``tol``.

    Returns
    -------
    (TangentialSolution, info) : info None without u_bar, else a dict of the Newton steps made
        ('iterations'), the last step's size ('residual', of abs(gamma) V), Q_ref [N] ('reference_force') and
        the periodic state reached ('state', a CreepageState; with ``lagged``, one step beyond the march).
    """
    if lagged is not None and not lagged > 0:  # NaN too
        raise ValueError(f"lagged = {lagged!r} is not allowed: it must be a number > 0 (of the creep velocity) or None.")
    modes = material.longitudinal
    head = material.rail_flexibility
    kw = dict(closure=numerics.closure, closure_scale=numerics.closure_scale, shape=mi.shape, dt=mi.dt)
    if modes is None and head is None:
        return solve_tangential(mi.P, mi.a, material, speed, mi.delta, mi.M, **kw), None
    bare = dataclasses.replace(material, longitudinal=None, rail_flexibility=None)
    period = slice(mi.spin, mi.spin + mi.Nx)
    steps = mi.P.size
    dt_all = np.full(steps, mi.delta / speed) if mi.dt is None else np.asarray(mi.dt, dtype=float)
    dtp = dt_all[period]
    T = float(np.sum(dtp))
    Pm = float(np.mean(mi.P[period]))
    steady = steady_material(material, speed)
    q_ref = None if modes is None else modes.reference_force
    if q_ref is None and modes is not None:
        q_ref = float(carter(0.0, Pm, steady, speed, material.wheel_radius)[2])
    slope = carter_creep_slope(Pm, steady) / speed  # dQ / d(u_bar rate) [N s/m]
    rigid = modes is not None and any(o == 0 for o in modes.omega)
    op, extra, u_P, lag = None, None, 0.0, 0.0
    label = modes.label if modes is not None else ""
    if head is not None:
        op = _rail_operator(head, speed, harmonics, mi)
        extra = op.diagonal(mi.Nx)
        u_P = op.from_vertical(mi.P[period])  # the vertical force's share: fixed over the Newton steps
        label = f"{label} and the {head.label}" if label else head.label
        lag = float(np.mean(mi.a[period])) / speed  # the stiff rail loads the contact up to its spring range
        max_iter = max(max_iter, RAIL_NEWTON_STEPS)
    idx = (np.arange(steps) - mi.spin) % mi.Nx
    t_all = np.cumsum(dt_all)
    phase = (np.cumsum(dtp) - dtp[0]) / T  # the bay's steps over the period, from 0
    p, vbar = (np.zeros(mi.Nx), 0.0) if start is None else (start.at(phase), float(start.vbar))
    if lagged is not None and start is not None:  # the secant across updates: the state the roughness drifts to
        p, vbar = p + start.drift_at(phase), vbar + start.vdrift
    scale = max(abs(material.creepage) * speed, 1e-12)
    size = np.inf
    for it in range(1, max_iter + 1):
        sol = solve_tangential(mi.P, mi.a, bare, speed, mi.delta, mi.M, ubar=p[idx] + vbar * t_all, **kw)
        Q = sol.Q[period]
        target, Fm = (periodic_response(0.5 * (np.roll(Q, 1) + Q) - q_ref, dtp, modes) if modes is not None
                      else (np.zeros(mi.Nx), 0.0))
        if op is not None:
            target = target + op.from_force(Q) - u_P
        r = target - p
        dp = precondition(r - np.mean(r), T, modes, slope, extra, lag)
        dv = -Fm / slope if (rigid and slope != 0) else 0.0
        size = max(float(np.max(np.abs(np.diff(np.concatenate([dp[-1:], dp])) / dtp))), abs(dv)) / scale
        if lagged is not None and size < lagged:
            p, vbar = p + dp, vbar + dv  # hand on the stepped state: the iteration goes on in the next update
            break
        if size < tol:
            break
        p, vbar = p + dp, vbar + dv
    else:
        raise ContactError(f"the dynamic creepage of the {label} did not settle to a periodic state in "
                           f"{max_iter} Newton steps (last step {size:.2g} of the creep velocity): the coupled torsion is "
                           "unstable or too close to resonance for the quasi-steady preconditioner.")
    state = CreepageState(phase, p, vbar, grid=mi.Nx)
    if lagged is not None and start is not None:
        if start.grid == mi.Nx:  # two states on one grid: their difference is the roughness's drift alone
            state = dataclasses.replace(state, drift=p - start.at(phase), vdrift=vbar - float(start.vbar))
        else:  # a new grid: its states differ by the grid-tied error too; the drift is carried over
            state = dataclasses.replace(state, drift=None if start.drift is None else start.drift_at(phase),
                                        vdrift=start.vdrift)
    return sol, {"iterations": it, "residual": size, "reference_force": q_ref, "state": state}


def steady_material(material: ContactMaterial, speed: float) -> ContactMaterial:
    """The contact parameters of Carter's steady rolling (the torque reference and the creep slope of
    march_with_creepage): with friction falling with the slip velocity (material.friction_decay = s_0 > 0),
    the friction at the creep velocity, mu(abs(gamma) V) = mu_d + (mu_s - mu_d) exp(-abs(gamma) V / s_0),
    stands for mu_d (the slip zone of steady rolling slips at about abs(gamma) V); with the step law, the
    material as it is.

    Parameters
    ----------
    material : ContactMaterial
    speed : float
        V [m/s].

    Returns
    -------
    ContactMaterial
    """
    if material.friction_decay <= 0:
        return material
    mu = material.friction_dynamic + (material.friction_static - material.friction_dynamic) * float(
        np.exp(-abs(material.creepage) * speed / material.friction_decay))
    return dataclasses.replace(material, friction_dynamic=mu)


def _rail_operator(head, speed: float, harmonics, mi: MarchInputs):
    """The rail head's operator over the march's period (rail.longitudinal.head_operator): N bays from
    the grid, K from the force table; on a track cell (rail.cell_head.CellHead) the cell's one table over
    the force table's harmonics J, the period the cell's."""
    if harmonics is None:
        raise ValueError("march_with_creepage needs harmonics (the force table's K) with material.rail_flexibility.")
    span = mi.Nx * mi.delta / head.track.L
    bays = int(round(span))
    if bays < 1 or abs(span - bays) > 1e-6 * span:
        raise ValueError(f"the march's period ({mi.Nx} x {mi.delta:g} m) is not a whole number of sleeper bays of "
                         f"{head.track.L:g} m: the rail's flexibility needs the period of the track.")
    if isinstance(head, CellHead):
        if bays != head.cell.bays:
            raise ValueError(f"the march's period holds {bays} bays, the track cell {head.cell.bays}: the rail's flexibility "
                             "on a cell needs the cell's period.")
        return cell_head_operator(head, speed, int(harmonics))
    return head_operator(head, speed, int(harmonics), bays)


def _dynamic_creepage(sol, i, speed: float, delta: float, dt) -> float:
    """The rms over the bay of the dynamic creepage (d u_bar / dt) / V [-] (0 without u_bar)."""
    if sol.ubar is None:
        return 0.0
    steps = np.full(sol.ubar.size, delta / speed) if dt is None else dt
    rate = np.diff(sol.ubar, prepend=0.0) / steps
    return float(np.sqrt(np.mean(rate[i] ** 2)) / speed)
