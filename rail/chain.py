"""The model chain, once: receptance table -> wheel/rail forces -> wear of one passage -> growth.

Every script, study and benchmark computes through these functions, so that the chain is written
in one place (report secs 4-5):

    table  = receptance_table(scn, speed)            moving-load receptances (sec. 4.1, rail.moving)
    forces = solve_forces(scn, table, roughness)     normal forces of every wheel (eq 21, rail.interaction)
    wear   = passage_wear(scn, forces, roughness)    contact and wear of one wheel passage (eqs 22-54, rail.wear)
    dZ, _  = train_wear(scn, table, Z)               wear of one train passage, wheel after wheel
    hist   = grow(scn, table, roughness)             roughness growth over many passages (sec. 5, rail.growth)
    tables = fleet_tables(classes)                     one table per speed of a fleet, shared by its vehicles (rail.fleet)
    dZ, _  = fleet_wear(classes, tables, Z)            traffic-weighted wear of one fleet passage, sum_c w_c dZ_c
    hist   = grow_fleet(classes, tables, roughness)    growth under the fleet
    cs     = contact_shift(scn, table, Z)            the neglected move of the contact centre (docs/contact.md)
"""

from __future__ import annotations

import dataclasses
import sys

import numpy as np

from . import growth, interaction, moving, provenance, wear
from .creepage import coupling
from .contact import normal
from .contact import ContactError, hertz_half_length
from .interaction import ForceResult, Roughness
from .moving import MovingReceptance
from .scenario import Scenario, TrackNumerics
from .track import Track

__all__ = ["cell_head_ready", "wheel_offsets", "receptance_table",
           "track_table", "table_speed", "initial_roughness", "solve_forces", "contact_filtered",
           "wheel_material", "passage_wear", "train_wear", "grow", "fleet_tables", "fleet_wear",
           "fleet_wheels", "grow_fleet", "single_wheel", "ContactShift", "contact_shift",
           "SWEEP_ERROR_LIMIT"]

SWEEP_ERROR_LIMIT = 2e-3  # largest |dc/dx| the wear model is taken to hold for (docs/contact.md, "The move of the contact centre")


def single_wheel(scn: Scenario) -> Scenario:
    """The scenario with one wheel of the train at position 0 (the report's single-wheel studies).

    Parameters
    ----------
    scn : Scenario

    Returns
    -------
    Scenario
    """
    w = scn.wheels
    return dataclasses.replace(scn, wheels=interaction.Wheels(w.mass, w.radius, w.static_load, (0.0,)))


def single_axle(scn: Scenario, wheel: int) -> Scenario:
    """The scenario with one wheel of the train alone at position 0, with that wheel's own creepage and wheelset
    where the wheels carry them per axle (a fleet vehicle's, rail.fleet; single_wheel for a train whose wheels are alike).

    Parameters
    ----------
    scn : Scenario
    wheel : int
        Index of the wheel in scn.wheels.positions [-].

    Returns
    -------
    Scenario
    """
    w = scn.wheels
    if not 0 <= wheel < len(w.positions):
        raise ValueError(f"wheel = {wheel!r} is not allowed: the train has wheels 0 .. {len(w.positions) - 1}.")
    return dataclasses.replace(scn, wheels=interaction.Wheels(
        w.mass, w.radius, w.static_load, (0.0,), None if w.creepage is None else (w.creepage[wheel],),
        None if w.wheelsets is None else (w.wheelsets[wheel],)))


def wheel_offsets(scn: Scenario) -> list[float]:
    """Offsets between the scenario's wheels that the receptance table needs.

    Parameters
    ----------
    scn : Scenario

    Returns
    -------
    list of float
        d = a_l - a_j [m] for every ordered pair of wheels, 0 first, by abs(d).
    """
    pos = [float(x) for x in scn.wheels.positions]
    out = {0.0} | {round(a - b, 9) for a in pos for b in pos if a != b}
    return sorted(out, key=lambda d: (abs(d), d))


def receptance_table(scn: Scenario, speed: float, offsets=None):
    """Moving-load receptance table of the scenario's track (sec. 4.1, rail.moving.receptance_table).

    Parameters
    ----------
    scn : Scenario
        Its track and track numerics (harmonics K, quadrature tolerance).
    speed : float
        Train speed [m/s].
    offsets : sequence of float, optional
        Offsets d [m] (default: those between the scenario's wheels, wheel_offsets).

    Returns
    -------
    MovingReceptance or tuple of MovingReceptance
        A_d[p, k] [m/N]; for a roughness periodic over N > 1 bays (scn.roughness.bays) the tables of
        the Bloch fractions r / N, r = 0..floor(N/2) (rail.moving.bloch_tables).
    """
    return track_table(scn.track, scn.track_numerics, speed, wheel_offsets(scn) if offsets is None else offsets,
                       scn.roughness.bays, scn.cell)


def track_table(track: Track, numerics: TrackNumerics, speed: float, offsets, bays: int = 1, cell=None, progress=None):
    """Moving-load receptance table of a track alone (what receptance_table computes for a scenario;
    the workflow shares one table between the scenarios on one track).

    Parameters
    ----------
    track : Track
    numerics : TrackNumerics
        Harmonics K and quadrature tolerance.
    speed : float
        Train speed [m/s].
    offsets : sequence of float
        Offsets d [m] between the wheels of every scenario that uses the table.
    bays : int
        Roughness period N in bays [-].
    cell : rail.cell.TrackCell, optional
        The track's cell of N bays whose supports differ (then one table over the cell's harmonics,
        rail.moving.cell_receptance_table; ``track`` is ignored).
    progress : callable, optional
        Called with one line of text as the computation proceeds: per table of the N > 1 fractions
        ("<i> of <n> tables"), else per block of quadrature nodes ("<i> of <n> node blocks"); default
        None, silent.

    Returns
    -------
    MovingReceptance or tuple of MovingReceptance
        A_d[p, k] [m/N]: one table (N = 1) or those of the fractions r / N, r = 0..floor(N/2).
    """
    if cell is not None:
        if cell.bays != bays:
            raise ValueError(f"roughness.bays = {bays} is not allowed with track.cell.bays = {cell.bays}: "
                             f"the roughness must be periodic over the cell.")
        return moving.cell_receptance_table(cell, speed, numerics.harmonics, offsets, numerics.rtol, progress=progress)
    if bays == 1:
        return moving.receptance_table(track, speed, numerics.harmonics, offsets, numerics.rtol, progress=progress)
    return moving.bloch_tables(track, speed, numerics.harmonics, bays, offsets, numerics.rtol, progress=progress)


def table_speed(table) -> float:
    """The speed of a receptance table or of a set of Bloch tables.

    Parameters
    ----------
    table : MovingReceptance or tuple of MovingReceptance

    Returns
    -------
    float
        Train speed [m/s].
    """
    return table.speed if isinstance(table, MovingReceptance) else table[0].speed


def initial_roughness(scn: Scenario, speed: float) -> Roughness:
    """The scenario's initial roughness (eqs 18-19).

    Parameters
    ----------
    scn : Scenario
    speed : float
        Train speed [m/s] (a harmonic roughness may be given by its excitation frequency).

    Returns
    -------
    Roughness
        Z_k, k = -K..K [m].
    """
    return scn.roughness.realise(speed, scn.L, scn.harmonics)


def solve_forces(scn: Scenario, table: MovingReceptance, roughness: Roughness, check_contact: bool = True) -> ForceResult:
    """Normal force harmonics of every wheel of the scenario (eq 21, rail.interaction.solve_forces).

    With the normal contact 'nonhertzian' the contact spring is driven by the roughness the patch
    sees, Z_j J0(beta_j a_0) (rail.contact.normal.approach_filter, linearised about the static wheel load's
    Hertz patch a_0, contact_filter); with 'report' by the roughness at the wheel centre.

    Parameters
    ----------
    scn : Scenario
        Its wheels, contact spring and normal-contact model.
    table : MovingReceptance
        At the train's speed, with every wheel offset.
    roughness : Roughness
        [m].
    check_contact : bool
        Refuse a force that falls to zero or below (rail.interaction.solve_forces; default).

    Returns
    -------
    ForceResult
        P[l, p] [N].
    """
    return interaction.solve_forces(table, scn.wheels, scn.spring, contact_filtered(scn, roughness), scn.L, check_contact)


def contact_filtered(scn: Scenario, roughness: Roughness) -> Roughness:
    """The roughness that drives the normal force: the contact filter J0(beta a_0) of the linearised
    2D contact about the static Hertz patch a_0 (rail.contact.normal.approach_filter) for the normal contact
    'nonhertzian'; the roughness itself for 'report'.

    Parameters
    ----------
    scn : Scenario
    roughness : Roughness
        Z_j over the period N L [m].

    Returns
    -------
    Roughness
        [m].
    """
    a0 = float(hertz_half_length(scn.wheels.static_load, scn.material.wheel_radius, scn.material))
    J = roughness.harmonics
    beta = 2 * np.pi * np.arange(-J, J + 1) / (roughness.bays * scn.L)
    return Roughness(roughness.Z * scn.contact_numerics.normal.filter(beta, a0), roughness.bays)


def passage_wear(scn: Scenario, forces: ForceResult, roughness: Roughness, wheel: int = 0,
                 grid_phase: float = 0.0, creepage_start=None) -> wear.WearResult:
    """Contact and wear of one passage of one wheel over the bay (eqs 22-54, rail.wear.bay_wear).

    Parameters
    ----------
    scn : Scenario
        Its contact material, wear law and contact numerics.
    forces : ForceResult
        [N].
    roughness : Roughness
        The profile the wheel rolls on [m].
    wheel : int
        Index of the wheel in ``forces``.
    grid_phase : float
        Contact grid phase in [0, 1) [-] (rail.wear.bay_wear).
    creepage_start : rail.creepage.coupling.CreepageState, optional
        Where the dynamic creepage's Newton steps start (rail.wear.bay_wear).

    Returns
    -------
    WearResult
    """
    return wear.bay_wear(forces, wheel, roughness, wheel_material(scn, wheel), scn.wear_law, scn.contact_numerics,
                         grid_phase=grid_phase, creepage_start=creepage_start)


def wheel_material(scn: Scenario, wheel: int):
    """The contact parameters of one wheel: the scenario's, with the wheel's own creepage and its own
    wheelset's modes where the wheels carry them per axle (rail.interaction.Wheels.creepage and
    Wheels.wheelsets, rail.fleet). The rail's flexibility and the friction law are the scenario's.

    Parameters
    ----------
    scn : Scenario
    wheel : int
        Index of the wheel in scn.wheels.positions.

    Returns
    -------
    rail.contact.ContactMaterial
        With creepage gamma_1 [-] and the wheelset's modes (``longitudinal``; None: the fixed creepage) of the wheel;
        the scenario's own object where the wheel has nothing of its own.
    """
    m, c, ws = scn.material, scn.wheels.creepage, scn.wheels.wheelsets
    own = {}
    if c is not None and c[wheel] != m.creepage:
        own["creepage"] = float(c[wheel])
    if ws is not None and ws[wheel] is not m.longitudinal:
        own["longitudinal"] = ws[wheel]
    return dataclasses.replace(m, **own) if own else m


def train_wear(scn: Scenario, table: MovingReceptance, Z, grid_phase: float = 0.0, warm: dict | None = None):
    """Wear of one train passage (secs 4.2-5).

    The forces of every wheel, then the wheels roll over the bay in turn, leading wheel (largest
    position) first, each on the profile the one before it left.

    Parameters
    ----------
    scn : Scenario
    table : MovingReceptance
    Z : ndarray
        Roughness coefficients k = -K..K [m].
    grid_phase : float
        Contact grid phase in [0, 1) [-].
    warm : dict, optional
        {wheel index: rail.creepage.coupling.CreepageState}: where each wheel's dynamic creepage starts its Newton
        steps, updated in place with the state reached (a growth run hands the same dict to every
        update); a wheel not in it starts from rest (rail.creepage.coupling.REST_STATE). Unused for the report's fixed
        creepage. With a start, rail.wear.bay_wear takes the lagged coupling (creepage_lag): the Newton
        steps stop at the first below rail.creepage.coupling.LAGGED_STEP, one march per update from the last update's
        state, and the first update's from rest at that threshold too (3 marches, not 5 to the tolerance);
        its cost and its error per wear harmonic against the Newton steps to 1e-8 are measured by
        tests/benchmarks/bench_growth_creepage.py (docs/dynamic-creepage.md, "The lagged coupling").
        None: no start, the Newton steps to the tolerance (rail.creepage.coupling.march_with_creepage); the growth-rate
        spectrum's probes start so: a probe's own small change of u_bar must not be left below the tolerance.

    Returns
    -------
    dZ : ndarray
        Delta Z_k summed over the wheels [m].
    full_slip : float
        Largest fraction of the bay without a stick zone over the wheels [-].
    """
    rough = Roughness(np.asarray(Z), scn.roughness.bays)
    forces = solve_forces(scn, table, rough)
    dZ = np.zeros_like(rough.Z, dtype=complex)
    current, slip = rough, 0.0
    for l in np.argsort(scn.wheels.positions)[::-1]:
        w = passage_wear(scn, forces, current, int(l), grid_phase, None if warm is None else warm.get(int(l), coupling.REST_STATE))
        if warm is not None and w.creepage_state is not None:
            warm[int(l)] = w.creepage_state
        dZ += w.Z
        slip = max(slip, w.full_slip)
        # the worn profile keeps the roughness's period (a 1-bay roughness here made the second wheel of
        # a train over an N-bay period fail; tests/test_fleet.py)
        current = wear.apply_wear(current, w.Z)
    return dZ, slip


def cell_head_ready(scn: Scenario, speed: float, say=None) -> float:
    """Build (and cache for the run) the rail head's table over a track cell before the first passage, saying so: on a
    cell of N bays the head's table (rail.creepage.rail_flexibility_cell.cell_head_table) holds the cell's 2 J + 1
    harmonics (J = N K; Q attachments: the rod's and the beam's narrow peaks at every harmonic set the wavenumber nodes,
    each node a Q J^2 product; measured to grow as Q (2 J + 1)^1.8, rail.creepage.rail_flexibility_cell.table_seconds):
    23 s for two bays, about 9 min of CPU for eight bays at K = 36 (docs/performance.md), silent in the log without
    this line.

    Parameters
    ----------
    scn : Scenario
        Its material's rail_flexibility (a CellHead on a track cell; otherwise nothing is built).
    speed : float
        V [m/s].
    say : callable, optional
        say(text) before and after the build.

    Returns
    -------
    float
        The build's wall time [s] (0 where there is no cell head).
    """
    import time

    from .creepage.rail_flexibility_cell import CellHead, cell_head_operator

    head = scn.material.rail_flexibility
    if not isinstance(head, CellHead):
        return 0.0
    J = scn.roughness.bays * scn.harmonics
    if say is not None:
        say(f"the rail head's moving receptances over the cell of {head.cell.bays} bays at {speed:g} m/s: {2 * J + 1} harmonics, "
            f"{len(head.cell.positions)} attachments (built once for the run)")
    t0 = time.perf_counter()
    cell_head_operator(head, float(speed), J)
    dt = time.perf_counter() - t0
    if say is not None:
        say(f"the rail head's table over the cell built in {dt:.0f} s")
    return dt


def grow(scn: Scenario, table: MovingReceptance, roughness: Roughness | None = None, *, checkpoint=None,
         identity: dict | None = None, progress=sys.stderr, **kwargs) -> growth.GrowthHistory:
    """Roughness growth over scn.growth.passages wheel passages (sec. 5, rail.growth.run_growth).

    Parameters
    ----------
    scn : Scenario
    table : MovingReceptance
        At the train's speed.
    roughness : Roughness, optional
        Initial roughness [m] (default: the scenario's, at the table's speed).
    checkpoint : path, optional
        Resumable checkpoint (rail.growth.run_growth).
    identity : dict, optional
        More of what the run depends on, for the checkpoint; the scenario, the table's speed, the
        initial roughness and the hash of the physics code (rail.provenance) are always in it.
    progress : file
    **kwargs
        Passed to rail.growth.run_growth (stop_after_updates, on_mismatch).

    Returns
    -------
    GrowthHistory
    """
    rough = initial_roughness(scn, table_speed(table)) if roughness is None else roughness
    cell_head_ready(scn, table_speed(table), None if progress is None else lambda t: print(t, file=progress, flush=True))
    ident = {"scenario": repr(scn), "speed": table_speed(table), "code": provenance.module_hash("rail.chain"), **(identity or {})}
    warm = coupling.WarmStates()  # the dynamic creepage's periodic state of each wheel, carried from update to update
    return growth.run_growth(lambda Z, phase: train_wear(scn, table, Z, phase, warm.states), rough, len(scn.wheels.positions),
                             scn.growth, checkpoint=checkpoint, identity=ident, progress=progress,
                             period=scn.L * scn.roughness.bays, carry=warm, **kwargs)


def fleet_tables(classes) -> dict:
    """The receptance tables of a fleet: one per speed, computed once and shared by every vehicle at
    that speed (rail.fleet).

    Parameters
    ----------
    classes : sequence of rail.fleet.FleetClass

    Returns
    -------
    dict
        {speed [m/s]: table} (receptance_table), each with the offsets of every wheel pair of every
        vehicle at that speed (the union of wheel_offsets).
    """
    by_speed = {}
    for c in classes:
        by_speed.setdefault(c.speed, []).append(c.scenario)
    tables = {}
    for speed, scns in by_speed.items():
        offsets = sorted({d for s in scns for d in wheel_offsets(s)}, key=lambda d: (abs(d), d))
        tables[speed] = receptance_table(scns[0], speed, offsets)
    return tables


def fleet_wheels(classes) -> float:
    """Mean wheels on the rail per fleet passage, sum_c w_c n_c [-] (rail.fleet.Fleet.axles_per_train).

    Parameters
    ----------
    classes : sequence of rail.fleet.FleetClass

    Returns
    -------
    float
    """
    # the weighted mean sum w_c n_c / sum w_c: the weights sum to 1 only to rounding (rail.fleet.SUM_TOLERANCE),
    # and a fleet whose vehicles all have n wheels has n wheels per passage exactly, not 3.9999999999999996
    return float(sum(c.weight * len(c.scenario.wheels.positions) for c in classes) / sum(c.weight for c in classes))


def fleet_wear(classes, tables: dict, Z, grid_phase: float = 0.0, warm: dict | None = None):
    """Expected wear of one fleet passage, one train drawn from the traffic: sum_c w_c dZ_c over the
    (vehicle, speed) classes, dZ_c the wear of one passage of class c's train (train_wear).

    Parameters
    ----------
    classes : sequence of rail.fleet.FleetClass
        Weights w_c summing to 1.
    tables : dict
        {speed: receptance table} (fleet_tables).
    Z : ndarray
        Roughness coefficients [m].
    grid_phase : float
        Contact grid phase in [0, 1) [-].
    warm : dict, optional
        {class index: train_wear's ``warm`` of that class}, updated in place (grow_fleet hands the same
        dict to every update).

    Returns
    -------
    dZ : ndarray
        sum_c w_c Delta Z_k,c [m].
    full_slip : float
        Largest fraction of the bay without a stick zone over the classes and wheels [-].
    """
    dZ, slip = None, 0.0
    for n, c in enumerate(classes):
        d, s = train_wear(c.scenario, tables[c.speed], Z, grid_phase, None if warm is None else warm.setdefault(n, {}))
        dZ = c.weight * d if dZ is None else dZ + c.weight * d
        slip = max(slip, s)
    return dZ, slip


def grow_fleet(classes, tables: dict, roughness: Roughness | None = None, *, checkpoint=None, identity: dict | None = None,
               progress=sys.stderr, **kwargs) -> growth.GrowthHistory:
    """Roughness growth under a fleet (sec. 5, rail.growth.run_growth with fleet_wear).

    Passages are axle (wheel) passages on the rail, as for one train: an update of
    growth.passages_per_update wheel passages applies passages_per_update / fleet_wheels(classes)
    fleet passages, each the traffic-weighted wear fleet_wear.

    Parameters
    ----------
    classes : sequence of rail.fleet.FleetClass
        Their scenarios share growth settings and initial roughness (rail.fleet.Fleet.classes).
    tables : dict
        {speed: receptance table} (fleet_tables).
    roughness : Roughness, optional
        Initial roughness [m] (default: the scenarios', which must not depend on the speed).
    checkpoint, identity, progress, **kwargs
        As grow.

    Returns
    -------
    GrowthHistory
    """
    scn = classes[0].scenario
    if roughness is None:
        r = scn.roughness
        if r.kind == "harmonic" and r.wavelength is None:
            raise ValueError("roughness.frequency sets the wavelength at one speed: under a fleet at several speeds give "
                             "roughness.wavelength instead.")
        roughness = initial_roughness(scn, classes[0].speed)
    for speed in sorted({c.speed for c in classes}):
        cell_head_ready(scn, speed, None if progress is None else lambda t: print(t, file=progress, flush=True))
    ident = {"fleet": [(c.weight, repr(c.scenario)) for c in classes], "speeds": sorted(tables),
             "code": provenance.module_hash("rail.chain"), **(identity or {})}
    warm = coupling.WarmStates()  # each class's dynamic-creepage states, carried from update to update
    return growth.run_growth(lambda Z, phase: fleet_wear(classes, tables, Z, phase, warm.states), roughness, fleet_wheels(classes),
                             scn.growth, checkpoint=checkpoint, identity=ident, progress=progress,
                             period=scn.L * scn.roughness.bays, carry=warm, **kwargs)


@dataclasses.dataclass(frozen=True)
class ContactShift:
    """The largest move of the contact centre over the wheels and the period (contact_shift).

    Attributes
    ----------
    shift : largest abs(c) [m], c the centre of the single-zone patch relative to the wheel centre
    ratio : largest abs(c) / a [-]
    sweep : largest abs(dc/dx_w) [-]: the patch sweeps the rail at V (1 + dc/dx_w), so the wear depth the
            model leaves out is -dc/dx_w of the mean wear (for a harmonic, beta abs(c))
    """

    shift: float
    ratio: float
    sweep: float


def contact_shift(scn: Scenario, table: MovingReceptance, Z) -> ContactShift:
    """Where the contact patch sits relative to the wheel centre along the period, which the wear
    model neglects (docs/contact.md, "The move of the contact centre").

    The single-zone 2D contact (rail.contact.normal.patch_contact) centres the patch at c = R_w <r'>, the
    roughness slope averaged over the patch with the weight 1 / (pi sqrt(a^2 - s^2)) (c = R_w r'
    J0(beta a) for a small cosine). It is evaluated for every wheel with the forces of the
    roughness Z, on either normal-contact model (the report's keeps the patch on the wheel centre
    too), at max(512, 16 K) positions per bay: the largest abs(c) sampled at 16 points per shortest
    wavelength is low by at most 1 - cos(pi / 16) = 1.9 %. dc/dx_w is the spectral derivative.

    Parameters
    ----------
    scn : Scenario
    table : MovingReceptance
        At the train's speed.
    Z : ndarray
        Roughness coefficients j = -J..J over the period [m].

    Returns
    -------
    ContactShift
        Largest abs(c) [m], abs(c) / a [-] and abs(dc/dx_w) [-]; NaN where the single-zone contact does not
        hold (contact lost, multiple contact: the run stops there, rail.growth.run_growth).
    """
    rough = Roughness(np.asarray(Z), scn.roughness.bays)
    if not np.any(rough.Z):
        return ContactShift(0.0, 0.0, 0.0)
    forces = solve_forces(scn, table, rough, check_contact=False)  # a lost contact gives NaN below, as documented
    period = forces.period
    n = max(512, 16 * forces.harmonics // forces.bays) * forces.bays
    x = np.arange(n) * period / n
    slope = wear.roughness_slope(rough, period)
    k = 2 * np.pi * np.fft.fftfreq(n, period / n)  # rad/m
    shift = ratio = sweep = 0.0
    for P in interaction.force_on_grid(forces, n):
        if not np.all(P > 0):
            return ContactShift(np.nan, np.nan, np.nan)
        try:
            pc = normal.patch_contact(P, x, slope, scn.material, np.zeros(1))
        except ContactError:
            return ContactShift(np.nan, np.nan, np.nan)
        dc = np.real(np.fft.ifft(1j * k * np.fft.fft(pc.shift)))
        shift = max(shift, float(np.max(np.abs(pc.shift))))
        ratio = max(ratio, float(np.max(np.abs(pc.shift) / pc.a)))
        sweep = max(sweep, float(np.max(np.abs(dc))))
    return ContactShift(shift, ratio, sweep)
