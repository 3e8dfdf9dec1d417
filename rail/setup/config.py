"""Configuration: merge a scenario onto the defaults and validate it with errors a user can act on.

The JSON schema (``config/schema/config.schema.yaml``) is the single statement of types,
units and valid ranges; this module turns a schema violation into one line per problem that
names the key, the value, the valid range and the file it came from.  It never reads a file
it is not handed a path to.
"""

from __future__ import annotations

import copy
import functools
from pathlib import Path

import numpy as np

import yaml
from jsonschema import Draft202012Validator

__all__ = ["ConfigError", "load_yaml", "deep_merge", "validate_config", "resolve",
           "FLEET_SPECTRUM_KEYS", "fleet_spectrum", "expand_sweep", "check_scenario_names",
           "scenario_files", "RESERVED_SCENARIO_NAMES", "SCENARIO_SUFFIXES"]


class ConfigError(ValueError):
    """A configuration value is missing, unknown, of the wrong type or out of range."""


class _UniqueKeyLoader(yaml.SafeLoader):
    """A YAML loader that refuses a key given twice in one mapping (PyYAML keeps the last silently).
    PyYAML's own parser, not libyaml's: it names the offending character of a syntax error (a tab:
    "found character '\\t' that cannot start any token"), which libyaml's message leaves out."""


def _construct_unique_mapping(loader, node, deep=False):
    seen = {}
    for key_node, _ in node.value:
        key = loader.construct_object(key_node, deep=deep)
        if key in seen:
            raise ConfigError(
                f"{loader.name}, line {key_node.start_mark.line + 1}: the key {key!r} is given twice in one mapping "
                f"(first at line {seen[key] + 1}); YAML would keep only the last value."
            )
        seen[key] = key_node.start_mark.line
    return loader.construct_mapping(node, deep=deep)


_UniqueKeyLoader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, _construct_unique_mapping)

RESERVED_SCENARIO_NAMES = ("default",)
LARGE_SWEEP = 100  # sweep points above which a study must be confirmed in its file (confirm_large_sweep: true)


MAX_YAML_NODES = 100_000  # values in a YAML file once its aliases are expanded (config.yaml holds 248, the schema 2,012)


def _check_expanded_size(node, path) -> None:
    """ConfigError naming the file unless the YAML document ``node`` holds at most MAX_YAML_NODES values
    with every alias (*name) expanded: nested aliases multiply (an "alias bomb" of a few lines expands
    to billions), which would exhaust the memory of the schema's validator."""
    sizes = {}

    def size(n) -> int:
        if id(n) in sizes:
            return sizes[id(n)]
        sizes[id(n)] = 1  # a recursive alias counts once (PyYAML refuses it when building)
        if isinstance(n, yaml.MappingNode):
            total = 1 + sum(size(k) + size(v) for k, v in n.value)
        elif isinstance(n, yaml.SequenceNode):
            total = 1 + sum(size(v) for v in n.value)
        else:
            total = 1
        sizes[id(n)] = min(total, MAX_YAML_NODES + 1)
        return sizes[id(n)]

    if node is not None and size(node) > MAX_YAML_NODES:
        raise ConfigError(f"{path}: holds more than {MAX_YAML_NODES} values once its aliases (*name) are expanded: "
                          "write the values out, or check the file for nested aliases (a YAML 'alias bomb').")


def load_yaml(path) -> dict:
    """Read a YAML mapping; an empty file gives an empty dict. A key given twice in one mapping is
    an error naming the file and the line.

    Parameters
    ----------
    path : str or Path
        The YAML file.

    Returns
    -------
    dict

    Raises
    ------
    ConfigError
        Not YAML text, a key given twice, or not a mapping: naming the file and the line.
    """
    path = Path(path)
    with path.open() as fh:
        try:
            loader = _UniqueKeyLoader(fh)
        except (yaml.YAMLError, UnicodeDecodeError) as e:  # not text: the reader fails at its first bytes
            raise ConfigError(f"{path}: not a YAML text file ({' '.join(str(e).split())[:200]}).") from None
        loader.name = str(path)
        try:
            node = loader.get_single_node()
            _check_expanded_size(node, path)  # a YAML alias bomb stops here, before it is built or validated
            data = loader.construct_document(node) if node is not None else None
        except yaml.MarkedYAMLError as e:  # a tab, an unclosed bracket, ...: file, line and column in one line
            mark = e.problem_mark or e.context_mark
            where = f", line {mark.line + 1}, column {mark.column + 1}" if mark is not None else ""
            raise ConfigError(f"{path}{where}: not valid YAML: {e.problem or e.context}.") from None
        except (yaml.YAMLError, UnicodeDecodeError) as e:  # a binary or mis-encoded file
            raise ConfigError(f"{path}: not a YAML text file ({' '.join(str(e).split())[:200]}).") from None
        finally:
            loader.dispose()
    if data is None:
        return {}
    if not isinstance(data, dict):
        raise ConfigError(f"{path}: the top level must be a mapping of keys, not {type(data).__name__}.")
    return data


def deep_merge(base: dict, override: dict) -> dict:
    """Return a copy of ``base`` with ``override`` merged in (nested mappings merge, the rest replaces).

    Parameters
    ----------
    base : dict
        The mapping merged onto (not changed).
    override : dict
        The keys that replace or extend it.

    Returns
    -------
    dict
        A new mapping.
    """
    out = copy.deepcopy(base)
    for key, value in override.items():
        if isinstance(value, dict) and isinstance(out.get(key), dict):
            out[key] = deep_merge(out[key], value)
        else:
            out[key] = copy.deepcopy(value)
    return out


def _range_text(schema: dict) -> str:
    lo = "[" if "minimum" in schema else "("
    hi = "]" if "maximum" in schema else ")"
    vmin = schema.get("exclusiveMinimum", schema.get("minimum", "-inf"))
    vmax = schema.get("exclusiveMaximum", schema.get("maximum", "inf"))
    return f"{lo}{vmin}, {vmax}{hi}"


def _bound_text(validator: str, bound) -> str:
    return {"minimum": ">=", "maximum": "<=", "exclusiveMinimum": ">", "exclusiveMaximum": "<"}[validator] + f" {bound}"


def _short(value, limit: int = 120) -> str:
    """repr of a configuration value, cut to ``limit`` characters (a YAML alias bomb or a huge list
    would otherwise make a message of megabytes)."""
    return _cut(repr(value), limit)


def _cut(text: str, limit: int = 200) -> str:
    """A message part cut to ``limit`` characters."""
    return text if len(text) <= limit else f"{text[:limit]}... ({len(text)} characters)"


def _message(error, source: str) -> str:
    key = ".".join(str(p) for p in error.absolute_path) or "(top level)"
    schema = error.schema if isinstance(error.schema, dict) else {}
    unit = schema.get("unit", "")
    unit_txt = f" {unit}" if unit and unit != "-" else ""
    kind = error.validator
    if kind in ("minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum"):
        return (
            f"{source}: {key} = {_short(error.instance)}{unit_txt} is not allowed: it must be "
            f"{_bound_text(kind, error.validator_value)}{unit_txt} (valid range {_range_text(schema)}{unit_txt})."
        )
    if kind == "additionalProperties":
        allowed = sorted(schema.get("properties", {}))
        unknown = sorted(set(error.instance) - set(allowed))
        prefix = f"{key}." if error.absolute_path else ""
        parts = [f"{prefix}{u} = {_short(error.instance[u])}" for u in unknown]
        return (
            f"{source}: unknown key {', '.join(parts)}; the keys allowed under {key} are: "
            f"{', '.join(allowed)}."
        )
    if kind == "enum":
        return f"{source}: {key} = {_short(error.instance)} is not allowed: it must be one of {error.validator_value}."
    if kind == "type":
        hint = ""
        if isinstance(error.instance, str):
            try:
                float(error.instance)
                hint = f" (YAML reads {error.instance} as text: write the number with a dot and a signed exponent, e.g. 3.5e+8 or 3.5E+08)"
            except ValueError:
                if error.instance.strip()[:1] in ("{", "[") and error.validator_value in ("object", "array"):
                    hint = (" (snakemake --config passes a nested value as text: put the nested keys in a YAML file "
                            "and give it with --configfile)")
        if not hint:
            hint = _accepted_forms(schema, error.validator_value)
        return f"{source}: {key} = {_short(error.instance)} has the wrong type: it must be of type {error.validator_value}{hint}."
    if kind == "required":
        return f"{source}: {key} lacks a required key: {error.message}."
    return f"{source}: {key} = {_short(error.instance)}: {_cut(error.message)}."


def _accepted_forms(schema: dict, kind) -> str:
    """The forms a type error names: the schema's ``examples`` as YAML, else a mapping's keys."""
    if schema.get("examples"):
        forms = [yaml.safe_dump(x, default_flow_style=True, sort_keys=False).strip() for x in schema["examples"]]
        return f" (a mapping; the accepted forms are, e.g., {'; or '.join(forms)})"
    if kind == "object" and schema.get("properties"):
        return f" (a mapping of the keys {', '.join(schema['properties'])})"
    return ""


def _cross_checks(cfg: dict, source: str) -> list[str]:
    """Constraints between keys that a JSON schema cannot state."""
    out = []
    c = cfg.get("contact", {})
    if {"friction_static", "friction_dynamic"} <= set(c) and c["friction_static"] < c["friction_dynamic"]:
        out.append(
            f"{source}: contact.friction_static = {c['friction_static']!r} is not allowed: it must be "
            f">= contact.friction_dynamic = {c['friction_dynamic']!r} (static friction at least the dynamic)."
        )
    r = cfg.get("roughness", {})
    headers = {"file": "k,A_m,B_m", "profile": "position_m,height_m", "spectrum": "wavelength_m,level_dB"}
    if r.get("kind") in headers and not r.get("file"):
        out.append(f"{source}: roughness.kind = '{r['kind']}' needs roughness.file, a CSV with header {headers[r['kind']]}.")
    h = cfg.get("figures", {}).get("halfspace", {})
    if {"radius_min", "radius_max"} <= set(h) and not h["radius_min"] < h["radius_max"]:
        out.append(
            f"{source}: figures.halfspace.radius_min = {h['radius_min']!r} m is not allowed: it must be "
            f"< figures.halfspace.radius_max = {h['radius_max']!r} m."
        )
    nz = cfg.get("figures", {}).get("noise") or {}
    if nz.get("pad_class") is not None and nz.get("sleeper") in ("wooden", "direct"):
        out.append(f"{source}: figures.noise.pad_class = {nz['pad_class']!r} is not allowed with figures.noise.sleeper = "
                   f"{nz['sleeper']!r}: Table G-3a has one track transfer for it; leave pad_class out (null).")
    if "fleet" in cfg and nz.get("axles_per_vehicle") is not None:  # issue 56: a fleet's classes take each vehicle's axles
        out.append(f"{source}: figures.noise.axles_per_vehicle = {nz['axles_per_vehicle']!r} is not used by a fleet: each vehicle's "
                   "axles in its noise are its positions (fleet.vehicles[*].positions); leave it out.")
    if "fleet" in cfg:
        out += _fleet_checks(cfg["fleet"], source)
    return out


def _sum_problem(key: str, values, source: str) -> list[str]:
    """Weights that do not sum to 1 (rail.fleet.SUM_TOLERANCE)."""
    from ..fleet import SUM_TOLERANCE

    total = float(np.sum(values))
    if abs(total - 1) <= SUM_TOLERANCE:
        return []
    return [f"{source}: {key} = {_short(list(values))} sums to {total:.9g}: it must sum to 1 (each value in [0, 1], the sum "
            f"within {SUM_TOLERANCE:g} of 1)."]


def _fleet_checks(fleet: dict, source: str) -> list[str]:
    """The fleet's constraints between keys (docs/traffic.md): names of one printable line, one creepage per axle,
    no two axles at one position, distinct names, shares and speed weights summing to 1, one form of speed distribution
    with its parameters, every speed class > 0."""
    from ..fleet import speed_classes

    out = []
    vehicles = fleet["vehicles"]
    for i, v in enumerate(vehicles):
        key = f"fleet.vehicles[{i}] ({v['name']})"
        if not str(v["name"]).isprintable():  # a line break or a control character would split or garble every line naming it
            out.append(f"{source}: fleet.vehicles[{i}].name = {v['name']!r} is not allowed: a vehicle type's name must be one "
                       "line of printable characters.")
            key = f"fleet.vehicles[{i}]"
        if len(v["creepage"]) != len(v["positions"]):
            out.append(f"{source}: {key}.creepage has {len(v['creepage'])} values: it needs one per axle, "
                       f"{key}.positions has {len(v['positions'])}.")
        if len(set(v["positions"])) != len(v["positions"]):
            out.append(f"{source}: {key}.positions = {_short(v['positions'])} m is not allowed: two axles at one position.")
    out += _fleet_wheelset_checks(fleet, source)
    names = [v["name"] for v in vehicles]
    if len(set(names)) != len(names):
        out.append(f"{source}: fleet.vehicles names {names} are not all different: give each vehicle type its own name.")
    out += _sum_problem("fleet.vehicles[*].share", [v["share"] for v in vehicles], source)
    sp = fleet["speeds"]
    given, named = "values" in sp or "weights" in sp, "distribution" in sp
    need = {"normal": ("mean", "std", "classes"), "uniform": ("low", "high", "classes")}
    if given == named:
        out.append(f"{source}: fleet.speeds = {_short(sp)} is not allowed: give either values and weights, or distribution "
                   "(normal with mean, std and classes; uniform with low, high and classes).")
        return out
    if given:
        if not {"values", "weights"} <= set(sp):
            out.append(f"{source}: fleet.speeds needs both values (m/s) and weights (-), one weight per speed.")
            return out
        extra = sorted(set(sp) - {"values", "weights"})
        if extra:
            out.append(f"{source}: fleet.speeds.{extra[0]} is not allowed with fleet.speeds.values: it belongs to a distribution.")
        if len(sp["weights"]) != len(sp["values"]):
            out.append(f"{source}: fleet.speeds.weights has {len(sp['weights'])} values: it needs one per speed, "
                       f"fleet.speeds.values has {len(sp['values'])}.")
        out += _sum_problem("fleet.speeds.weights", sp["weights"], source)
    else:
        d = sp["distribution"]
        missing = [k for k in need[d] if k not in sp]
        extra = sorted(set(sp) - {"distribution", *need[d]})
        if missing:
            out.append(f"{source}: fleet.speeds.distribution = '{d}' needs fleet.speeds.{missing[0]} "
                       f"(a {d} distribution takes {', '.join(need[d])}).")
        if extra:
            out.append(f"{source}: fleet.speeds.{extra[0]} is not allowed with fleet.speeds.distribution = '{d}' "
                       f"(it takes {', '.join(need[d])}).")
        if d == "uniform" and not missing and not sp["low"] <= sp["high"]:
            out.append(f"{source}: fleet.speeds.low = {sp['low']!r} m/s is not allowed: it must be <= fleet.speeds.high = "
                       f"{sp['high']!r} m/s.")
    if not out:
        try:
            speed_classes(sp)
        except ValueError as e:
            out.append(f"{source}: {e}")
    return out


def _fleet_wheelset_checks(fleet: dict, source: str) -> list[str]:
    """The fleet's wheelsets between keys (docs/traffic.md): one per axle where a vehicle gives a list, every
    name defined in fleet.wheelsets, a motored wheelset with its motor, a trailer without one."""
    out = []
    named = fleet.get("wheelsets") or {}
    for name, ws in named.items():
        out += _drive_problems(ws, f"fleet.wheelsets.{name}", source)
    for i, v in enumerate(fleet["vehicles"]):
        given = v.get("wheelsets")
        if given is None:
            continue
        key = f"fleet.vehicles[{i}] ({v['name']}).wheelsets"
        if isinstance(given, list) and len(given) != len(v["positions"]):
            out.append(f"{source}: {key} has {len(given)} entries: it needs one per axle, fleet.vehicles[{i}] ({v['name']}).positions "
                       f"has {len(v['positions'])} (or give one name or wheelset for every axle).")
        for j, w in enumerate(given if isinstance(given, list) else [given]):
            where = f"{key}[{j}]" if isinstance(given, list) else key
            if isinstance(w, str) and w not in named:
                defined = f"the names defined there are {', '.join(named)}" if named else "the file defines none"
                out.append(f"{source}: {where} = {w!r} is not allowed: it must name a wheelset of fleet.wheelsets ({defined}), "
                           "or give the wheelset in place (a mapping with drive).")
            elif isinstance(w, dict):
                out += _drive_problems(w, where, source)
    return out


def _drive_problems(ws: dict, key: str, source: str) -> list[str]:
    """A motored wheelset needs motor_inertia > 0; a trailer has no drive (motor_inertia, coupling_stiffness not given)."""
    if ws["drive"] == "motored" and not ws.get("motor_inertia", 0) > 0:
        return [f"{source}: {key}.drive = 'motored' needs {key}.motor_inertia > 0 kg m^2 (the motor's and gear's inertia reflected "
                f"to the axle, now {ws.get('motor_inertia', 'not given')}); or make it drive: trailer."]
    if ws["drive"] == "trailer":
        drive = [k for k in ("motor_inertia", "coupling_stiffness") if k in ws and not (k == "motor_inertia" and ws[k] == 0)]
        if drive:
            return [f"{source}: {key}.{drive[0]} = {ws[drive[0]]!r} is not allowed with {key}.drive = 'trailer': a trailer has no "
                    "drive; leave it out, or make it drive: motored."]
    return []


def _non_finite(node, source: str, path: str = "") -> list[str]:
    """NaN and inf anywhere in the configuration (the schema's comparisons never reject NaN)."""
    out = []
    if isinstance(node, dict):
        for k, v in node.items():
            out += _non_finite(v, source, f"{path}.{k}" if path else str(k))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            out += _non_finite(v, source, f"{path}[{i}]")
    elif isinstance(node, float) and not np.isfinite(node):
        out.append(f"{source}: {path} = {node!r} is not allowed: it must be a finite number.")
    return out


_BOUNDS = ("minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum")


def _dotted(path) -> str:
    """A schema error's path as _non_finite writes it: keys dotted, list items [i]."""
    out = ""
    for p in path:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else str(p))
    return out


SCENARIO_SUFFIXES = (".yaml", ".yml")


def scenario_files(directory) -> dict:
    """{name: path} of the scenario and sweep files in ``directory`` (config/scenarios/): every
    <name>.yaml and <name>.yml, sorted by name. Two files that give one name (x.yaml and x.yml) are
    refused, naming both: neither may silently replace the other.

    Parameters
    ----------
    directory : str or Path
        The scenarios' folder (config/scenarios/); none: no files.

    Returns
    -------
    dict
        {name: Path}, by name.

    Raises
    ------
    ConfigError
        Two files giving one name, naming both.
    """
    directory = Path(directory)
    by_name = {}
    for path in sorted(directory.iterdir()) if directory.is_dir() else []:
        if path.suffix in SCENARIO_SUFFIXES and path.is_file():
            by_name.setdefault(path.stem, []).append(path)
    twice = [f"{' and '.join(map(str, paths))}: both give the scenario name '{name}'; keep one of them."
             for name, paths in by_name.items() if len(paths) > 1]
    if twice:
        raise ConfigError("invalid scenarios:\n  " + "\n  ".join(twice))
    return {name: paths[0] for name, paths in sorted(by_name.items())}


def check_scenario_names(files: dict, sweep_points: dict) -> None:
    """Refuse scenario names that would silently replace another scenario: 'default' is the configuration
    itself; '<study>-p<n>' names the points of sweep studies.

    Parameters
    ----------
    files : dict
        {name: path} of ``config/scenarios/*.yaml`` and ``*.yml`` (scenario_files) and of the cases of the
        study files.
    sweep_points : dict
        {point name: sweep file}.

    Returns
    -------
    None

    Raises
    ------
    ConfigError
        One line per name refused, naming its file.
    """
    import re

    out = []
    for name, path in files.items():
        if name in RESERVED_SCENARIO_NAMES:
            out.append(f"{path}: the scenario name '{name}' is reserved for config/config.yaml (and --configfile); rename the file.")
        elif re.fullmatch(r".+-p\d+", name):
            out.append(f"{path}: the scenario name '{name}' has the form <study>-p<n> reserved for the points of sweep studies; rename the file.")
    for name, sweep in sweep_points.items():
        if name in files:
            out.append(f"{files[name]}: the scenario name '{name}' is also a point of the sweep {sweep}; rename one of them.")
    if out:
        raise ConfigError("invalid scenarios:\n  " + "\n  ".join(out))


def configured_speeds(cfg: dict) -> list[float]:
    """Every train speed a configuration computes at (speeds and the figures' speeds), m/s.

    Parameters
    ----------
    cfg : dict
        A configuration (resolved, or as written).

    Returns
    -------
    list of float
        The speeds [m/s], each once, increasing.
    """
    f = cfg.get("figures", {})
    v = set(cfg.get("speeds", []))
    v |= set(f.get("fig22", {}).get("speeds", [])) | set(f.get("growth", {}).get("speeds", []))
    v |= {x for x in (f.get("fig08", {}).get("speed"), f.get("wear", {}).get("speed")) if x is not None}
    if "fleet" in cfg:  # the speed classes of the traffic (rail.fleet)
        from ..fleet import speed_classes

        v |= set(speed_classes(cfg["fleet"]["speeds"]).speeds)
    return sorted(float(x) for x in v)


def validate_config(cfg: dict, schema: dict, source: str = "config") -> dict:
    """Check ``cfg`` against ``schema``; raise ConfigError listing every problem, or return ``cfg``.

    Each line names the key (dotted path), the offending value with its unit, the valid range
    and ``source`` (the file the value came from).

    Parameters
    ----------
    cfg : dict
        A configuration (config/config.yaml merged with a scenario).
    schema : dict
        config/schema/config.schema.yaml.
    source : str
        The file the values come from (a scenario file), named in every message.

    Returns
    -------
    dict
        ``cfg`` itself (defaults are not written into it).

    Raises
    ------
    ConfigError
        Every problem, one line each.
    """
    validator = Draft202012Validator(schema)
    errors = sorted(validator.iter_errors(cfg), key=lambda e: list(map(str, e.absolute_path)))
    typed = {tuple(e.absolute_path) for e in errors if e.validator == "type"}
    # a value of the wrong type is one problem: its range or enum, which the schema checks too, is not said again
    errors = [e for e in errors if e.validator == "type" or tuple(e.absolute_path) not in typed]
    # NaN or inf: said once, with the valid range where the schema states one (its range error not said again)
    ranged = {_dotted(e.absolute_path): e.schema for e in errors
              if isinstance(e.schema, dict) and e.validator in _BOUNDS}
    non_finite = []
    for m in _non_finite(cfg, source):
        key = m[len(source) + 2:].split(" = ", 1)[0]
        if key in ranged:
            unit = ranged[key].get("unit", "")
            unit = f" {unit}" if unit and unit != "-" else ""
            m = f"{m[:-1]} (valid range {_range_text(ranged[key])}{unit})."
        non_finite.append(m)
    said = {m[len(source) + 2:].split(" = ", 1)[0] for m in non_finite}
    errors = [e for e in errors if _dotted(e.absolute_path) not in said]
    messages = non_finite + [_message(e, source) for e in errors]
    if not messages:
        messages = _cross_checks(cfg, source)
    if messages:
        raise ConfigError("invalid configuration:\n  " + "\n  ".join(messages))
    return cfg


FLEET_SPECTRUM_KEYS = ("bays", "shortest", "longest", "per_octave", "eps", "grid_phases")


def resolve(defaults: dict, schema: dict, scenario: dict | None = None, source: str = "config") -> dict:
    """Merge a scenario (only the keys that differ) onto the defaults and validate the result.

    Problems are reported against ``source``, the scenario file's name. With a fleet, the
    figures.rate_spectrum every door reads for the class spectra is the fleet's (fleet_spectrum).

    Parameters
    ----------
    defaults : dict
        The validated default configuration (config/config.yaml).
    schema : dict
        config/schema/config.schema.yaml.
    scenario : dict or None
        The scenario's own keys (only those that differ from the defaults).
    source : str
        The file the values come from (a scenario file), named in every message.

    Returns
    -------
    dict
        The resolved, validated configuration (a new mapping).

    Raises
    ------
    ConfigError
        Every problem, one line each, naming ``source``.
    """
    merged = deep_merge(defaults, scenario or {})
    cfg = validate_config(merged, schema, source)
    return fleet_spectrum(cfg, scenario or {}, schema, source) if cfg.get("fleet") is not None else cfg


def fleet_spectrum(cfg: dict, scenario: dict, schema: dict, source: str) -> dict:
    """A fleet's configuration with figures.rate_spectrum set to the class spectra's settings: the keys
    of fleet.spectrum as the file gives them, else the schema's defaults (sized for a 2-core, 8 GB
    machine, docs/traffic.md); figures.rate_spectrum.speeds is kept (a fleet does not use it), except with
    fleet.spectrum.band, which is resolved at the fleet's class speeds: they become its speeds.

    Parameters
    ----------
    cfg : dict
        The validated configuration, with a fleet.
    scenario : dict
        The scenario's own keys (before the merge): a figures.rate_spectrum key other than speeds is
        refused, since a fleet would not use it.
    schema : dict
    source : str
        The scenario file, named in the error.

    Returns
    -------
    dict
        A new configuration: ``cfg`` with the fleet's spectrum settings [m, -] in figures.rate_spectrum.

    Raises
    ------
    ConfigError
        One line naming the key and the fleet.spectrum key to set instead.
    """
    given = [k for k in ((scenario.get("figures") or {}).get("rate_spectrum") or {}) if k != "speeds"]
    if given:
        raise ConfigError(f"invalid configuration:\n  {source}: figures.rate_spectrum.{given[0]} is not used by a fleet: its class "
                          f"spectra take fleet.spectrum (docs/traffic.md); set fleet.spectrum.{given[0]} instead.")
    out = copy.deepcopy(cfg)
    out["figures"]["rate_spectrum"] = {**out["figures"]["rate_spectrum"],
                                       **{k: setting(out, f"fleet.spectrum.{k}", schema) for k in FLEET_SPECTRUM_KEYS}}
    band = (out["fleet"].get("spectrum") or {}).get("band")
    out["figures"]["rate_spectrum"].pop("band", None)  # the class spectra take fleet.spectrum's lines: its band or none
    if band:
        # resolved at every class's speed, so that every class takes the same lines (the fleet's sum is per line)
        from ..fleet import speed_classes

        at = band.get("speeds") or speed_classes(out["fleet"]["speeds"]).speeds  # fleet.spectrum.band.speeds, else the classes'
        out["figures"]["rate_spectrum"]["band"] = {k: float(band[k]) for k in ("low", "high", "spacing")}
        out["figures"]["rate_spectrum"]["speeds"] = [float(v) for v in at]
    return out


# What every scenario file starts from on top of config/config.yaml: config.yaml reproduces the report
# (its normal contact, eqs 22-24, and its wear under the wheel centre), a user's scenario gets the normal
# contact of the field's practice, which sees the roughness under the patch, the wear where that patch
# really is (docs/contact.md), and a growth-rate spectrum down to the
# shortest wavelength L / K with the band near the pinned-pinned frequency resolved (lines at most 15 Hz apart over
# 900-1,400 Hz at each of the spectrum's speeds, issue 54: the band that grows with the rail's flexibility is about
# 50 Hz wide); a file that sets a key keeps its own, and one that sets its spectrum's period (figures.rate_spectrum.bays,
# a track cell's) without a band keeps the log-spaced lines of that period (resolve_scenario_file).
# The one table of defaults that differ by design: every other default is config.yaml's value or, for an optional key,
# the schema's (setting).
SCENARIO_FILE_DEFAULTS = {"contact": {"normal": "nonhertzian", "wear_path": "patch"},
                          "figures": {"rate_spectrum": {"shortest": 0.0, "band": {"low": 900.0, "high": 1400.0, "spacing": 15.0}}}}


# The full physics a scenario file starts from on top of SCENARIO_FILE_DEFAULTS (issue 55): the rail's longitudinal
# flexibility (the head's e psi: without it nothing grows by feedback at any speed or pad, docs/growth-spectrum.md) and,
# for one train, a torsional wheelset, motored where the train's creepage drives (contact.creepage < 0, eq 25: the
# traction comes from a motor through its coupling, so the motor's inertia is in the slip) and a trailer otherwise
# (braked or rolling: no motor). The values are docs/dynamic-creepage.md's "Parameters" (the dynspeed_* studies'):
# J_w 50 kg m^2, J_c 20 kg m^2, k_a 5.5 MN m/rad, the motor 288 kg m^2 and its coupling 3.6 MN m/rad at the axle.
# A fleet takes its vehicles' own wheelsets (fleet.wheelsets; without them the fixed creepage of each axle). A file
# that sets wheelset or rail_flexibility keeps its own; config.yaml keeps the report's model, and the study files'
# cases keep what their files say (physics=False).
SCENARIO_FILE_RAIL = {"rail_flexibility": {"model": "rod_and_bending"}}
TRAILER_WHEELSET = {"model": "torsional", "other_wheel": "in_phase", "wheel_inertia": 50.0, "centre_inertia": 20.0,
                    "axle_stiffness": 5.5e6, "motor_inertia": 0.0, "damping": 0.02}
MOTORED_WHEELSET = {**TRAILER_WHEELSET, "motor_inertia": 288.0, "coupling_stiffness": 3.6e6}


def scenario_file_physics(defaults: dict, scenario: dict | None) -> dict:
    """The model a scenario file starts from beyond SCENARIO_FILE_DEFAULTS (the comment above it): the rail's
    flexibility and, for one train, the wheelset its creepage calls for; only the sections the file does not set.

    Parameters
    ----------
    defaults : dict
        The validated default configuration (config/config.yaml).
    scenario : dict or None
        The file's own keys.

    Returns
    -------
    dict
        The sections to start from (rail_flexibility, wheelset).
    """
    own = scenario or {}
    out = {} if "rail_flexibility" in own else dict(SCENARIO_FILE_RAIL)
    if "wheelset" not in own and "fleet" not in own:
        creepage = ((own.get("contact") or {}).get("creepage", defaults["contact"]["creepage"]))
        try:
            driven = float(creepage) < 0
        except (TypeError, ValueError):  # a wrong value: the schema names it
            driven = False
        out["wheelset"] = dict(MOTORED_WHEELSET if driven else TRAILER_WHEELSET)
    return out


def resolve_scenario_file(defaults: dict, schema: dict, scenario: dict | None, source: str, physics: bool = True) -> dict:
    """A scenario file's resolved configuration: config.yaml, then SCENARIO_FILE_DEFAULTS, then the
    file's keys, validated (problems reported against ``source``). The workflow, the command line and
    the API all resolve scenario files here.

    Parameters
    ----------
    defaults : dict
        The validated default configuration (config/config.yaml).
    schema : dict
        config/schema/config.schema.yaml.
    scenario : dict or None
        The scenario's own keys (only those that differ from the defaults).
    source : str
        The file the values come from (a scenario file), named in every message.
    physics : bool
        Start from the full physics too (scenario_file_physics: a file of config/scenarios/); False for a study
        file's case, which keeps what its file says.

    Returns
    -------
    dict
        The resolved, validated configuration.

    Raises
    ------
    ConfigError
        Every problem, one line each, naming ``source``.
    """
    own = ((scenario or {}).get("figures") or {}).get("rate_spectrum") or {}
    start = deep_merge(defaults, SCENARIO_FILE_DEFAULTS)
    if physics:
        start = deep_merge(start, scenario_file_physics(defaults, scenario))
    if "bays" in own and "band" not in own:  # its own period: its own lines (a cell's, or the 2-bay surveys')
        start["figures"]["rate_spectrum"]["band"] = None
    return resolve(start, schema, scenario, source)


def _set_dotted(d: dict, dotted: str, value) -> dict:
    out = copy.deepcopy(d)
    node = out
    keys = dotted.split(".")
    for k in keys[:-1]:
        node = node.setdefault(k, {})
    node[keys[-1]] = value
    return out


def expand_sweep(defaults: dict, schema: dict, scenario: dict, source: str, physics: bool = True):
    """Expand a scenario with a ``sweep:`` mapping (dotted config key or ``speed`` -> list of values)
    into its grid points.

    Returns (keys, values, points) with points a list of (index tuple, assignment dict, resolved
    config). Every point is validated like a scenario; an error names the file, the point and the key.

    Parameters
    ----------
    defaults : dict
        The validated default configuration (config/config.yaml).
    schema : dict
        config/schema/config.schema.yaml.
    scenario : dict
        The sweep file's keys: ``sweep`` ({dotted key or 'speed': [values]}), optionally confirm_large_sweep, and
        the keys every point shares.
    source : str
        The file the values come from (a scenario file), named in every message.
    physics : bool
        Each point starts from the full physics of a scenario file (resolve_scenario_file); False for a study
        file's sweep case.

    Returns
    -------
    tuple
        (keys, values, points): the swept keys, their values, and per grid point (in C order) its index
        tuple, its assignment {key: value} (a speed in m/s) and its resolved configuration.

    Raises
    ------
    ConfigError
        A sweep that is not a mapping of non-empty lists, too many points without confirm_large_sweep, or a
        point that is not valid (naming the file, the point and the key).
    """
    sweep = scenario.get("sweep")
    if not isinstance(sweep, dict) or not sweep:
        raise ConfigError(f"{source}: sweep must map config keys (dotted, or 'speed') to lists of values.")
    confirmed = scenario.get("confirm_large_sweep", False) is True
    base = {k: v for k, v in scenario.items() if k not in ("sweep", "confirm_large_sweep")}
    keys = list(sweep)
    values = []
    for k in keys:
        v = sweep[k]
        if not isinstance(v, list) or not v:
            raise ConfigError(f"{source}: sweep.{k} = {v!r} is not allowed: it must be a non-empty list of values.")
        values.append(v)
    n = int(np.prod([len(v) for v in values]))
    if n > LARGE_SWEEP and not confirmed:
        raise ConfigError(
            f"{source}: the sweep has {n} points (one growth run each, and their receptance tables); above "
            f"{LARGE_SWEEP} points it runs only with 'confirm_large_sweep: true' at the top of the file."
        )
    points = []
    for index in np.ndindex(*[len(v) for v in values]):
        assignment = {k: values[i][j] for i, (k, j) in enumerate(zip(keys, index))}
        override = base
        for k, v in assignment.items():
            override = _set_dotted(override, "speeds", [v]) if k == "speed" else _set_dotted(override, k, v)
        label = ", ".join(f"{k} = {v}" for k, v in assignment.items())
        cfg = resolve_scenario_file(defaults, schema, override, source=f"{source} (sweep point {label})", physics=physics)
        points.append((index, assignment, cfg))
    return keys, values, points


def _schema_node(schema: dict, key: str) -> dict:
    """The schema's node of a dotted configuration key (a shared $defs definition merged in)."""
    node = schema
    for part in key.split("."):
        props = node.get("properties", {})
        if part not in props:
            raise KeyError(f"{key}: not a key of config/schema/config.schema.yaml")
        node = props[part]
    if "$ref" in node:  # a shared definition: its own keys, then the definition's
        node = {**schema["$defs"][node["$ref"].split("/")[-1]], **{k: v for k, v in node.items() if k != "$ref"}}
    return node


def schema_unit(schema: dict, key: str) -> str:
    """The unit the schema states for a configuration key, as result files write it: "-" (dimensionless)
    becomes "1" (CF); 'speed' (a sweep over the train speed) is the unit of speeds' items.

    Parameters
    ----------
    schema : dict
        config/schema/config.schema.yaml.
    key : str
        A dotted key ('track.pad.stiffness') or 'speed'.

    Returns
    -------
    str
        e.g. 'N/m', 'm/s', '1'.

    Raises
    ------
    KeyError
        If the schema has no such key, or states no unit for it.
    """
    node = schema["properties"]["speeds"]["items"] if key == "speed" else _schema_node(schema, key)
    if "unit" not in node:
        raise KeyError(f"{key}: config/schema/config.schema.yaml states no unit for it")
    return "1" if node["unit"] == "-" else str(node["unit"])


# The schema beside the package (the project folder holds rail/ and config/): the one home of the
# defaults of optional keys, read by ``setting``. rail.provenance hashes these defaults into the code
# hash of every script that imports this module, so that a changed default reruns what it changes.
SCHEMA_FILE = Path(__file__).resolve().parents[2] / "config" / "schema" / "config.schema.yaml"


@functools.lru_cache(maxsize=1)
def project_schema() -> dict:
    """config/schema/config.schema.yaml of the project folder holding this package (read once per process).

    Returns
    -------
    dict
        The schema (one cached object: not to be changed).
    """
    return load_yaml(SCHEMA_FILE)


def schema_default(schema: dict, key: str):
    """The default the schema states (``default:``) for an optional configuration key.

    Parameters
    ----------
    schema : dict
        config/schema/config.schema.yaml.
    key : str
        A dotted key ('contact.friction_decay').

    Returns
    -------
    object
        The default, as the YAML states it.

    Raises
    ------
    KeyError
        If the schema has no such key, or states no default for it (a key config/config.yaml sets,
        whose default is its value there).
    """
    node = _schema_node(schema, key)
    if "default" not in node:
        raise KeyError(f"{key}: config/schema/config.schema.yaml states no default for it")
    return node["default"]


def setting(cfg: dict, key: str, schema: dict | None = None):
    """The value of a dotted key in a resolved configuration, or the schema's default where the key
    is optional and absent (a key config/config.yaml sets is always present).

    Parameters
    ----------
    cfg : dict
        A resolved configuration (resolve, resolve_scenario_file), or the part of it a job reads.
    key : str
        A dotted key ('wheelset.other_wheel').
    schema : dict, optional
        The schema; by default the project's (project_schema).

    Returns
    -------
    object
        ``cfg``'s value, else the schema's default.

    Raises
    ------
    KeyError
        If the key is absent and the schema states no default for it.
    """
    node = cfg
    for part in key.split("."):
        if not isinstance(node, dict) or part not in node:
            return schema_default(project_schema() if schema is None else schema, key)
        node = node[part]
    return node
