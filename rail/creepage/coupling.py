"""The coupling of dynamic creepage with the contact (eq 26): the tangential march of a passage with u_bar in
its periodic steady state over the period, from the wheelset's modes (rail.creepage.wheelset, rail.creepage.modes)
and the rail head's flexibility (rail.creepage.rail_flexibility, rail.creepage.rail_flexibility_cell), by Newton
steps or, in the growth loop, the lagged coupling (one march per update from the last update's state).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ..contact import ContactMaterial, ContactNumerics, carter, solve_tangential
from ..contact.hertz import ContactError, compliance, hertz_half_length
from ..contact.passage import MarchInputs
from .modes import periodic_response, precondition
from .rail_flexibility import head_operator
from .rail_flexibility_cell import CellHead, cell_head_operator

__all__ = ["LAGGED_STEP", "RAIL_NEWTON_STEPS", "CreepageState", "REST_STATE", "WarmStates", "march_with_creepage", "steady_material",
           "carter_creep_slope", "dynamic_creepage", "rail_operator"]


# the lagged coupling's threshold (march_with_creepage's ``lagged``, bay_wear's creepage_lag): a growth update
# whose first Newton step from the last update's (extrapolated) state is below this, of abs(gamma) V, takes that
# one march; a larger step (a sudden change of the roughness, a new speed) runs more Newton steps, until one is
# below it; the first update, from rest (REST_STATE), too. Measured (docs/dynamic-creepage.md, "The lagged
# coupling"): the first steps of the default growth with the trailer and the rail's flexibility are 0.4-2.4e-4,
# and the worst wear harmonic within 40 dB is 1.2 % (40 m/s) and 0.45 % (60 m/s) off the loop converged to 1e-8
# (0.84 % and 0.58 % with the first update's Newton steps to 1e-5, two marches more)
LAGGED_STEP = 3e-4



def carter_creep_slope(P: float, material) -> float:
    """dQ/dgamma [N] of Carter's steady traction at load P [N] and the material's creepage (0 when saturated).

    Parameters
    ----------
    P : float
        Normal load [N], > 0.
    material : rail.contact.ContactMaterial
        Its compliance, dynamic friction coefficient [-], wheel radius [m], half-width [m] and creepage [-].

    Returns
    -------
    float
        The slope dQ/dgamma [N] of the traction against the creepage; <= 0, and 0 in full slip.
    """
    m = material
    k, mu = compliance(m), m.friction_dynamic
    a = float(hertz_half_length(P, m.wheel_radius, m))
    gamma_s = np.pi * k * mu * P / (np.pi * a * m.half_width)
    f = abs(m.creepage) / gamma_s
    return 0.0 if f >= 1 else -2 * mu * P * (1 - f) / gamma_s


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


class WarmStates:
    """The periodic u_bar of each wheel (and each fleet class) carried by a growth run from update to update,
    saved in its checkpoint so that a resumed run continues from the same states (rail.growth.run_growth's
    ``carry``).

    Without them a resumed run would start its Newton steps from rest again and land elsewhere within the
    lagged coupling's threshold: the SLURM cluster test (tests/cluster/run.sh) found the resumed run's
    roughness differing from the uninterrupted run's once the scenario files took the rail's flexibility.

    Attributes
    ----------
    states : dict
        {wheel index: CreepageState} for one train (rail.chain.train_wear's ``warm``), or
        {class index: {wheel index: CreepageState}} for a fleet (rail.chain.fleet_wear's).
    """

    _FIELDS = ("phase", "p", "vbar", "drift", "vdrift", "grid")

    def __init__(self):
        self.states: dict = {}

    def arrays(self) -> dict[str, np.ndarray]:
        """Every state as named arrays, "<key path>.<field>" (a state's drift None is left out).

        Returns
        -------
        dict
            {name: ndarray}; empty for the report's fixed creepage (no state).
        """
        out = {}

        def walk(d, path):
            for k, v in d.items():
                name = f"{path}{int(k)}"
                if isinstance(v, dict):
                    walk(v, name + "_")
                    continue
                for f in self._FIELDS:
                    x = getattr(v, f)
                    if x is not None:
                        out[f"{name}.{f}"] = np.asarray(x)
        walk(self.states, "")
        return out

    def restore(self, arrays: dict) -> None:
        """Set the states from arrays written by ``arrays`` (replacing any held).

        Parameters
        ----------
        arrays : dict
            {name: ndarray} as ``arrays`` returns.
        """
        by_key: dict = {}
        for name, x in arrays.items():
            path, f = name.rsplit(".", 1)
            by_key.setdefault(path, {})[f] = np.asarray(x)
        self.states = {}
        for path, fields in by_key.items():
            *outer, wheel = [int(k) for k in path.split("_")]
            d = self.states
            for k in outer:
                d = d.setdefault(k, {})
            d[wheel] = CreepageState(fields["phase"].copy(), fields["p"].copy(), float(fields["vbar"]),
                                     fields["drift"].copy() if "drift" in fields else None, float(fields["vdrift"]),
                                     int(fields["grid"]))


def march_with_creepage(mi: MarchInputs, material: ContactMaterial, speed: float, numerics: ContactNumerics,
                        tol: float = 1e-5, max_iter: int = 12, harmonics: int | None = None,
                        start: CreepageState | None = None, lagged: float | None = None):
    """The tangential march of a passage with the dynamic creepage u_bar of eq 26 in its periodic steady
    state over the period: the wheelset's (material.longitudinal, rail.creepage.modes) and the rail's
    (material.rail_flexibility, rail.creepage.rail_flexibility: u_bar_rail = A_Q Q - A_P P, from the contact's
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
        With ``longitudinal`` (rail.creepage.modes.LongitudinalModes) or None, and ``rail_flexibility``
        (rail.creepage.rail_flexibility.RailHead, or rail.creepage.rail_flexibility_cell.CellHead on a track cell) or None.
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
        op = rail_operator(head, speed, harmonics, mi)
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


def rail_operator(head, speed: float, harmonics, mi: MarchInputs):
    """The rail head's operator over the march's period (rail.creepage.rail_flexibility.head_operator): N bays from
    the grid, the force table's harmonics J = N K of the period (K = J / N per bay in each Bloch class, so that the
    head holds the period's harmonics up to J, as the vertical forces do); on a track cell
    (rail.creepage.rail_flexibility_cell.CellHead) the cell's one table over the same J, the period the cell's.

    Before 2026-12-03 the uniform track's classes were each handed J as their K: N times the harmonics of the
    period, N^2 times the table's size (a 16-bay period's head tables, 2,050 columns at 132,800 nodes, exhausted
    24 GB before its first passage), and a head reaching beyond the forces' harmonics.

    Parameters
    ----------
    head : rail.creepage.rail_flexibility.RailHead or rail.creepage.rail_flexibility_cell.CellHead
        The rail head (the uniform track's or a track cell's).
    speed : float
        V [m/s].
    harmonics : int
        J, the force table's harmonics of the march's period [-].
    mi : MarchInputs
        The march's inputs (its period: N_x steps of delta [m]).

    Returns
    -------
    rail.creepage.rail_flexibility.HeadOperator
        u_bar_rail over the march's period from Q and P [m].

    Raises
    ------
    ValueError
        Where the period is not a whole number of bays (or not the cell's), or J not a whole number per bay.
    """
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
    if int(harmonics) % bays:
        raise ValueError(f"the force table's {harmonics} harmonics are not a whole number per bay of the march's {bays} bays.")
    return head_operator(head, speed, int(harmonics) // bays, bays)


def dynamic_creepage(sol, i, speed: float, delta: float, dt) -> float:
    """The rms over the bay of the dynamic creepage (d u_bar / dt) / V (0 without u_bar), as rail.wear.bay_wear reports it.

    Parameters
    ----------
    sol : rail.contact.TangentialSolution
        The march, with its u_bar at every step [m] (None without dynamic creepage).
    i : slice or ndarray of int
        The bay's steps [-].
    speed : float
        V [m/s].
    delta : float
        The grid spacing [m] (uniform steps of delta / V where dt is None).
    dt : ndarray or None
        The step times [s].

    Returns
    -------
    float
        The rms of (d u_bar / dt) / V over the bay [-].
    """
    if sol.ubar is None:
        return 0.0
    steps = np.full(sol.ubar.size, delta / speed) if dt is None else dt
    rate = np.diff(sol.ubar, prepend=0.0) / steps
    return float(np.sqrt(np.mean(rate[i] ** 2)) / speed)
