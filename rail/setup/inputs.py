"""A scenario's input files and speed-dependent constraints, checked in one place.

The workflow at start-up (workflow/rules/common.smk), ``railgrowth check`` and ``run`` and
rail.app.api all call ``check_inputs`` after the schema (rail.setup.config) and the physics checks
(rail.setup.build.scenario), so that they accept and refuse the same scenarios, with the same
one-line messages naming the scenario, its file, the key and the problem.
"""

from __future__ import annotations

import copy
from pathlib import Path

from ..decay import read_measured_decay_rate
from ..growth_spectrum import settings_lines
from ..roughness import read_limit_spectrum, read_third_octave_spectrum
from ..scenario import Scenario
from .build import fleet_classes, physics_problems
from .config import ConfigError

__all__ = ["FILE_KEYS", "MAX_SPEED", "resolve_paths", "measured_decay_file", "check_inputs", "check_speed", "fleet_checked", "band_inputs",
           "wheel_source_spectra", "vehicle_wheel_key", "noise_problem", "noise_files"]

MAX_SPEED = 300.0  # m/s, the schema's bound on a configured speed (config/schema: speeds.items.maximum)

# The configuration keys that name files (relative paths are relative to the project folder)
FILE_KEYS = (("roughness", "file"), ("figures", "bands", "limit"), ("figures", "bands", "wheel_roughness"), ("measured", "decay_rate"),
             ("wheel_source", "file"), ("wheel_source", "ground_file"))


def _get(cfg: dict, keys):
    node = cfg
    for k in keys:
        if not isinstance(node, dict) or k not in node:
            return None
        node = node[k]
    return node


def resolve_paths(cfg: dict, root) -> dict:
    """The configuration with every relative file path (FILE_KEYS, and fleet.vehicles[*].wheel_source.file) made relative to the project
    folder ``root`` instead of the current folder (a copy; absolute paths and empty keys unchanged).

    Parameters
    ----------
    cfg : dict
        Resolved configuration.
    root : path
        The project folder holding config/.

    Returns
    -------
    dict
    """
    out = copy.deepcopy(cfg)
    root = Path(root)
    for keys in FILE_KEYS:
        value = _get(out, keys)
        if value and not Path(str(value)).is_absolute():
            node = out
            for k in keys[:-1]:
                node = node[k]
            node[keys[-1]] = str(root / str(value))
    for v in (out.get("fleet") or {}).get("vehicles", []):  # a fleet vehicle's own wheel roughness file
        own = v.get("wheel_source") or {}
        if own.get("file") and not Path(str(own["file"])).is_absolute():
            own["file"] = str(root / str(own["file"]))
    return out


def measured_decay_file(cfg: dict, name: str, root=".") -> tuple[str | None, str]:
    """The measured decay-rate file of a scenario and the key that names it: measured.decay_rate if
    given, else config/measured/<name>_decay_rate.csv under ``root`` if it exists, else None.

    Parameters
    ----------
    cfg : dict
        A resolved configuration.
    name : str
        The scenario's name.
    root : str or Path
        The project folder.

    Returns
    -------
    tuple of (str or None, str)
        The file (None: none) and the key that names it (measured.decay_rate, or where it was looked for).
    """
    given = _get(cfg, ("measured", "decay_rate"))
    if given:
        return str(given), "measured.decay_rate"
    found = Path(root) / "config" / "measured" / f"{name}_decay_rate.csv"
    return (str(found), f"{found} (the track's measured decay rate)") if found.exists() else (None, "")


def check_speed(cfg: dict, speed, source: str, name: str = "speed") -> float:
    """A speed given outside the configuration (a target's file name, the command line, the API),
    checked like a configured one: a finite number > 0 within the schema's bound at which the
    harmonics reach the pinned-pinned frequency. The workflow's targets, railgrowth and the API all
    check a speed here.

    Parameters
    ----------
    cfg : dict
        Resolved configuration.
    speed : float
        Train speed [m/s].
    source : str
        Where the speed comes from (named first in the message).
    name : str
        What the message calls the speed (e.g. 'target speed V40').

    Returns
    -------
    float
        The speed [m/s].

    Raises
    ------
    ConfigError
    """
    if isinstance(speed, bool) or not isinstance(speed, (int, float)):
        raise ConfigError(f"{source}: {name} = {speed!r} is not allowed: it must be a number in m/s.")
    V = float(speed)
    if not (V == V and 0 < V <= MAX_SPEED):
        raise ConfigError(f"{source}: {name} = {V!r} m/s is not allowed: it must lie in (0, {MAX_SPEED:g}] m/s (as speeds in the "
                          "configuration).")
    problems = physics_problems({**cfg, "speeds": [V], "figures": {}}, source)
    if problems:
        raise ConfigError("invalid speed:\n  " + "\n  ".join(problems))
    return V


def fleet_checked(cfg: dict, scn: Scenario, source: str) -> tuple:
    """The (vehicle, speed) classes of a scenario's fleet, checked across keys as every door checks
    them (the workflow's plan, railgrowth and the API): a fleet on a track cell, a roughness whose
    wavelength is tied to one speed, and every class speed (check_speed).

    Parameters
    ----------
    cfg : dict
        Resolved configuration (with the key ``fleet``; () is returned without one).
    scn : Scenario
        Built from ``cfg`` (rail.setup.build.scenario).
    source : str
        The scenario's file (named first in every message).

    Returns
    -------
    tuple of rail.fleet.FleetClass

    Raises
    ------
    ConfigError
        One line naming the file, the keys and what to give instead.
    """
    if "fleet" not in cfg:
        return ()
    r = cfg["roughness"]
    if cfg["track"].get("cell") is not None:
        raise ConfigError(f"{source}: fleet with track.cell is not allowed: a fleet's receptance tables are one per speed shared by "
                          "its vehicles, a track cell's are its own Bloch tables; give each vehicle its own scenario on the cell "
                          "(wheels, contact.creepage, speeds), or the fleet on a track without track.cell.")
    if r.get("kind") == "harmonic" and r.get("wavelength") is None:
        raise ConfigError(f"{source}: roughness.frequency = {r.get('frequency')!r} Hz sets the wavelength at one speed: "
                          "under a fleet at several speeds give roughness.wavelength (m) instead.")
    try:
        classes = fleet_classes(cfg, scn)
    except ConfigError as e:
        raise ConfigError(str(e).replace("invalid configuration:\n  ", f"{source}: ")) from None
    for c in classes:
        try:
            check_speed(cfg, c.speed, f"{source}: fleet class {c.label}")
        except ConfigError as e:
            raise ConfigError(str(e).replace("invalid speed:\n  ", "")) from None
    return classes


def check_inputs(cfg: dict, scn: Scenario, name: str, source: str, root=".") -> None:
    """Read and check every input file of a scenario and the settings that need its physics.

    The initial roughness realised at every speed (its file read: a missing file, a folder, a
    binary or mis-encoded file, a header whose unit is missing or not accepted, values implausible
    for the header's unit, a harmonic wavelength that does not divide the period are errors; a
    measured profile is processed as the run will process it: spike removal, the record's segments),
    the limit spectrum of the band view, the growth-rate spectrum's lines, and the measured decay
    rate (given, or found by the scenario's name under config/measured/); a fleet's cross-key checks
    (fleet_checked).

    Parameters
    ----------
    cfg : dict
        Resolved configuration (its relative paths relative to the current folder).
    scn : Scenario
        Built from ``cfg`` (rail.setup.build.scenario).
    name, source : str
        The scenario's name and file (named in the messages).
    root : path
        The project folder (for config/measured/).

    Returns
    -------
    None

    Raises
    ------
    ConfigError
        One line naming the scenario, its file, the key and the problem.
    """
    where = f"scenario {name} ({source})"
    fleet_checked(cfg, scn, source)
    try:
        for V in scn.speeds:
            scn.roughness.realise(V, scn.L, scn.harmonics)
    except (OSError, ValueError) as e:
        raise ConfigError(f"{where}: roughness: {e}") from None
    for key, read in (("limit", read_limit_spectrum), ("wheel_roughness", read_third_octave_spectrum)):
        path = _get(cfg, ("figures", "bands", key))
        if path:
            try:
                read(path)
            except (OSError, ValueError) as e:
                raise ConfigError(f"{where}: figures.bands.{key}: {e}") from None
    try:  # the wheels' source: its spectrum and the ground rail read now, not after the spectrum's hours
        wheel_source_spectra(cfg)
    except (OSError, ValueError) as e:
        raise ConfigError(f"{where}: {e}") from None
    s = _get(cfg, ("figures", "rate_spectrum"))
    if s:
        try:  # the spectrum's period must resolve its longest wavelength, its shortest lie above L / K
            settings_lines(scn.L, int(s["bays"]), scn.harmonics, s)
        except ValueError as e:
            raise ConfigError(f"{where}: {'fleet.spectrum' if cfg.get('fleet') else 'figures.rate_spectrum'}: {e}") from None
    file, key = measured_decay_file(cfg, name, root)
    if file:
        try:
            read_measured_decay_rate(file)
        except (OSError, ValueError) as e:
            raise ConfigError(f"{where}: {key}: {e}") from None


def band_inputs(cfg: dict, scn: Scenario) -> dict:
    """What the band view of a scenario's growth run reads besides the run (rail.studies.exports.band_outputs),
    read here so that the physics and the studies read no file: the limit spectrum, the wheel roughness,
    the initial roughness's input spectrum (kind spectrum) and the traffic (a fleet's, or the train's).

    Parameters
    ----------
    cfg : dict
        The resolved configuration (figures.bands, roughness, traffic, fleet).
    scn : rail.scenario.Scenario

    Returns
    -------
    dict
        limit, wheel, initial_spectrum: tuples or None; traffic: rail.traffic.Traffic or None.
    """
    from ..traffic import Traffic, traffic_of
    from .build import fleet as build_fleet

    s = cfg["figures"]["bands"]
    wheel = s.get("wheel_roughness")
    r = cfg["roughness"]
    fl = build_fleet(cfg)
    traffic = (Traffic(fl.axles_per_day, fl.mean_axle_load) if fl is not None
               else traffic_of(scn) if scn.axles_per_day is not None else None)
    return {
        "limit": read_limit_spectrum(s["limit"]) if s.get("limit") else None,
        "wheel": (*read_third_octave_spectrum(wheel), str(wheel)) if wheel else None,
        "initial_spectrum": ((*read_third_octave_spectrum(r["file"]), str(r["file"])) if r.get("kind") == "spectrum" and r.get("file")
                             else None),
        "traffic": traffic,
    }


def _wheel_spectrum(name: str, file, key: str):
    """The wheels' roughness a wheel_source section names (key: where, for the messages), or None for none."""
    from ..noise.named import RoughnessSpectrum, named_spectrum

    if name == "none":
        return None
    if name != "file":
        return named_spectrum(name, "wheel")
    if not file:
        raise ValueError(f"{key}.roughness = 'file' needs {key}.file: a CSV wavelength_m,level_dB of the wheels' roughness.")
    try:
        return RoughnessSpectrum(*read_third_octave_spectrum(file), f"the file {file}")
    except (OSError, ValueError) as e:
        raise ValueError(f"{key}.file: {e}") from None


def vehicle_wheel_key(cfg: dict, i: int) -> str:
    """The key that sets fleet vehicle i's wheels' roughness: its own wheel_source, or the top-level one it takes.

    Parameters
    ----------
    cfg : dict
        A resolved configuration with a fleet.
    i : int
        The vehicle's index in fleet.vehicles [-].

    Returns
    -------
    str
        ``fleet.vehicles[i] (<name>).wheel_source`` or ``wheel_source``.
    """
    v = cfg["fleet"]["vehicles"][i]
    return f"fleet.vehicles[{i}] ({v['name']}).wheel_source" if v.get("wheel_source") else "wheel_source"


def wheel_source_spectra(cfg: dict):
    """The wheels' roughness, the ground rail and the limit of a configuration's wheel_source (rail.studies.wheel_source),
    read here so that the studies read no file; None without a source. A fleet's vehicles each take their own
    (fleet.vehicles[*].wheel_source) or the top-level wheel_source.roughness; the ground rail is the top-level's.

    Parameters
    ----------
    cfg : dict
        The resolved configuration (wheel_source, figures.bands.limit, fleet).

    Returns
    -------
    dict or None
        wheel, ground, limit: rail.noise.named.RoughnessSpectrum (limit None without figures.bands.limit; for a fleet
        wheel the top-level's or None); for a fleet also vehicles: {vehicle name: RoughnessSpectrum or None (none)}.
        None where no wheel is rough (one train: roughness none; a fleet: every vehicle's none).

    Raises
    ------
    ValueError
        Naming the key: a file missing or not a spectrum (rail.roughness.read_spectrum_table's checks), roughness
        'file' without a file (roughness or ground; a vehicle's fleet.vehicles[i] (<name>).wheel_source).
    """
    from ..noise.named import RoughnessSpectrum, named_spectrum

    w = cfg.get("wheel_source") or {}
    wheel = _wheel_spectrum(w.get("roughness", "none"), w.get("file"), "wheel_source")
    vehicles = None
    if "fleet" in cfg:
        vehicles = {}
        for i, v in enumerate(cfg["fleet"]["vehicles"]):
            own = v.get("wheel_source")
            vehicles[str(v["name"])] = wheel if not own else _wheel_spectrum(own["roughness"], own.get("file"), vehicle_wheel_key(cfg, i))
        if all(x is None for x in vehicles.values()):
            return None
    elif wheel is None:
        return None
    g = str(w.get("ground", "E"))
    if g in ("E", "M"):
        ground = named_spectrum(g, "rail")
    elif not w.get("ground_file"):
        raise ValueError("wheel_source.ground = 'file' needs wheel_source.ground_file: a CSV wavelength_m,level_dB of the ground rail.")
    else:
        try:
            ground = RoughnessSpectrum(*read_third_octave_spectrum(w["ground_file"]), f"the file {w['ground_file']}")
        except (OSError, ValueError) as e:
            raise ValueError(f"wheel_source.ground_file: {e}") from None
    lim = cfg["figures"]["bands"].get("limit")
    limit = RoughnessSpectrum(*read_limit_spectrum(lim), f"the file {lim}") if lim else None
    out = {"wheel": wheel, "ground": ground, "limit": limit}
    if vehicles is not None:
        out["vehicles"] = vehicles
    return out


def noise_problem(cfg: dict, speed: float | None = None) -> str | None:
    """Why the noise of a growth run of this configuration at ``speed`` [m/s] (a fleet: its class
    speeds, ``speed`` not read) cannot be computed (rail.studies.noise), or None: a speed (a fleet's
    class speed, naming fleet.speeds) outside CNOSSOS-EU's
    7.94 .. 100 m/s, a concrete sleeper's pad stiffness without a pad class and none named
    (figures.noise.pad_class; not asked with figures.noise.track_transfer: own), no traffic. The
    workflow leaves such a run out of study_<name>'s noise and the named target noise
    (docs/noise.md), and the doors refuse it with the same words.

    Parameters
    ----------
    cfg : dict
        The resolved configuration.
    speed : float or None
        Train speed [m/s] of a one-train run (a fleet's classes carry their own).

    Returns
    -------
    str or None
    """
    from ..noise.cnossos import check_speed as noise_speed
    from ..noise.cnossos import pad_class
    from .build import fleet, noise_settings

    s = noise_settings(cfg)
    try:
        if "fleet" in cfg:
            from ..noise.rolling import fleet_traffic
            fleet_traffic(fleet(cfg), s.fleet_brakes, 2 * float(cfg["wheels"]["radius"]), s.vehicles_per_hour)  # each class's speed
        else:
            noise_speed(float(speed), "growth speed")
        if s.sleeper in ("monoblock", "biblock") and s.pad_class is None and s.track_transfer == "cnossos":
            pad_class(cfg["track"]["pad"]["stiffness"])  # the own track transfer needs no pad class
    except ValueError as e:
        return str(e)
    if s.vehicles_per_hour is None and not (cfg.get("traffic") or {}).get("axles_per_day"):
        return "no traffic: give traffic.axles_per_day or figures.noise.vehicles_per_hour"
    return None


def noise_files(scenarios, runs) -> list[str]:
    """The noise outputs (figure, CSV) of the one-train runs [(scenario, speed [m/s])] whose noise can be
    computed (noise_problem); the others are left out (study_<name> and the named target noise; docs/noise.md).

    Parameters
    ----------
    scenarios : mapping
        Scenario name -> resolved configuration (rail.setup.plan.Plan.scenarios).
    runs : sequence of (str, float)

    Returns
    -------
    list of str
    """
    from .targets import speed_label

    return [f"results/growth/{n}/V{speed_label(v)}_noise.{ext}" for n, v in runs
            if n in scenarios and noise_problem(scenarios[n], v) is None for ext in ("png", "csv")]


def fleet_noise_growth_file(name: str, fleets, cfg) -> str:
    """The growth file of a fleet's noise (rule fleet_noise's input); a scenario without a fleet, or a fleet whose
    noise cannot be computed (noise_problem: a class speed outside CNOSSOS-EU's range, naming fleet.speeds), stops
    the run at start-up when, and only when, the target is asked for.

    Parameters
    ----------
    name : str
        The scenario.
    fleets : container of str
        The scenarios that hold a fleet (the plan's fleet_classes).
    cfg : dict or None
        The scenario's resolved configuration.

    Returns
    -------
    str
        ``results/fleet/<name>/growth.nc``.

    Raises
    ------
    ConfigError
        Naming why the fleet's noise cannot be computed.
    """
    from .config import ConfigError

    if name not in fleets:
        raise ConfigError(f"scenario '{name}' has no fleet: its noise is results/growth/{name}/V<speed>_noise.nc per speed.")
    why = noise_problem(cfg)
    if why is not None:
        raise ConfigError(f"scenario '{name}': its fleet's noise cannot be computed: {why}")
    return f"results/fleet/{name}/growth.nc"
