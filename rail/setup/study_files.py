"""The study files of config/ that are not scenarios: the studies of config/studies/ (a named target each:
defaults and cases), the traffic study (traffic_study.yaml), the convergence study (convergence.yaml), the
uncertainty ensemble (uncertainty.yaml), and the name of a fleet class's spectrum job. Read at start-up by the
plan (rail.setup.plan), before any job runs; each problem is one line naming the file and key."""

from __future__ import annotations

import copy
import dataclasses
from pathlib import Path

import numpy as np

__all__ = ["STUDY_FILE_KEYS", "BUILDS", "SUMMARIES", "SPEED_STUDY", "study_file", "read_studies", "study_cases", "study_summary",
           "TRAFFIC_KEYS", "traffic_cases",
           "CLASS_SPECTRUM_READS", "class_key", "ClassEstimate", "class_estimate", "check_convergence_study",
           "uncertainty_study"]


# The studies of config/studies/<name>.yaml (issue 57, item 9): a named target each (snakemake -j2 <name>); each
# case is a scenario named by its key (or a sweep, its points <case>-p<n>), the file's defaults merged under the
# case's own keys, as a scenario file would hold them (only the keys that differ from config/config.yaml). The
# target builds of each case what ``builds`` says (BUILDS; by default its growth-rate spectrum,
# results/spectrum/<case>/rate_spectrum.png), then the study's summary, if it has one. config/scenarios/ holds
# the users' own scenarios: a file there joins no named target by its name.

STUDY_FILE_KEYS = ("description", "defaults", "cases", "include", "builds", "summary")
# What a named target builds of a case: its growth-rate spectrum's figure, the outputs of its target
# study_<case> (Plan.study_targets), or nothing (the study's summary alone).
BUILDS = ("spectrum", "settled", "study", "none")
# The summaries a study file may name (summary.kind), each made by its own rules from the cases its roles name
# (a role of one case, or of a list of cases; None: optional), and each set by one study file at most (its
# outputs' paths are fixed): the speed study over every case (rule speed_study, results/dynamic_creepage/speeds.*),
# the closure study (workflow/rules/closure.smk, results/closure/), the irregular track
# (workflow/rules/irregular.smk, results/irregular/) and the mitigation study (workflow/rules/mitigation.smk,
# results/mitigation/: spread, the default track's cases at three speeds each; dampers, soft_pad, stiff_pad and
# trailer, the mitigations' cases at one of those speeds each).
SUMMARIES = {"speed_study": {}, "closure_study": {"run": str, "soft": str, "four": str},
             "irregular_track": {"uniform": str, "cases": list, "random": None},
             "mitigation": {"spread": list, "dampers": list, "soft_pad": list, "stiff_pad": list, "trailer": list}}
SPEED_STUDY = "speed_study"  # the summary kind of the speed study (Plan.speed_study_spectra)


def study_file(path, data: dict) -> dict:
    """A study file's cases as scenario mappings, checked.

    Parameters
    ----------
    path : str or Path
        The file (config/studies/<name>.yaml), named in every message.
    data : dict
        Its content: description (text), defaults (scenario keys every case starts from), cases ({name:
        scenario keys, or null for the defaults alone; with ``sweep:`` a sweep study}), include (names of cases
        of other study files the target shows too, listed first), builds (what the target builds of each
        case, BUILDS: one for every case, or {case: kind} with spectrum for a case not named), summary
        ({kind: a key of SUMMARIES, and its roles: the names of the cases each part of the summary reads}).

    Returns
    -------
    dict
        {"cases": {name: scenario mapping}, "include": [names], "builds": {case: kind} of every case included
        and of every case, "summary": the summary mapping or None}, cases in the file's order.

    Raises
    ------
    ValueError
        Naming the file and the key.
    """
    import copy
    import re

    from .config import deep_merge

    unknown = sorted(set(data) - set(STUDY_FILE_KEYS))
    if unknown:
        raise ValueError(f"{path}: unknown key {unknown[0]}; the keys of a study file are "
                         f"{', '.join(STUDY_FILE_KEYS)}.")
    defaults, cases, include = data.get("defaults") or {}, data.get("cases"), data.get("include") or []
    if not isinstance(defaults, dict):
        raise ValueError(f"{path}: defaults = {defaults!r} is not allowed: it must be a mapping of scenario keys.")
    if not isinstance(cases, dict) or not cases:
        raise ValueError(f"{path}: cases must map each case's name to its scenario keys (a mapping, or null for "
                         "the defaults alone); the file has none.")
    if not isinstance(include, list) or not all(isinstance(n, str) for n in include):
        raise ValueError(f"{path}: include = {include!r} is not allowed: it must be a list of case names of other study files.")
    out = {}
    for name, keys in cases.items():
        if not isinstance(name, str) or not re.fullmatch(r"[A-Za-z0-9_.]+(-[A-Za-z0-9_.]+)*", name):
            raise ValueError(f"{path}: case name {name!r} is not allowed: it must be letters, digits, '_', '.' and '-' "
                             "(it names the results' folder).")
        if keys is not None and not isinstance(keys, dict):
            raise ValueError(f"{path}: cases.{name} = {keys!r} is not allowed: it must be a mapping of scenario keys (or null).")
        out[name] = deep_merge(copy.deepcopy(defaults), keys or {})
    names = list(include) + list(out)
    builds = data.get("builds", "spectrum")
    if builds in BUILDS:
        builds = dict.fromkeys(names, builds)
    elif isinstance(builds, dict) and set(builds) <= set(names) and set(builds.values()) <= set(BUILDS):
        builds = {n: builds.get(n, "spectrum") for n in names}
    else:
        raise ValueError(f"{path}: builds = {builds!r} is not allowed: it must be one of {', '.join(BUILDS)}, or map cases of "
                         "the file (or included) to one of them.")
    return {"cases": out, "include": list(include), "builds": builds, "summary": _summary(path, data.get("summary"), names)}


def _summary(path, summary, names: list) -> dict | None:
    """A study file's summary (SUMMARIES), checked: a known kind, and each of its roles naming cases of the file."""
    if summary is None:
        return None
    kinds = ", ".join(SUMMARIES)
    if not isinstance(summary, dict) or summary.get("kind") not in SUMMARIES:
        raise ValueError(f"{path}: summary = {summary!r} is not allowed: it must be a mapping with a kind, one of {kinds}, "
                         "and that summary's roles.")
    roles = SUMMARIES[summary["kind"]]
    for role in sorted(set(summary) - {"kind"} - set(roles)):
        raise ValueError(f"{path}: summary.{role} is not known: the roles of summary {summary['kind']} are "
                         f"{', '.join(roles) or 'none'}.")
    for role, kind in roles.items():
        value = summary.get(role)
        given = [value] if isinstance(value, str) else value
        if value is None and kind is None:
            continue
        if not isinstance(value, kind or str) or not given or [n for n in given if n not in names]:
            what = "a list of cases" if kind is list else "one case"
            raise ValueError(f"{path}: summary.{role} = {value!r} is not allowed: it must be {what} of the file "
                             f"({', '.join(names)}).")
    return dict(summary)


def read_studies(root) -> tuple[dict, dict, dict]:
    """Every study file of ``root``/config/studies/ (sorted by name), each checked (study_file).

    Parameters
    ----------
    root : str or Path
        The project folder.

    Returns
    -------
    tuple of dict
        studies {name: {"path", "cases": [case names], "include", "builds", "summary"}}; cases {case name:
        (source for messages, scenario mapping)}; problems {study name: one line naming the file} of the
        files that are not valid (left out: only their targets stop).

    Raises
    ------
    ValueError
        A case name given by two study files, or a summary kind set by two, naming both.
    """
    from .config import ConfigError, load_yaml

    studies, cases, problems = {}, {}, {}
    folder = Path(root) / "config" / "studies"
    for path in sorted(folder.glob("*.yaml")) if folder.is_dir() else []:
        try:
            st = study_file(path, load_yaml(path))
        except (ConfigError, ValueError) as e:
            problems[path.stem] = " ".join(str(e).split())
            continue
        for name, keys in st["cases"].items():
            if name in cases:
                raise ValueError(f"{path}: the case name '{name}' is also a case of {cases[name][0].split(' (case')[0]}; "
                                 "rename one of them.")
            cases[name] = (f"{path} (case {name})", keys)
        kind = (st["summary"] or {}).get("kind")
        other = next((s["path"] for s in studies.values() if (s["summary"] or {}).get("kind") == kind), None) if kind else None
        if other:
            raise ValueError(f"{path}: summary {kind} is also {other}'s: each summary writes its own files, so one study file "
                             "at most may name it.")
        studies[path.stem] = {**st, "path": str(path), "cases": list(st["cases"])}
    return studies, cases, problems


def study_summary(studies: dict, kind: str) -> dict:
    """The summary of kind ``kind`` (SUMMARIES) of the study file that names it, with its file's name as
    ``study``, or {} where no study file names it.

    Parameters
    ----------
    studies : dict
        {name: study} as read_studies gives them.
    kind : str
        A key of SUMMARIES.

    Returns
    -------
    dict
        {"kind", "study", and the roles: case names}.
    """
    return next(({**st["summary"], "study": name} for name, st in studies.items() if (st["summary"] or {}).get("kind") == kind), {})


def study_cases(root) -> dict:
    """{case name: (source, scenario mapping)} of every study file of ``root``/config/studies/
    (rail.app.api.load finds a case by its name as it finds a scenario file).

    Parameters
    ----------
    root : str or Path
        The project folder.

    Returns
    -------
    dict
        {case name: (source for messages, scenario mapping)}.

    Raises
    ------
    ValueError
        The first study file that is not valid, or a case name given twice.
    """
    _, cases, problems = read_studies(root)
    if problems:
        raise ValueError(next(iter(problems.values())))
    return cases


# The traffic study (config/traffic_study.yaml, README "Traffic"): cases of one fleet at a spread of
# speeds with the locomotive driven or braked, compared by their growth-rate spectra.

TRAFFIC_KEYS = ("speed", "spreads", "distribution", "classes", "vehicles", "drives", "spectrum")


def _study_error(key, value, rule):
    return ValueError(f"config/traffic_study.yaml: {key} = {value!r} is not allowed: {rule}.")


def traffic_cases(study: dict) -> dict:
    """The scenario mappings of the traffic study, one per (drive, spread): the keys a scenario file
    would hold (``fleet``, with the study's ``spectrum`` as ``fleet.spectrum``), named ``traffic_study-<drive>-s<percent>``.

    Parameters
    ----------
    study : dict
        config/traffic_study.yaml: speed [m/s], spreads [-] (uniform on speed (1 -+ s)), distribution
        ('uniform' or 'normal': a normal of standard deviation s speed / sqrt(3), the uniform's),
        classes [-], vehicles (name, positions [m], static_load [N], unsprung_mass [kg], share [-]),
        drives ({drive: {vehicle: creepage [-]}}), spectrum (fleet.spectrum keys).

    Returns
    -------
    dict
        {name: scenario mapping}, drives outer, spreads inner, in the file's order.

    Raises
    ------
    ValueError
        Naming the key, value and valid range (the fleet's own checks follow when each scenario is built).
    """
    missing = [k for k in TRAFFIC_KEYS if k not in study]
    extra = [k for k in study if k not in TRAFFIC_KEYS]
    if missing or extra:
        raise ValueError(f"config/traffic_study.yaml: keys {missing} missing, {extra} unknown: it holds exactly {list(TRAFFIC_KEYS)}.")
    V = study["speed"]
    if isinstance(V, bool) or not isinstance(V, (int, float)) or not (np.isfinite(V) and V > 0):
        raise _study_error("speed", V, "it must be a finite number > 0 m/s")
    spreads = study["spreads"]
    if not isinstance(spreads, list) or not spreads:
        raise _study_error("spreads", spreads, "give a non-empty list of speed spreads in [0, 0.5)")
    for i, s in enumerate(spreads):
        if isinstance(s, bool) or not isinstance(s, (int, float)) or not (np.isfinite(s) and 0 <= s < 0.5):
            raise _study_error(f"spreads[{i}]", s, "it must be a number in [0, 0.5)")
    if len({round(100 * float(s), 6) for s in spreads}) != len(spreads):
        raise _study_error("spreads", spreads, "each spread must be given once (to 1e-6 %)")
    if study["distribution"] not in ("uniform", "normal"):
        raise _study_error("distribution", study["distribution"], "it must be 'uniform' or 'normal'")
    n = study["classes"]
    if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= 50:
        raise _study_error("classes", n, "it must be an integer in [1, 50]")
    vehicles = study["vehicles"]
    names = [v.get("name") for v in vehicles] if isinstance(vehicles, list) else []
    if not names:
        raise _study_error("vehicles", vehicles, "give a list of vehicles (name, positions, static_load, unsprung_mass, share)")
    drives = study["drives"]
    if not isinstance(drives, dict) or not drives:
        raise _study_error("drives", drives, "give {drive: {vehicle: creepage}}")
    for d, creep in drives.items():
        if not isinstance(creep, dict) or sorted(creep) != sorted(names):
            raise _study_error(f"drives.{d}", creep, f"give one creepage for each vehicle, {names}")
    out = {}
    for d, creep in drives.items():
        for s in spreads:
            s = float(s)
            if s == 0:
                speeds = {"values": [float(V)], "weights": [1.0]}
            elif study["distribution"] == "uniform":
                speeds = {"distribution": "uniform", "low": V * (1 - s), "high": V * (1 + s), "classes": n}
            else:
                speeds = {"distribution": "normal", "mean": float(V), "std": V * s / np.sqrt(3), "classes": n}
            fleet = {"vehicles": [{**v, "creepage": [float(creep[v["name"]])] * len(v["positions"])} for v in vehicles],
                     "speeds": speeds}
            out[f"traffic_study-{d}-s{100 * s:g}"] = {"fleet": {**fleet, "spectrum": copy.deepcopy(study["spectrum"])}}
    band = study["spectrum"].get("band") if isinstance(study["spectrum"], dict) else None
    if band and "speeds" not in band:  # resolved at every case's speeds, so that a class is computed once for all cases
        from ..fleet import speed_classes

        try:
            every = sorted({round(float(v), 9) for c in out.values() for v in speed_classes(c["fleet"]["speeds"]).speeds})
        except ValueError as e:
            raise _study_error("spreads", spreads, str(e)) from None
        for c in out.values():
            c["fleet"]["spectrum"]["band"]["speeds"] = every
    return out


# The Scenario fields a class spectrum reads (rail.growth_spectrum.rate_spectrum through rail.chain), besides
# its roughness period scn.roughness.bays: class_key hashes these and nothing else
CLASS_SPECTRUM_READS = ("track", "track_numerics", "wheels", "spring", "material", "elastic", "wear_law", "contact_numerics",
                        "speeds", "cell")


def class_key(fleet_class, settings: dict, wheel=None) -> str:
    """A name for one class's spectrum that says what it holds and is the same in every fleet holding
    the class: ``<vehicle>_V<speed>_<hash>``, the vehicle's name (characters other than letters,
    digits, ``.`` and ``-`` written as ``-``), the speed to four significant figures, and a hash of
    what the class spectrum reads (CLASS_SPECTRUM_READS: the class's track, wheels, contact spring and
    material, half-space, wear law, contact numerics, the spectrum's period and speed; the track cell)
    and of the spectrum's settings, which keeps two classes of the same vehicle and speed on other
    tracks or settings apart. The scenario's name, its growth settings (growth.passages, ...), its
    initial roughness (a spectrum is taken about the smooth rail: only its period N counts) and its
    traffic are not read by a class spectrum and are not hashed, so that changing them reruns no class
    (issue 57, item 8). The name is a label only: the plan maps it to its class, nothing parses it back.

    Parameters
    ----------
    fleet_class : rail.fleet.FleetClass
    settings : dict
        figures.rate_spectrum (shortest, longest, per_octave, eps, grid_phases, bays) [m, -].
    wheel : rail.noise.named.RoughnessSpectrum, optional
        The vehicle's wheels' roughness where the fleet's wheels are a source (rail.setup.inputs.wheel_source_spectra):
        its band centres [m] and levels [dB re 1 µm] are hashed too (the class file then carries the source's arrays,
        rail.studies.wheel_source.class_source_arrays); without one (None) the key is the one before the source existed.

    Returns
    -------
    str
        e.g. ``locomotive_V40_3f2a9c0d1e4b5a67`` (the hash: 16 hexadecimal digits).
    """
    import hashlib
    import json
    import re

    scn = fleet_class.scenario
    read = {field: getattr(scn, field) for field in CLASS_SPECTRUM_READS}
    read["bays"] = scn.roughness.bays  # the spectrum's period (its roughness is the smooth rail's)
    text = repr(read) + json.dumps({k: settings[k] for k in sorted(settings) if k != "speeds"}, sort_keys=True, default=str)
    if wheel is not None:  # the wheels' source: what the class file's source arrays read (none: the key as before)
        text += json.dumps({"wheel_source": [np.asarray(wheel.centres).tolist(), np.asarray(wheel.levels).tolist()]})
    vehicle = re.sub(r"[^A-Za-z0-9.-]+", "-", str(fleet_class.vehicle)).strip("-") or "vehicle"
    return f"{vehicle}_V{fleet_class.speed:.4g}_{hashlib.sha256(text.encode()).hexdigest()[:16]}"


# A class spectrum's cost (rule fleet_class_spectrum), fitted to max_rss and CPU time of measured jobs
# (docs/traffic.md, docs/cluster.md): the four-axle locomotive and coach of the traffic study, 17 axle offsets.
CLASS_MEMORY_MB = (700.0, 7.0)  # MB: base, and per line and axle
CLASS_CPU_SECONDS = 1.6         # s per line, axle and contact grid (61 nodes, one core)


@dataclasses.dataclass(frozen=True)
class ClassEstimate:
    """What one class spectrum job needs.

    lines       : wavenumber lines of the spectrum [-]
    axles       : axles of the class's vehicle [-]
    memory_mb   : resident memory [MB], CLASS_MEMORY_MB[0] + CLASS_MEMORY_MB[1] x lines x axles
    cpu_seconds : CPU time on one core [s], CLASS_CPU_SECONDS x lines x axles x grid phases x (nodes / 61)^2
    """

    lines: int
    axles: int
    memory_mb: float
    cpu_seconds: float


def class_estimate(fleet_class, settings: dict) -> ClassEstimate:
    """The memory and CPU time of one class spectrum (rule fleet_class_spectrum), from its lines
    (rail.growth_spectrum.spectrum_lines over the settings' wavelengths and period), its axles and its
    contact grids; the coefficients are fitted to measured jobs (CLASS_MEMORY_MB, CLASS_CPU_SECONDS).

    Parameters
    ----------
    fleet_class : rail.fleet.FleetClass
        Its scenario gives the sleeper spacing, harmonics, axles and contact nodes.
    settings : dict
        figures.rate_spectrum of the fleet (bays, shortest, longest, per_octave, grid_phases) [m, -].

    Returns
    -------
    ClassEstimate
    """
    from ..growth_spectrum import settings_lines

    scn = fleet_class.scenario
    lines = len(settings_lines(scn.L, int(settings["bays"]), scn.harmonics, settings))
    axles = len(scn.wheels.positions)
    nodes = scn.contact_numerics.nodes
    return ClassEstimate(lines, axles, CLASS_MEMORY_MB[0] + CLASS_MEMORY_MB[1] * lines * axles,
                         CLASS_CPU_SECONDS * lines * axles * int(settings["grid_phases"]) * (nodes / 61) ** 2)


def uncertainty_study(config: dict, schema: dict, path) -> dict:
    """The uncertainty ensemble (config/uncertainty.yaml, rail.uncertainty): the members' configurations,
    drawn with the seed and validated (a draw outside a key's range names the member and the key).

    Parameters
    ----------
    config : dict
        The resolved, validated default configuration the members are drawn about.
    schema : dict
        config/schema/config.schema.yaml.
    path : Path
        config/uncertainty.yaml (members, seed, parameters, interval [-], speed [m/s], spectrum; optional changes,
        keys merged into every member before its draws).

    Returns
    -------
    dict
        {"members": [{"cfg": configuration as the physics reads it, "values": the draws}], "speed" [m/s],
        "interval" [-], "draws": {key: [value per member]}}; {} without the file.

    Raises
    ------
    rail.setup.config.ConfigError
        Naming the file, the member and the key.
    """
    from .. import uncertainty as unc
    from .build import spectrum_scenario
    from .config import ConfigError, load_yaml, validate_config
    from .targets import read_part

    if not path.exists():
        return {}
    u = load_yaml(path)
    try:
        draws = unc.sample(u["parameters"], u["members"], u["seed"])
        unc.band_statistics(np.zeros((1, 1)), u["interval"])  # the interval's quantiles checked
    except (ValueError, KeyError) as e:
        raise ConfigError(f"invalid configuration:\n  {path}: {e}") from None
    members = []
    base = config
    if u.get("changes"):  # keys every member holds before its draws (e.g. the rail's flexibility, which e and k_x act through)
        from .config import deep_merge
        base = deep_merge(config, u["changes"])
    for m in range(int(u["members"])):
        vals = {k: float(v[m]) for k, v in draws.items()}
        try:
            cfg = unc.member_config(base, vals, schema)
        except ValueError as e:
            raise ConfigError(f"invalid configuration:\n  {path}: {e}") from None
        cfg["figures"]["rate_spectrum"].update(u["spectrum"])
        src = f"{path} (member {m}: {', '.join(f'{k} = {v:.6g}' for k, v in vals.items())})"
        cfg = read_part(validate_config(cfg, schema, source=src), schema)
        spectrum_scenario(cfg, f"uncertainty-m{m}", src)  # physics constraints, naming the member
        members.append({"cfg": cfg, "values": vals})
    return {"members": members, "speed": float(u["speed"]), "interval": list(u["interval"]),
            "draws": {k: [float(x) for x in v] for k, v in draws.items()}}


def check_convergence_study(study: dict, source: str = "config/convergence.yaml") -> None:
    """Check the convergence study's file before any job: a speed, and per known setting a quantity
    (force, wear or growth), values and a reference that are finite numbers > 0 (integers for the
    counts), and the wear frequencies finite > 0. Raises ValueError, one line naming file and key.

    Parameters
    ----------
    study : dict
        config/convergence.yaml: speed [m/s], settings ({name: quantity, values, reference}), wear_frequencies [Hz].
    source : str
        The file, named in the message.

    Returns
    -------
    None

    Raises
    ------
    ValueError
        One line naming the file and the key.
    """
    def positive(key, v, whole=False):
        ok = isinstance(v, (int, float)) and not isinstance(v, bool) and np.isfinite(v) and v > 0
        if not ok or (whole and float(v) != int(v)):
            kind = "a whole number > 0" if whole else "a finite number > 0"
            raise ValueError(f"{source}: {key} = {v!r} is not allowed: it must be {kind}.")

    if not isinstance(study, dict) or not isinstance(study.get("settings"), dict):
        raise ValueError(f"{source}: the file must map 'speed', 'settings' and 'wear_frequencies'.")
    positive("speed", study.get("speed"))
    whole = {"harmonics", "nodes", "nodes_growth", "passages_per_update"}
    for name, st in study["settings"].items():
        if name not in whole | {"rtol"}:
            raise ValueError(f"{source}: settings.{name} is not known: the settings are harmonics, rtol, nodes, nodes_growth, "
                             "passages_per_update.")
        if not isinstance(st, dict) or st.get("quantity") not in ("force", "wear", "growth"):
            raise ValueError(f"{source}: settings.{name}.quantity = {(st or {}).get('quantity')!r} is not allowed: it must be one "
                             "of force, wear, growth.")
        values = st.get("values")
        if not isinstance(values, list) or not values:
            raise ValueError(f"{source}: settings.{name}.values = {values!r} is not allowed: it must be a non-empty list.")
        for i, v in enumerate(values):
            positive(f"settings.{name}.values[{i}]", v, name in whole)
        positive(f"settings.{name}.reference", st.get("reference"), name in whole)
    freqs = study.get("wear_frequencies")
    if not isinstance(freqs, list) or not freqs:
        raise ValueError(f"{source}: wear_frequencies = {freqs!r} is not allowed: it must be a non-empty list of Hz.")
    for i, f in enumerate(freqs):
        positive(f"wear_frequencies[{i}]", f)
