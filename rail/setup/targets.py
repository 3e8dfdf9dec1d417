"""What the workflow's targets are named by and what each job is handed (split from rail.setup.plan,
issue 44; every name here is importable from rail.setup.plan as before).

- File-name labels, one way each: a speed (``speed_label``), a fleet class's speed, exact
  (``fleet_speed_label``), a wear excitation frequency and a closure value. A label becomes a value
  again only in rail.setup.plan.Plan (``target_speed``), checked like a configured value.
- The configuration parts a job is handed as ``params.cfg`` (``config_part`` over the key tuples
  below, ``physics_part``, ``track_part``): params are a rerun trigger, and every result records
  the configuration it read. Each is cut from a configuration as the physics reads it
  (``read_part``: an optional key at its schema default, or one the chosen models do not read, is
  left out), so that writing such a key reruns nothing (issue 57, item 5).
- The fixed sets the target lists are built from (report figures by section, the irregular-track
  study's speed, the characterisation results, report suffixes, job priorities; the studies' cases are
  those of their study files, rail.setup.study_files) and the
  small frozen records a Plan holds (SweepPoint, Sweep, Table).

Conventions
-----------
Speeds in m/s, frequencies in Hz; labels are plain text without exponents ('40', '37.5', '533').
"""

from __future__ import annotations

import copy
from collections.abc import Mapping
from dataclasses import dataclass, field

from ..creepage.choices import wheelset_model
from .build import OPTIONAL_KEYS, PASSAGE_KEYS, wheel_source_settings
from .config import ConfigError, deep_merge, schema_default, setting

__all__ = ["known_value", "speed_label", "fleet_speed_label", "wear_frequency_label", "closure_label", "config_part", "physics_part", "track_part",
           "read_part", "case_base", "RAIL_HEAD_KEYS", "KnownNames",
           "SweepPoint", "Sweep", "Table", "HALFSPACE_KEYS", "FORCE_KEYS", "WEAR_CASE_KEYS", "GROWTH_FIGURE_KEYS", "HALFSPACE_FIGURES",
           "FORCE_FIGURES", "WEAR_FIGURES", "GROWTH_FIGURES", "IRREGULAR_SPEED",
           "CHARACTERISATION", "REPORT_SUFFIXES", "PRIORITY_KERNELS", "PRIORITY_TABLES", "DEFAULT_SOURCE"]

DEFAULT_SOURCE = "configuration (config/config.yaml and --config/--configfile)"

# What each report figure reads of the configuration (its rule's params.cfg). A figure drawn from
# another job's result carries that job's keys too, so that it records all it was computed from.
HALFSPACE_KEYS = ("material", "contact.hertz_stiffness", "numerics.halfspace", "figures.halfspace")
FORCE_KEYS = tuple(k for k in PASSAGE_KEYS if k not in ("wear", "wheelset", "rail_flexibility"))
  # the forces of one passage (rail.chain.solve_forces)
WEAR_CASE_KEYS = PASSAGE_KEYS + ("figures.wear.speed", "figures.wear.amplitude")
GROWTH_FIGURE_KEYS = ("figures.growth", "figures.wear.spectrum_max_wavenumber")

# Report figures produced so far, by section of the report.
HALFSPACE_FIGURES = ["02", "03", "04", "05", "06"]
FORCE_FIGURES = ["08", "22"]
WEAR_FIGURES = [f"{n:02d}" for n in range(9, 20)]
GROWTH_FIGURES = ["20", "21", "23", "24", "25", "26", "27"]

# The speed [m/s] of the irregular-track study (named target irregular_track: its cases are those of
# config/studies/irregular_track.yaml, read by rail.setup.study_files, each at this speed).
IRREGULAR_SPEED = "40"
# The three characterisation results of a track: data results/.../<name>.nc, figure <name>.png.
CHARACTERISATION = ["track_receptance", "moving_receptance", "track_decay_rate"]
# Suffixes of the outputs a report shows (figures, CSV exports, markdown and HTML tables).
REPORT_SUFFIXES = (".png", ".csv", ".md", ".html")
# Job priorities: the contact march's compile first, then the tables (the most wheels first), then
# the growth runs, longest first.
PRIORITY_KERNELS = 100
PRIORITY_TABLES = 50


def speed_label(v) -> str:
    """Speed in a file name: 40.0 -> '40', 37.5 -> '37.5'.

    Parameters
    ----------
    v : float
        Speed [m/s].

    Returns
    -------
    str
    """
    return f"{float(v):g}"


def fleet_speed_label(v) -> str:
    """A fleet class's speed in a file name, exact: float(label) == v (40.0 -> '40', 33.6 -> '33.6').
    The classes of a distribution need not be round numbers, and a table must be at the class's speed.

    Parameters
    ----------
    v : float
        Speed [m/s].

    Returns
    -------
    str
    """
    text = repr(float(v))
    return text[:-2] if text.endswith(".0") else text


def wear_frequency_label(f) -> str:
    """Excitation frequency in a file name: 533.333 -> '533'.

    Parameters
    ----------
    f : float
        Excitation frequency [Hz].

    Returns
    -------
    str
    """
    return f"{float(f):.0f}"


def closure_label(s) -> str:
    """Closure value in a file name: 0.01 -> '0.01'.

    Parameters
    ----------
    s : float
        Closure value [-] (contact.closure_scale).

    Returns
    -------
    str
    """
    return f"{float(s):g}"


def config_part(keys, cfg: dict) -> dict:
    """The part of a configuration under the dotted keys, nested as there: what a job is handed as
    params.cfg (params are a rerun trigger, and each result records the configuration it read). A key of
    rail.setup.build.OPTIONAL_KEYS (the wheelset) is left out where the configuration does not have it.

    Parameters
    ----------
    keys : iterable of str
        Dotted keys ('track', 'numerics.track', 'figures.wear.speed').
    cfg : dict
        A configuration as the physics reads it (read_part).

    Returns
    -------
    dict
        A new nested mapping of those keys' values.
    """
    out = {}
    for key in keys:
        if key in OPTIONAL_KEYS and key not in cfg:
            continue
        *parents, leaf = key.split(".")
        src, dst = cfg, out
        for p in parents:
            src, dst = src[p], dst.setdefault(p, {})
        dst[leaf] = src[leaf]
    return out


def physics_part(cfg: dict) -> dict:
    """A configuration without the figure settings, site measurements and half-space quadrature (which
    no growth computation reads: the contact damping has its own, Fig. 6).

    Parameters
    ----------
    cfg : dict
        A configuration as the physics reads it (read_part).

    Returns
    -------
    dict
        A new mapping (the values shared with ``cfg``).
    """
    out = {k: v for k, v in cfg.items() if k not in ("figures", "measured", "numerics")}
    return {**out, "numerics": {k: v for k, v in cfg["numerics"].items() if k != "halfspace"}}


def track_part(cfg: dict) -> dict:
    """The track and track numerics of a configuration: all a receptance table depends on (the keys
    of the rail head's longitudinal flexibility, RAIL_HEAD_KEYS, left out: no table reads them).

    Parameters
    ----------
    cfg : dict
        A configuration as the physics reads it (read_part).

    Returns
    -------
    dict
        {"track": ..., "numerics": {"track": ...}}, a new mapping.
    """
    track = copy.deepcopy(cfg["track"])
    for key in RAIL_HEAD_KEYS:
        _drop(track, key.split(".")[1:])
    return {"track": track, "numerics": {"track": cfg["numerics"]["track"]}}


# What only the rail head's longitudinal flexibility reads (rail.setup.build._rail_flexibility): unread
# without it (rail_flexibility absent or model none), and never read by a receptance table.
RAIL_HEAD_KEYS = ("track.pad.longitudinal_stiffness", "track.pad.longitudinal_loss_factor",
                  "track.pad.longitudinal_viscous_damping", "track.rail.head_height")


def _drop(node: dict, parts: list) -> None:
    """Remove the key at path ``parts`` from the nested mapping ``node``, if it is there."""
    for p in parts[:-1]:
        node = node.get(p)
        if not isinstance(node, dict):
            return
    node.pop(parts[-1], None)


def _same_value(value, default) -> bool:
    """Whether a configuration value is its schema default (1.0 is 1; True is not 1)."""
    if isinstance(value, bool) or isinstance(default, bool):
        return type(value) is type(default) and value == default
    if isinstance(value, (int, float)) and isinstance(default, (int, float)):
        return float(value) == float(default)
    return value == default


def _without_defaults(node: dict, schema_node: dict, defs: dict) -> dict:
    """``node`` without the optional keys (those with a schema ``default``) at their default, at any
    depth; a mapping that this leaves empty is left out too (absent: every key at its default)."""
    out = {}
    props = schema_node.get("properties", {})
    for key, value in node.items():
        sub = props.get(key, {})
        if "$ref" in sub:
            sub = {**defs[sub["$ref"].split("/")[-1]], **sub}
        if "default" in sub and _same_value(value, sub["default"]):
            continue
        if isinstance(value, dict) and value:
            value = _without_defaults(value, sub, defs)
            if not value:
                continue
        out[key] = value
    return out


def read_part(cfg: dict, schema: dict, base: bool = False) -> dict:
    """A resolved configuration as the physics reads it: what a job's params (its rerun trigger) and
    a receptance table's name are made from, so that a key nothing reads, or one written at its
    default, reruns nothing (issue 57, item 5).

    Left out: every optional key (one with a schema ``default``, read through
    rail.setup.config.setting) at its default, and a section that leaves empty
    (``rail_flexibility: {model: none}``); a wheelset of model fixed_creepage (the report's rigid wheel:
    rail.setup.build reads nothing of it); and, unless ``base``, the keys the chosen models leave
    unread: RAIL_HEAD_KEYS without the rail's flexibility, and the wheelset keys its model does not
    read (the rigid wheelset's stiffnesses and damping; a trailer's coupling), and wheel_source without a source
    (roughness none). Every key that a
    rail.setup.build object holds is kept (tests/test_rerun.py checks both directions over every
    optional key of the schema). The order of the keys is kept.

    Parameters
    ----------
    cfg : dict
        A resolved, validated configuration (rail.setup.config.resolve).
    schema : dict
        config/schema/config.schema.yaml.
    base : bool
        The configuration is a base that cases are merged onto (the stability suite's): keep every key a
        case could switch on (only the defaults, and a wheelset that is nothing but fixed_creepage, go).

    Returns
    -------
    dict
        A new mapping; ``cfg`` is not changed.
    """
    out = _without_defaults(cfg, schema, schema.get("$defs", {}))
    ws = out.get("wheelset")
    # a wheelset at the schema's default model (fixed_creepage, left out above) is read by nothing
    if ws is not None and not wheelset_model(setting(out, "wheelset.model", schema)).modelled and (not base or set(ws) <= {"model"}):
        del out["wheelset"]
    if base:
        return out
    out = copy.deepcopy(out)
    if wheel_source_settings(out) is None:  # no source (a fleet: no vehicle's wheels rough): its other keys unread
        out.pop("wheel_source", None)
        for v in (out.get("fleet") or {}).get("vehicles", []):
            v.pop("wheel_source", None)
    if "rail_flexibility" not in out:
        for key in RAIL_HEAD_KEYS:
            _drop(out, key.split("."))
    ws = out.get("wheelset")
    if ws is not None:
        motor = float(ws.get("motor_inertia", schema_default(schema, "wheelset.motor_inertia")))
        for key in wheelset_model(setting(out, "wheelset.model", schema)).unread_keys(motor > 0):
            ws.pop(key, None)
    return out


@dataclass(frozen=True)
class SweepPoint:
    """One grid point of a sweep study: its scenario name, grid index and speed [m/s]."""

    name: str
    index: tuple
    speed: float


@dataclass(frozen=True)
class Sweep:
    """A sweep study (a scenario file with ``sweep:``): swept keys, their values, the points in grid order."""

    keys: list
    values: list
    points: tuple
    units: list  # of each key, as the schema states it (rail.setup.config.schema_unit)

    def values_of(self, key: str) -> list:
        """The swept values of one key."""
        return self.values[self.keys.index(key)]


@dataclass(frozen=True)
class Table:
    """A shared receptance table (issue 36), named by its content: the first scenario holding it, its
    wheel offsets [m] and every scenario it serves."""

    scenario: str
    offsets: list
    scenarios: list = field(default_factory=list)


def case_base(base: dict, overrides: dict, schema: dict) -> dict:
    """What a case (its overrides merged onto ``base``, as the stability suite's) reads of the base: the
    keys of ``base`` that read_part of the merged configuration keeps, so that a base key the case
    leaves unread reruns nothing. The base as given where the merge is no configuration read_part can
    cut (a case that is refused: its error is its outcome).

    Parameters
    ----------
    base : dict
        The configuration the cases are merged onto (read_part with base=True).
    overrides : dict
        The case's keys.
    schema : dict

    Returns
    -------
    dict
    """
    try:
        read = read_part(deep_merge(base, overrides), schema)
    except (KeyError, TypeError, AttributeError, ValueError):
        return base
    return _restrict(base, read)


def _restrict(node: dict, keep: dict) -> dict:
    """``node`` with only the keys that ``keep`` holds, at any depth."""
    return {k: _restrict(v, keep[k]) if isinstance(v, dict) and isinstance(keep[k], dict) else v
            for k, v in node.items() if k in keep}


class KnownNames(Mapping):
    """A read-only mapping of scenario names in which looking up a scenario left out of the run (its
    file is not valid: Plan.left_out) raises the ConfigError that names the file and its problem,
    rather than a KeyError; ``in`` and iteration see only the scenarios that run."""

    def __init__(self, data: dict, left_out):
        self._data, self._left_out = dict(data), left_out

    def __getitem__(self, name):
        if name in self._data:
            return self._data[name]
        why = self._left_out(name) if isinstance(name, str) else None
        if why:
            raise ConfigError(why)
        raise KeyError(name)

    def __contains__(self, name):
        return name in self._data

    def __iter__(self):
        return iter(self._data)

    def __len__(self):
        return len(self._data)

    def __repr__(self):
        return f"KnownNames({self._data!r})"


def known_value(known: dict, label: str, what: str, key: str):
    """The value a target's file-name label names, or one line saying which labels exist.

    Parameters
    ----------
    known : dict
        {label: value} of the configured values.
    label : str
        The label a target names.
    what : str
        What the label is, for the message (for example "wear frequency f").
    key : str
        The configuration key that lists the values.

    Returns
    -------
    The value the label names.
    """
    if label not in known:
        raise ConfigError(f"target names the {what}{label}, which is not configured: the labels are "
                          f"{', '.join(sorted(known))} ({key}).")
    return known[label]
