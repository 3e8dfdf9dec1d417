"""Turn a resolved, validated configuration mapping into a Scenario (the one place where dicts become
dataclasses, SI units).

``scenario(cfg)`` is called once per scenario, at start-up of the workflow (common.smk) and in
scripts, studies and benchmarks; everything below takes the Scenario and arrays. The checks that
need physics (the rail damping the moving-load integrals need, the harmonics that reach the
pinned-pinned frequency at every speed) are made here and raise ConfigError naming the key, its
value, the valid range and the source file, like the schema's checks (rail.setup.config).
"""

from __future__ import annotations

import dataclasses
import functools
from dataclasses import dataclass

import numpy as np

from ..cell import RandomSupports, TrackCell, make_cell
from ..creepage.rail_flexibility_cell import CellHead
from ..contact import ContactMaterial, ContactNumerics
from ..fleet import Fleet, Vehicle, speed_classes
from ..growth import GrowthSettings
from ..halfspace import ElasticMaterial, HalfSpaceNumerics, contact_loss_factor
from ..interaction import ContactSpring, Wheels
from ..roughness import read_profile_record, record_bays
from ..scenario import InitialRoughness, Scenario, TrackNumerics
from ..track import Ballast, Pad, Rail, Sleeper, Track, damping_problem, min_harmonics, pinned_pinned_frequency
from ..wear import WearLaw
from ..creepage.rail_flexibility import RailHead
from ..creepage.wheelset import Wheelset, hz_text, wheelset_modes
from ..creepage.choices import rail_flexibility, wheelset_model
from ..contact.hertz import hertz_half_length
from ..contact.numerics import rolling_grid
from .config import ConfigError, configured_speeds, project_schema, schema_default, setting

MAX_ROUGHNESS_BAYS = 64  # the schema's bound on roughness.bays (config/schema: roughness.bays.maximum)

__all__ = ["HalfSpaceFigureSettings", "PASSAGE_KEYS", "OPTIONAL_KEYS", "elastic", "fleet",
           "fleet_classes", "track_cell", "passage_scenario", "scenario", "spectrum_scenario", "track",
           "physics_problems", "halfspace_numerics", "halfspace_figures",
           "NoiseSettings", "noise_settings", "wheel_source_settings", "wheel_source_vehicles"]


@dataclass(frozen=True, slots=True)
class HalfSpaceFigureSettings:
    """What Figs 2-6 show.

    frequency       : Hz, frequency of Figs 2-4
    radius          : m, observer distance of Fig. 2
    radii           : m, observer distances of Fig. 4
    frequencies     : Hz, frequencies of Figs 5-6 (from 0)
    hertz_stiffness : N/m, k_H of Fig. 6
    """

    frequency: float
    radius: float
    radii: np.ndarray
    frequencies: np.ndarray
    hertz_stiffness: float


@dataclass(frozen=True, slots=True)
class NoiseSettings:
    """Rolling noise at the saves of a growth run and grinding by noise (config key ``figures.noise``,
    every key optional with the schema's default; docs/noise.md).

    vehicles_per_hour  : Q [1/h], > 0, or None (traffic.axles_per_day / 24 h / axles_per_vehicle)
    axles_per_vehicle  : N_a [-], >= 1
    wheel              : brake type of Table G-1a's wheel roughness ("disc", "composite", "cast_iron")
    sleeper            : "monoblock", "biblock", "wooden", "direct" (Table G-3a)
    pad_class          : "soft", "medium", "hard", or None (from track.pad.stiffness for concrete sleepers)
    track_transfer     : "cnossos" (Table G-3a's L_H,TR) or "own" (the scenario's rail receptance and decay rate, rail.noise.own_track)
    rule               : wavelength-to-frequency rule, "energy" or "level"
    fill               : Table G-1b class for the bands the run does not resolve ("M", "E") or None
    rise_dB            : criterion (a) [dB], > 0
    average_target_dBA : criterion (b) [dB(A) re 1 pW/m], or None (not assessed)
    band_rms           : criterion (c) on (Grassie, Saxon & Smith 1999)
    extrapolation_max  : the criteria followed up to this many times the run's passages [-], >= 1
    fleet_brakes       : a fleet's wheel roughness per vehicle type (fleet.vehicles[*].brake, default wheel), or None
    """

    vehicles_per_hour: float | None
    axles_per_vehicle: int
    wheel: str
    sleeper: str
    pad_class: str | None
    rule: str
    fill: str | None
    rise_dB: float
    average_target_dBA: float | None
    band_rms: bool
    extrapolation_max: float
    track_transfer: str = "cnossos"
    fleet_brakes: tuple | None = None


def wheel_source_settings(cfg: dict):
    """wheel_source of a resolved configuration as the spectrum's jobs read it (rail.setup.inputs.wheel_source_spectra):
    None without a source (roughness none; a fleet: every vehicle's none), else (roughness, file, ground, ground_file) with
    each absent key at its default, and for a fleet each vehicle's (wheel_source_vehicles).

    Parameters
    ----------
    cfg : dict
        A resolved, validated configuration.

    Returns
    -------
    tuple or None
        (roughness, file, ground, ground_file) [names and paths].
    """
    w = cfg.get("wheel_source") or {}
    vehicles = wheel_source_vehicles(cfg)
    if vehicles is None:
        return None if w.get("roughness", "none") == "none" else (w["roughness"], w.get("file"), setting(cfg, "wheel_source.ground"),
                                                                 w.get("ground_file"))
    if all(r == "none" for r, _ in vehicles.values()):
        return None
    return (w.get("roughness", "none"), w.get("file"), setting(cfg, "wheel_source.ground"), w.get("ground_file"),
            tuple(sorted(vehicles.items())))


def wheel_source_vehicles(cfg: dict):
    """Each fleet vehicle's wheels' roughness as it is read: its own fleet.vehicles[*].wheel_source, or the top-level
    wheel_source's roughness and file (none by default); None without a fleet.

    Parameters
    ----------
    cfg : dict
        A resolved, validated configuration.

    Returns
    -------
    dict or None
        {vehicle name: (roughness, file or None)} [names and paths].
    """
    if cfg.get("fleet") is None:
        return None
    w = cfg.get("wheel_source") or {}
    top = (w.get("roughness", "none"), w.get("file") if w.get("roughness") == "file" else None)
    out = {}
    for v in cfg["fleet"]["vehicles"]:
        own = v.get("wheel_source")
        out[str(v["name"])] = top if not own else (own["roughness"], own.get("file") if own["roughness"] == "file" else None)
    return out


def noise_settings(cfg: dict) -> NoiseSettings:
    """figures.noise of a resolved configuration, each absent key at the schema's default (setting).

    Parameters
    ----------
    cfg : dict
        A resolved, validated configuration (rail.setup.config.resolve), SI units.

    Returns
    -------
    NoiseSettings
        Traffic [1/h], axles per vehicle, wheel and sleeper types, pad class, the grinding rule and its targets [dB(A)].
    """
    def get(key):
        return setting(cfg, f"figures.noise.{key}")

    q, target = get("vehicles_per_hour"), get("average_target_dBA")
    return NoiseSettings(vehicles_per_hour=None if q is None else float(q), axles_per_vehicle=int(get("axles_per_vehicle")),
                         wheel=str(get("wheel")), sleeper=str(get("sleeper")), pad_class=get("pad_class"), rule=str(get("rule")),
                         fill=get("fill"), rise_dB=float(get("rise_dB")),
                         average_target_dBA=None if target is None else float(target), band_rms=bool(get("band_rms")),
                         extrapolation_max=float(get("extrapolation_max")), track_transfer=str(get("track_transfer")),
                         fleet_brakes=None if cfg.get("fleet") is None else
                         tuple(str(v.get("brake") or get("wheel")) for v in cfg["fleet"]["vehicles"]))


def elastic(cfg: dict) -> ElasticMaterial:
    """Rail steel as an elastic half-space (config key ``material``): all that Figs 2-6 read of the
    physics.

    Parameters
    ----------
    cfg : dict
        A resolved, validated configuration (rail.setup.config.resolve), SI units.

    Returns
    -------
    ElasticMaterial
        Young's modulus [Pa], Poisson's ratio [-], density [kg/m^3].
    """
    m = cfg["material"]
    return ElasticMaterial(float(m["youngs_modulus"]), float(m["poisson_ratio"]), float(m["density"]))


def halfspace_numerics(cfg: dict) -> HalfSpaceNumerics:
    """Quadrature settings of eq (16) (config key ``numerics.halfspace``).

    Parameters
    ----------
    cfg : dict
        A resolved, validated configuration (rail.setup.config.resolve), SI units.

    Returns
    -------
    HalfSpaceNumerics
        Relative tolerance [-] and subdivision limit [-] of the quadrature.
    """
    n = cfg["numerics"]["halfspace"]
    return HalfSpaceNumerics(epsrel=float(n["epsrel"]), limit=int(n["limit"]))


def halfspace_figures(cfg: dict) -> HalfSpaceFigureSettings:
    """Settings of Figs 2-6 (config key ``figures.halfspace`` and ``contact.hertz_stiffness``).

    Parameters
    ----------
    cfg : dict
        A resolved, validated configuration (rail.setup.config.resolve), SI units.

    Returns
    -------
    HalfSpaceFigureSettings
        Frequencies [Hz] and contact radii [m] of Figs 2-6, the contact stiffness [N/m].
    """
    f = cfg["figures"]["halfspace"]
    return HalfSpaceFigureSettings(
        frequency=float(f["frequency"]),
        radius=float(f["radius"]),
        radii=np.linspace(float(f["radius_min"]), float(f["radius_max"]), int(f["radius_count"])),
        frequencies=np.linspace(0.0, float(f["frequency_max"]), int(f["frequency_count"])),
        hertz_stiffness=float(cfg["contact"]["hertz_stiffness"]),
    )


def track(cfg: dict) -> tuple[Track, TrackNumerics]:
    """The track and its receptance numerics alone (config keys ``track``, ``numerics.track``): what a
    receptance table depends on. Raises ConfigError if the rail damping is too small for the
    moving-load integrals.

    Parameters
    ----------
    cfg : dict
        A resolved, validated configuration (rail.setup.config.resolve), SI units.

    Returns
    -------
    tuple of (Track, TrackNumerics)
        The track (SI units) and its harmonics K per bay [-] and relative tolerance [-].
    """
    tr = _track(cfg)
    if (problem := damping_problem(tr)) is not None:
        raise ConfigError(f"invalid configuration:\n  {problem}")
    n = cfg["numerics"]["track"]
    return tr, TrackNumerics(int(n["harmonics"]), float(n["rtol"]))


def track_cell(cfg: dict) -> TrackCell | None:
    """The track's cell of N bays (config key ``track.cell``, rail.cell.make_cell), or None for
    identical supports at equal spacing. Raises ConfigError naming the key if a list has the wrong
    length.

    Parameters
    ----------
    cfg : dict
        A resolved, validated configuration (rail.setup.config.resolve), SI units.

    Returns
    -------
    TrackCell or None
        The cell's supports (spacing [m], factors [-] of pad, ballast and sleeper mass, dampers).
    """
    c = cfg["track"].get("cell")
    if c is None:
        return None
    r = c.get("random")
    rnd = None if r is None else RandomSupports(int(r["seed"]), str(setting(cfg, "track.cell.random.distribution")),
                                               *(float(setting(cfg, f"track.cell.random.{k}"))
                                                 for k in ("spacing", "pad", "ballast", "sleeper_mass")))
    damper = None if c.get("damper") is None else {
        **c["damper"], **{k: setting(cfg, f"track.cell.damper.{k}") for k in ("loss_factor", "viscous_damping", "position")}}
    try:
        return make_cell(_track(cfg), int(c["bays"]), c.get("spacing"), c.get("pad"), c.get("ballast"), c.get("sleeper_mass"),
                         damper, rnd)
    except ValueError as e:
        raise ConfigError(f"invalid configuration:\n  {e}") from None


def _cell_track(cfg: dict) -> Track:
    """The scenario's nominal track: with a cell, its spacing is the cell's mean P / N."""
    c = track_cell(cfg)
    return _track(cfg) if c is None else c.track


def _track(cfg: dict) -> Track:
    t = cfg["track"]
    r, p, s, b = t["rail"], t["pad"], t["sleeper"], t["ballast"]
    return Track(
        rail=Rail(
            youngs_modulus=float(r["youngs_modulus"]),
            shear_modulus=float(r["shear_modulus"]),
            density=float(r["density"]),
            area=float(r["area"]),
            second_moment_of_area=float(r["second_moment_of_area"]),
            shear_coefficient=float(r["shear_coefficient"]),
            loss_factor=float(r["loss_factor"]),
            damping_time=float(r["damping_time"]),
        ),
        pad=Pad(float(p["stiffness"]), float(p["loss_factor"]), float(p["viscous_damping"]),
                float(setting(cfg, "track.pad.rotational_stiffness"))),
        sleeper=Sleeper(float(s["mass"]), float(s["spacing"])),
        ballast=Ballast(float(b["stiffness"]), float(b["loss_factor"]), float(b["viscous_damping"])),
        damping=str(t["damping"]),
    )


@functools.lru_cache(maxsize=64)
def _halfspace_loss_slope(kH: float, material: ElasticMaterial) -> float:
    """eta_H / omega [s/rad] of the half-space contact damping (Fig. 6); eta_H is exactly
    proportional to frequency, so one value gives the slope (cached: a half-space integral)."""
    om = 2 * np.pi * 1000.0
    return float(contact_loss_factor(om, kH, material) / om)


def _spring(cfg: dict) -> ContactSpring:
    c = cfg["contact"]
    kH = float(c["hertz_stiffness"])
    model = c["loss_factor_model"]
    if model == "halfspace":
        return ContactSpring(kH, loss_slope=_halfspace_loss_slope(kH, elastic(cfg)))
    if model == "constant":
        return ContactSpring(kH, loss_factor=float(c["loss_factor"]))
    return ContactSpring(kH)


def _material(cfg: dict, source: str = "config") -> ContactMaterial:
    """The contact's material, friction law and dynamic creepage. A value the dataclasses refuse (their
    ranges are the schema's, so this is a backstop) is a ConfigError naming the key and ``source``."""
    try:
        return _material_unchecked(cfg)
    except ValueError as e:
        raise ConfigError(f"invalid configuration:\n  {source}: {e}") from None


def _material_unchecked(cfg: dict) -> ContactMaterial:
    c, mat = cfg["contact"], cfg["material"]
    return ContactMaterial(
        youngs_modulus=float(mat["youngs_modulus"]),
        poisson_ratio=float(mat["poisson_ratio"]),
        half_width=float(c["half_width"]),
        wheel_radius=float(cfg["wheels"]["radius"]),
        friction_dynamic=float(c["friction_dynamic"]),
        friction_static=float(c["friction_static"]),
        creepage=float(c["creepage"]),
        friction_decay=float(setting(cfg, "contact.friction_decay")),
        longitudinal=_longitudinal(cfg),
        rail_flexibility=_rail_flexibility(cfg),
    )


def _rail_flexibility(cfg: dict):
    """The rail head's longitudinal flexibility (rail.creepage.rail_flexibility.RailHead; on a track cell
    rail.creepage.rail_flexibility_cell.CellHead,
    the cell's supports and dampers), None without it (the report's): rail_flexibility.model
    (rail.creepage.choices.RailFlexibility), absent at the schema's default."""
    choice = rail_flexibility(setting(cfg, "rail_flexibility.model"))
    if not choice.modelled:
        return None
    keys = {"longitudinal_stiffness": "track.pad.longitudinal_stiffness", "longitudinal_loss_factor": "track.pad.longitudinal_loss_factor",
            "longitudinal_viscous_damping": "track.pad.longitudinal_viscous_damping", "head_height": "track.rail.head_height"}
    kw = {k: float(setting(cfg, v)) for k, v in keys.items()}
    cell = track_cell(cfg)
    if cell is not None:
        return CellHead(cell, bending=choice.bending, **kw)
    return RailHead(_track(cfg), bending=choice.bending, **kw)


def _longitudinal(cfg: dict):
    """The wheelset's tread receptance in modal form (rail.creepage.wheelset), None for the report's fixed creepage:
    wheelset.model (rail.creepage.choices.WheelsetModel), an absent section at the schema's default."""
    choice = wheelset_model(setting(cfg, "wheelset.model"))
    if not choice.modelled:
        return None
    keys = ("wheel_inertia", "centre_inertia", "axle_stiffness", "motor_inertia", "coupling_stiffness", "damping")
    ws = Wheelset(model=choice.name, radius=float(cfg["wheels"]["radius"]), other_wheel=str(setting(cfg, "wheelset.other_wheel")),
                  **{k: float(setting(cfg, f"wheelset.{k}")) for k in keys})  # every key: the schema holds the defaults
    return wheelset_modes(ws)


def _roughness(cfg: dict, source: str = "config") -> InitialRoughness:
    r = cfg["roughness"]
    wl = r.get("wavelength")
    record = str(r["record"])
    bays = int(r["bays"])
    if record == "period" and r.get("kind") == "profile" and r.get("file"):
        bays = _record_bays(cfg, source)
    try:
        return InitialRoughness(kind=str(r["kind"]), amplitude=float(r["amplitude"]), frequency=float(r["frequency"]),
                                wavelength=None if wl is None else float(wl), file=r.get("file"), bays=bays,
                                seed=int(r["seed"]), record=record, spike_removal=bool(r["spike_removal"]),
                                spike_threshold=float(r["spike_threshold"]))
    except ValueError as e:  # a combination of keys the schema cannot state, named with the file
        raise ConfigError(f"invalid configuration:\n  {source}: {e}") from None


def _record_bays(cfg: dict, source: str) -> int:
    """roughness.record = 'period': the roughness period N from the measured record's length
    (rail.roughness.record_bays), within the schema's bound of roughness.bays."""
    r = cfg["roughness"]
    try:
        rec = read_profile_record(r["file"])
    except (OSError, ValueError) as e:
        raise ConfigError(f"invalid configuration:\n  {source}: roughness: {e}") from None
    N = record_bays(rec.length, _track(cfg).L, rec.spacing)  # N samples at spacing d cover N d
    if N > MAX_ROUGHNESS_BAYS:
        raise ConfigError(f"invalid configuration:\n  {source}: roughness.record = 'period' is not allowed with {r['file']}: the "
                          f"{rec.length:g} m record holds {N} bays, more than roughness.bays allows ({MAX_ROUGHNESS_BAYS}); use "
                          "roughness.record = 'average' (the record's segments of roughness.bays bays averaged).")
    return N


def physics_problems(cfg: dict, source: str) -> list[str]:
    """Constraints that need physics to state: rail damping for the moving-load integrals, and
    numerics.track.harmonics reaching the pinned-pinned frequency at every configured speed.

    Parameters
    ----------
    cfg : dict
        A resolved, validated configuration (rail.setup.config.resolve), SI units.
    source : str
        Where the configuration comes from, at the start of each line.

    Returns
    -------
    list of str
        One line per broken constraint, [] when there is none.
    """
    out = []
    tr = _track(cfg)
    if (problem := damping_problem(tr)) is not None:
        out.append(f"{source}: {problem}")
    cell = cfg["track"].get("cell")
    if cell is not None and cfg["roughness"].get("record", "average") == "period":
        out.append(f"{source}: roughness.record = 'period' is not allowed with track.cell: the roughness period must be the "
                   f"cell's {int(cell['bays'])} bays; use roughness.record = 'average'.")
    if cell is not None:
        nb, rb = int(cell["bays"]), int(cfg["roughness"].get("bays", 1))
        if nb != rb:
            out.append(f"{source}: roughness.bays = {rb} is not allowed with track.cell.bays = {nb}: the roughness must be "
                       f"periodic over the track's cell, so roughness.bays must be {nb}.")
        for key in ("spacing", "pad", "ballast", "sleeper_mass"):
            if key in cell and len(cell[key]) != nb:
                out.append(f"{source}: track.cell.{key} has {len(cell[key])} values: it needs one per bay, track.cell.bays = {nb}.")
        if float(setting(cfg, "track.pad.rotational_stiffness")) > 0:
            out.append(f"{source}: track.pad.rotational_stiffness = {setting(cfg, 'track.pad.rotational_stiffness')!r} N m/rad is not "
                       "allowed with track.cell: the pads' moment springs are carried on the uniform track only (rail.moving, "
                       "rail.creepage.rail_flexibility); use 0 on a cell, or the rotational stiffness on a track without track.cell.")
        if "spacing" in cell and len(cell["spacing"]) == nb:
            tr = dataclasses.replace(tr, sleeper=Sleeper(tr.sleeper.mass, float(np.mean(cell["spacing"]))))
    out += dynamic_creepage_problems(cfg, source)
    K = int(cfg["numerics"]["track"]["harmonics"])
    for V in configured_speeds(cfg):
        try:
            need = min_harmonics(tr, V)
        except ValueError as e:
            out.append(f"{source}: speeds: {e}")
            continue
        if K < need:
            out.append(
                f"{source}: numerics.track.harmonics = {K} is not allowed at V = {V:g} m/s: K V / L = {K * V / tr.L:.0f} Hz "
                f"does not reach the pinned-pinned frequency {pinned_pinned_frequency(tr):.0f} Hz, below which the force needs "
                f"every harmonic; it must be >= {need} at this speed."
            )
    return out


def dynamic_creepage_problems(cfg: dict, source: str) -> list[str]:
    """The wheelset's modes the contact march cannot resolve, one line each naming the keys and ``source``.

    The march advances the modes step by step (rail.creepage.modes): a step of dt = Delta / V (Delta the
    grid spacing of rail.contact.numerics.rolling_grid, from the patch at the static load; the dynamic
    load's larger patch coarsens it, which the march checks again with its own grid) resolves
    frequencies below its Nyquist frequency V / (2 Delta), lowest at the slowest configured speed. A
    mode above it is aliased, and its force, extrapolated over the step, drives it unstably; the mode
    responds quasi-statically to all the march resolves, so it is refused with what to change rather
    than run. A value the wheelset refuses (rail.creepage.wheelset.Wheelset) is named here too.

    Parameters
    ----------
    cfg : dict
        A resolved, validated configuration.
    source : str
        The scenario file, named in each line.

    Returns
    -------
    list of str
        [] when the wheelset is absent, fixed_creepage, or every excited mode lies below the Nyquist frequency.
    """
    try:
        modes = _longitudinal(cfg)
    except ValueError as e:
        return [f"{source}: {e}"]
    flexible = rail_flexibility(setting(cfg, "rail_flexibility.model")).modelled
    if (modes is not None or flexible) and float(cfg["contact"]["creepage"]) == 0.0 and "fleet" not in cfg:
        # the periodic u_bar is found relative to the steady creep velocity abs(gamma) V (rail.creepage.coupling): with no
        # steady traction there is nothing to linearise about, and the reference's Newton steps never settle
        return [f"{source}: contact.creepage = 0.0 is not allowed with the dynamic creepage (wheelset.model "
                f"{setting(cfg, 'wheelset.model')}, rail_flexibility.model {setting(cfg, 'rail_flexibility.model')}): "
                "it is linearised about the steady traction; give a "
                "creepage in [-1, 1] other than 0 (a trailer axle's rolling resistance: of order +1e-5 to +1e-4), or the report's "
                "fixed creepage (no wheelset, rail_flexibility none)."]
    speeds = configured_speeds(cfg)
    if not speeds:
        return []
    try:
        m = _material_unchecked({**cfg, "wheelset": None})
    except ValueError:
        return []  # the material's own problem is named where it is built
    vehicles = (cfg.get("fleet") or {}).get("vehicles", [])
    out = []
    # the wheelset section: run by the one train and by every vehicle that names no wheelsets of its own
    if modes is not None and not (vehicles and all(v.get("wheelsets") is not None for v in vehicles)):
        loads = [float(cfg["wheels"]["static_load"])] + [float(v["static_load"]) for v in vehicles]
        out += _unresolved_modes(cfg, m, modes, max(loads), min(speeds), "wheelset", "wheelset.", source)
    if vehicles:
        try:
            fl = fleet(cfg)
        except ConfigError as e:
            return out + [str(e).replace("invalid configuration:\n  ", f"{source}: ")]
        V = min(fl.speeds.speeds)
        out += _fleet_zero_creepages(fl, modes is not None, flexible, source)
        for i, v in enumerate(fl.vehicles):
            seen = set()
            for j, (name, ws) in enumerate(zip(v.wheelset_names or (), v.wheelsets or ())):
                if id(ws) in seen or (fm := wheelset_modes(ws)) is None:
                    continue
                seen.add(id(ws))
                key = f"fleet.wheelsets.{name}" if name else f"fleet.vehicles[{i}] ({v.name}).wheelsets[{j}]"
                out += _unresolved_modes(cfg, m, fm, v.static_load, V, f"{key} (vehicle {v.name})", f"{key}.", source)
    return out


def _fleet_zero_creepages(fl, scenario_modes: bool, flexible: bool, source: str) -> list[str]:
    """One line per fleet vehicle with an axle at a creepage of exactly 0 whose contact carries a dynamic creepage (its
    own wheelset's modes, the scenario's wheelset, or the rail's flexibility): the per-axle form of the one train's check
    in dynamic_creepage_problems (found by the fleet source's benchmark, whose coach's trailing axles at 0 stopped
    after minutes with "did not settle"). A vehicle's axles run the scenario's wheelset unless it names its own."""
    out = []
    for i, v in enumerate(fl.vehicles):
        own = v.wheelsets or (None,) * len(v.creepage)
        zero = [j for j, (c, ws) in enumerate(zip(v.creepage, own))
                if float(c) == 0.0 and (flexible or (wheelset_modes(ws) is not None if ws is not None else scenario_modes))]
        if zero:
            out.append(f"{source}: fleet.vehicles[{i}] ({v.name}).creepage = {list(v.creepage)}: an axle at exactly 0 (axle(s) "
                       f"{', '.join(str(j) for j in zero)}) is not allowed with the dynamic creepage (the rail's flexibility or the "
                       "axle's wheelset modes): it is linearised about the steady traction; give each such axle a creepage in "
                       "[-1, 1] other than 0 (a trailer axle's rolling resistance: of order +1e-5 to +1e-4), or the report's fixed "
                       "creepage (no wheelsets, rail_flexibility none).")
    return out


def _unresolved_modes(cfg: dict, m: ContactMaterial, modes, load: float, V: float, what: str, prefix: str, source: str) -> list[str]:
    """One line naming the wheelset (``what``, its keys by ``prefix``) whose modes lie above the contact march's Nyquist
    frequency at the wheel load ``load`` [N] and the slowest speed ``V`` [m/s] (dynamic_creepage_problems), or []."""
    a = float(hertz_half_length(load, m.wheel_radius, m))
    delta = rolling_grid(1.02 * a, _cell_track(cfg).L, int(cfg["numerics"]["contact"]["nodes"]))[0]
    nyquist = V / (2 * delta)
    above = [float(om) / (2 * np.pi) for om in modes.omega if float(om) / (2 * np.pi) > nyquist]
    if not above:
        return []
    return [f"{source}: {what}: the {modes.label} has mode(s) at {', '.join(hz_text(f) for f in above)} Hz, above the "
            f"{hz_text(nyquist)} Hz the contact march resolves at V = {V:g} m/s (its step's Nyquist frequency V / (2 Delta), "
            f"grid spacing Delta = {delta * 1e3:.3g} mm from numerics.contact.nodes = {int(cfg['numerics']['contact']['nodes'])}): "
            f"such a mode is aliased and its force, held over a step, drives it unstably; raise {prefix}wheel_inertia or "
            f"{prefix}centre_inertia (or {prefix}motor_inertia), or lower {prefix}axle_stiffness or {prefix}coupling_stiffness, "
            "to bring it below (the torsional modes of real wheelsets lie at tens to hundreds of hertz)."]


def model_notes(scn: Scenario) -> list[str]:
    """What a valid scenario runs that its keys might not say: a friction law made flat by mu_s = mu_d
    (contact.friction_decay then changes nothing; rail.contact.ContactMaterial.friction_law). The workflow
    says each at start-up and ``railgrowth check`` with its verdict.

    Parameters
    ----------
    scn : Scenario

    Returns
    -------
    list of str
        One line each [-]; [] for most scenarios.
    """
    law = scn.material.friction_law
    return [law.description] if law.flat else []


def spectrum_scenario(cfg: dict, name: str = "default", source: str = "config") -> Scenario:
    """The Scenario of a growth-rate spectrum (``figures.rate_spectrum``): the configuration's, about
    the smooth rail, with the spectrum's roughness period N = figures.rate_spectrum.bays (its lines
    2 pi j / (N L), rail.growth_spectrum).

    Parameters
    ----------
    cfg : dict
        A resolved, validated configuration (rail.setup.config.resolve), SI units.
    name : str
        The scenario's name (results/<...>/<name>/).
    source : str
        Where the configuration comes from (a scenario file), named in every message.

    Returns
    -------
    Scenario
        About the smooth rail, its roughness period the spectrum's N bays.

    Raises
    ------
    ConfigError
        A spectrum period other than the track cell's, or a physics constraint broken (physics_problems).
    """
    bays = int(cfg["figures"]["rate_spectrum"]["bays"])
    cell = cfg["track"].get("cell")
    if cell is not None and int(cell["bays"]) != bays:
        raise ConfigError(f"invalid configuration:\n  {source}: figures.rate_spectrum.bays = {bays} is not allowed with track.cell.bays = "
                          f"{int(cell['bays'])}: the spectrum's lines must be periodic over the track's cell; set it to {int(cell['bays'])}.")
    return scenario({**cfg, "roughness": {**cfg["roughness"], "kind": "smooth", "bays": bays, "record": "average",
                                          "spike_removal": False}}, name, source)


# What one wheel passage over a given roughness reads (forces, contact and wear: Figs 8, 22, 9-19).
# "wheelset" and "rail_flexibility" are optional (absent: the report's fixed creepage); rail.setup.plan.config_part
# skips them when absent.
PASSAGE_KEYS = ("material", "track", "wheels.mass", "wheels.radius", "wheels.static_load", "contact", "numerics.track", "numerics.contact", "wear",
                "wheelset", "rail_flexibility")
OPTIONAL_KEYS = frozenset({"wheelset", "rail_flexibility"})


def passage_scenario(cfg: dict, name: str = "default", source: str = "config") -> Scenario:
    """The single-wheel Scenario of one wheel passage over a given roughness (Figs 8, 22 and 9-19),
    built from the keys of PASSAGE_KEYS alone, so that a job can be handed exactly what it reads.

    Without ``wear`` (the forces alone) the wear law is None; the growth settings, the initial
    roughness and the traffic, which one passage never reads, are None, and the speeds are those of
    the figures in ``cfg`` (checked like the scenario's: physics_problems).

    Parameters
    ----------
    cfg : dict
        A resolved, validated configuration (rail.setup.config.resolve), SI units.
    name : str
        The scenario's name (results/<...>/<name>/).
    source : str
        Where the configuration comes from (a scenario file), named in every message.

    Returns
    -------
    Scenario
        One wheel (wheels.positions not read), speeds [m/s] of the figures.

    Raises
    ------
    ConfigError
        Every physics constraint the configuration breaks (physics_problems), naming ``source``.
    """
    problems = physics_problems(cfg, source)
    if problems:
        raise ConfigError("invalid configuration:\n  " + "\n  ".join(problems))
    w, c, num = cfg["wheels"], cfg["contact"], cfg["numerics"]
    return Scenario(
        name=name,
        track=_cell_track(cfg),
        track_numerics=TrackNumerics(int(num["track"]["harmonics"]), float(num["track"]["rtol"])),
        wheels=Wheels(float(w["mass"]), float(w["radius"]), float(w["static_load"]), (0.0,)),
        spring=_spring(cfg),
        material=_material(cfg, source),
        elastic=elastic(cfg),
        wear_law=WearLaw(float(cfg["material"]["density"]), float(cfg["wear"]["coefficient"])) if "wear" in cfg else None,
        contact_numerics=ContactNumerics(int(num["contact"]["nodes"]), str(c["closure"]), float(c["closure_scale"]), str(c["normal"]),
                                         str(c["wear_path"])),
        growth=None,
        roughness=None,
        speeds=tuple(configured_speeds(cfg)),
        axles_per_day=None,
    )


def scenario(cfg: dict, name: str = "default", source: str = "config") -> Scenario:
    """The Scenario of a resolved, validated configuration (rail.setup.config.resolve).

    The passage's Scenario (passage_scenario: track, contact, wear) with the train's wheel positions, the
    growth settings, the initial roughness, the speeds, the traffic and the track's cell added.
    Raises ConfigError listing every physics constraint the configuration breaks (physics_problems),
    with ``source`` (the scenario file) in each line.

    Parameters
    ----------
    cfg : dict
        A resolved, validated configuration (rail.setup.config.resolve), SI units.
    name : str
        The scenario's name (results/<...>/<name>/).
    source : str
        Where the configuration comes from (a scenario file), named in every message.

    Returns
    -------
    Scenario
    """
    passage = passage_scenario(cfg, name, source)
    g = cfg["growth"]
    return dataclasses.replace(
        passage,
        wheels=dataclasses.replace(passage.wheels, positions=tuple(float(a) for a in cfg["wheels"]["positions"])),
        growth=GrowthSettings(passages=int(g["passages"]), passages_per_update=int(g["passages_per_update"]),
                              save_every=int(g["save_every"]), vary_grid_spacing=bool(g["vary_grid_spacing"]),
                              step_tolerance=float(g["step_tolerance"])),
        roughness=_roughness(cfg, source),
        speeds=tuple(float(v) for v in cfg["speeds"]),
        axles_per_day=float(cfg["traffic"]["axles_per_day"]),
        cell=track_cell(cfg),
    )


def fleet(cfg: dict) -> Fleet | None:
    """The traffic of a resolved configuration (config key ``fleet``, rail.fleet), or None without one.

    Raises ConfigError naming the key if a vehicle or the speed distribution is not allowed (the
    schema and rail.setup.config's cross-checks have refused most of it already).

    Parameters
    ----------
    cfg : dict
        A resolved, validated configuration (rail.setup.config.resolve), SI units.

    Returns
    -------
    rail.fleet.Fleet or None
    """
    f = cfg.get("fleet")
    if f is None:
        return None
    try:
        named = {str(n): _fleet_wheelset(cfg, w, f"fleet.wheelsets.{n}") for n, w in (f.get("wheelsets") or {}).items()}
        vehicles = tuple(Vehicle(str(v["name"]), tuple(float(a) for a in v["positions"]), float(v["static_load"]),
                                 float(v["unsprung_mass"]), tuple(float(c) for c in v["creepage"]), float(v["share"]),
                                 *_vehicle_wheelsets(cfg, v, named, f"fleet.vehicles[{i}] ({v['name']}).wheelsets"))
                         for i, v in enumerate(f["vehicles"]))
        return Fleet(vehicles, speed_classes(f["speeds"]), float(cfg["traffic"]["axles_per_day"]))
    except ValueError as e:
        raise ConfigError(f"invalid configuration:\n  {e}") from None


FLEET_WHEELSET_KEYS = ("wheel_inertia", "centre_inertia", "axle_stiffness", "motor_inertia", "coupling_stiffness", "damping")


def _fleet_wheelset(cfg: dict, spec: dict, key: str) -> Wheelset:
    """One wheelset of a fleet (the schema's $defs fleet_wheelset): its model and chain from its keys, each left out
    at the schema's default of the wheelset section's key (not the section's value in the file); a trailer without
    a drive; the radius wheels.radius and the other wheel wheelset.other_wheel, as for one train. A value the
    Wheelset refuses (the schema has refused it first) is named by ``key``."""
    schema = project_schema()
    params = {k: float(spec[k]) if k in spec else float(schema_default(schema, f"wheelset.{k}")) for k in FLEET_WHEELSET_KEYS}
    if spec["drive"] == "trailer":
        params["motor_inertia"] = 0.0
    model = str(spec.get("model", schema["$defs"]["fleet_wheelset"]["properties"]["model"]["default"]))
    try:
        return Wheelset(model=model, radius=float(cfg["wheels"]["radius"]), other_wheel=str(setting(cfg, "wheelset.other_wheel")),
                        **params)
    except ValueError as e:
        text = str(e)
        raise ValueError(text if text.startswith("wheels.") else text.replace("wheelset.", f"{key}.", 1)) from None


def _vehicle_wheelsets(cfg: dict, v: dict, named: dict, key: str) -> tuple:
    """(wheelsets, wheelset_names) of a vehicle (rail.fleet.Vehicle): one Wheelset per axle, a named one the object of
    ``named`` (so two axles or vehicles naming it hold one object), one given in place built once for the axles it
    serves; (None, None) where the vehicle names none (every axle the wheelset section's)."""
    given = v.get("wheelsets")
    if given is None:
        return None, None
    n = len(v["positions"])
    entries = given if isinstance(given, list) else [given] * n
    built = {}
    for j, w in enumerate(entries):
        if not isinstance(w, str) and id(w) not in built:
            built[id(w)] = _fleet_wheelset(cfg, w, f"{key}[{j}]" if isinstance(given, list) else key)
    return (tuple(named[w] if isinstance(w, str) else built[id(w)] for w in entries),
            tuple(w if isinstance(w, str) else "" for w in entries))


def fleet_classes(cfg: dict, scn: Scenario) -> tuple:
    """The (vehicle, speed) classes of the configuration's fleet (rail.fleet.Fleet.classes), each the
    scenario ``scn`` with the vehicle's wheels, contact spring (scaled from the load
    ``wheels.static_load`` that ``contact.hertz_stiffness`` is given for) and per-axle creepage, at
    one speed; () without a fleet.

    Parameters
    ----------
    cfg : dict
        A resolved, validated configuration (rail.setup.config.resolve), SI units.
    scn : Scenario
        The scenario each class starts from (scenario or spectrum_scenario of ``cfg``).

    Returns
    -------
    tuple of rail.fleet.FleetClass
        In the fleet's order, each with its speed [m/s] and share [-].
    """
    fl = fleet(cfg)
    return () if fl is None else fl.classes(scn, float(cfg["wheels"]["static_load"]))
