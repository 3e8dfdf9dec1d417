"""What the workflow's targets are named by and what each job is handed (split from rail.setup.plan,
issue 44; every name here is importable from rail.setup.plan as before).

- File-name labels, one way each: a speed (``speed_label``), a fleet class's speed, exact
  (``fleet_speed_label``), a wear excitation frequency and a closure value. A label becomes a value
  again only in rail.setup.plan.Plan (``target_speed``), checked like a configured value.
- The configuration parts a job is handed as ``params.cfg`` (``config_part`` over the key tuples
  below, ``physics_part``, ``track_part``): params are a rerun trigger, and every result records
  the configuration it read.
- The fixed sets the target lists are built from (report figures by section, the closure and
  irregular-track studies, the characterisation results, report suffixes, job priorities) and the
  small frozen records a Plan holds (SweepPoint, Sweep, Table).

Conventions
-----------
Speeds in m/s, frequencies in Hz; labels are plain text without exponents ('40', '37.5', '533').
"""

from __future__ import annotations

from dataclasses import dataclass, field

from .build import OPTIONAL_KEYS, PASSAGE_KEYS

__all__ = ["speed_label", "fleet_speed_label", "wear_frequency_label", "closure_label", "config_part", "physics_part", "track_part",
           "SweepPoint", "Sweep", "Table", "HALFSPACE_KEYS", "FORCE_KEYS", "WEAR_CASE_KEYS", "GROWTH_FIGURE_KEYS", "HALFSPACE_FIGURES",
           "FORCE_FIGURES", "WEAR_FIGURES", "GROWTH_FIGURES", "CLOSURE_STUDIES", "IRREGULAR_SPEED", "IRREGULAR_NAMES",
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

# Closure sensitivity study (named target closure_study): three sweep files over contact.closure_scale,
# single wheel at two speeds, softer railpad and four wheels.
CLOSURE_STUDIES = {"run": "closure", "soft": "closure_soft_pad", "four": "closure_class87"}
# Irregular track (issue 34): the cases config/scenarios/irregular_<kind>.yaml beside irregular_uniform.yaml.
IRREGULAR_SPEED = "40"
IRREGULAR_NAMES = ("irregular_voided", "irregular_spacing", "irregular_stiff_pad", "irregular_dampers")
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
    The classes of a distribution need not be round numbers, and a table must be at the class's speed."""
    text = repr(float(v))
    return text[:-2] if text.endswith(".0") else text


def wear_frequency_label(f) -> str:
    """Excitation frequency in a file name: 533.333 -> '533'."""
    return f"{float(f):.0f}"


def closure_label(s) -> str:
    """Closure value in a file name: 0.01 -> '0.01'."""
    return f"{float(s):g}"


def config_part(keys, cfg: dict) -> dict:
    """The part of a configuration under the dotted keys, nested as there: what a job is handed as
    params.cfg (params are a rerun trigger, and each result records the configuration it read). A key of
    rail.setup.build.OPTIONAL_KEYS (the wheelset) is left out where the configuration does not have it."""
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
    no growth computation reads: the contact damping has its own, Fig. 6)."""
    out = {k: v for k, v in cfg.items() if k not in ("figures", "measured", "numerics")}
    return {**out, "numerics": {k: v for k, v in cfg["numerics"].items() if k != "halfspace"}}


def track_part(cfg: dict) -> dict:
    """The track and track numerics of a configuration: all a receptance table depends on."""
    return {"track": cfg["track"], "numerics": {"track": cfg["numerics"]["track"]}}


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
