"""Configuration: merge a scenario onto the defaults and validate it with errors a user can act on.

The JSON schema (``config/schema/config.schema.yaml``) is the single statement of types,
units and valid ranges; this module turns a schema violation into one line per problem that
names the key, the value, the valid range and the file it came from.  It never reads a file
it is not handed a path to.
"""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np

import yaml
from jsonschema import Draft202012Validator

__all__ = ["ConfigError", "load_yaml", "deep_merge", "validate_config", "resolve", "expand_sweep"]


class ConfigError(ValueError):
    """A configuration value is missing, unknown, of the wrong type or out of range."""


def load_yaml(path) -> dict:
    """Read a YAML mapping; an empty file gives an empty dict."""
    path = Path(path)
    with path.open() as fh:
        data = yaml.safe_load(fh)
    if data is None:
        return {}
    if not isinstance(data, dict):
        raise ConfigError(f"{path}: the top level must be a mapping of keys, not {type(data).__name__}.")
    return data


def deep_merge(base: dict, override: dict) -> dict:
    """Return a copy of ``base`` with ``override`` merged in (nested mappings merge, the rest replaces)."""
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


def _message(error, source: str) -> str:
    key = ".".join(str(p) for p in error.absolute_path) or "(top level)"
    schema = error.schema if isinstance(error.schema, dict) else {}
    unit = schema.get("unit", "")
    unit_txt = f" {unit}" if unit and unit != "-" else ""
    kind = error.validator
    if kind in ("minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum"):
        return (
            f"{source}: {key} = {error.instance!r}{unit_txt} is not allowed: it must be "
            f"{_bound_text(kind, error.validator_value)}{unit_txt} (valid range {_range_text(schema)}{unit_txt})."
        )
    if kind == "additionalProperties":
        allowed = sorted(schema.get("properties", {}))
        unknown = sorted(set(error.instance) - set(allowed))
        prefix = f"{key}." if error.absolute_path else ""
        parts = [f"{prefix}{u} = {error.instance[u]!r}" for u in unknown]
        return (
            f"{source}: unknown key {', '.join(parts)}; the keys allowed under {key} are: "
            f"{', '.join(allowed)}."
        )
    if kind == "enum":
        return f"{source}: {key} = {error.instance!r} is not allowed: it must be one of {error.validator_value}."
    if kind == "type":
        hint = ""
        if isinstance(error.instance, str):
            try:
                float(error.instance)
                hint = f" (YAML reads {error.instance} as text: write the number with a dot and a signed exponent, e.g. 3.5e+8 or 3.5E+08)"
            except ValueError:
                pass
        return f"{source}: {key} = {error.instance!r} has the wrong type: it must be of type {error.validator_value}{hint}."
    if kind == "required":
        return f"{source}: {key} lacks a required key: {error.message}."
    return f"{source}: {key} = {error.instance!r}: {error.message}."


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
    return out


def configured_speeds(cfg: dict) -> list[float]:
    """Every train speed a configuration computes at (speeds and the figures' speeds), m/s."""
    f = cfg.get("figures", {})
    v = set(cfg.get("speeds", []))
    v |= set(f.get("fig22", {}).get("speeds", [])) | set(f.get("growth", {}).get("speeds", []))
    v |= {x for x in (f.get("fig08", {}).get("speed"), f.get("wear", {}).get("speed")) if x is not None}
    return sorted(float(x) for x in v)


def validate_config(cfg: dict, schema: dict, source: str = "config") -> dict:
    """Check ``cfg`` against ``schema``; raise ConfigError listing every problem, or return ``cfg``.

    Each line names the key (dotted path), the offending value with its unit, the valid range
    and ``source`` (the file the value came from).
    """
    validator = Draft202012Validator(schema)
    errors = sorted(validator.iter_errors(cfg), key=lambda e: list(map(str, e.absolute_path)))
    messages = [_message(e, source) for e in errors]
    if not messages:
        messages = _cross_checks(cfg, source)
    if messages:
        raise ConfigError("invalid configuration:\n  " + "\n  ".join(messages))
    return cfg


def resolve(defaults: dict, schema: dict, scenario: dict | None = None, source: str = "config") -> dict:
    """Merge a scenario (only the keys that differ) onto the defaults and validate the result.

    Problems are reported against ``source``, the scenario file's name.
    """
    merged = deep_merge(defaults, scenario or {})
    return validate_config(merged, schema, source)


def _set_dotted(d: dict, dotted: str, value) -> dict:
    out = copy.deepcopy(d)
    node = out
    keys = dotted.split(".")
    for k in keys[:-1]:
        node = node.setdefault(k, {})
    node[keys[-1]] = value
    return out


def expand_sweep(defaults: dict, schema: dict, scenario: dict, source: str):
    """Expand a scenario with a ``sweep:`` mapping (dotted config key or ``speed`` -> list of values)
    into its grid points.

    Returns (keys, values, points) with points a list of (index tuple, assignment dict, resolved
    config). Every point is validated like a scenario; an error names the file, the point and the key.
    """
    sweep = scenario.get("sweep")
    if not isinstance(sweep, dict) or not sweep:
        raise ConfigError(f"{source}: sweep must map config keys (dotted, or 'speed') to lists of values.")
    base = {k: v for k, v in scenario.items() if k != "sweep"}
    keys = list(sweep)
    values = []
    for k in keys:
        v = sweep[k]
        if not isinstance(v, list) or not v:
            raise ConfigError(f"{source}: sweep.{k} = {v!r} is not allowed: it must be a non-empty list of values.")
        values.append(v)
    points = []
    for index in np.ndindex(*[len(v) for v in values]):
        assignment = {k: values[i][j] for i, (k, j) in enumerate(zip(keys, index))}
        override = base
        for k, v in assignment.items():
            override = _set_dotted(override, "speeds", [v]) if k == "speed" else _set_dotted(override, k, v)
        label = ", ".join(f"{k} = {v}" for k, v in assignment.items())
        cfg = resolve(defaults, schema, override, source=f"{source} (sweep point {label})")
        points.append((index, assignment, cfg))
    return keys, values, points
