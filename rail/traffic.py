"""Traffic units: growth rates per 100,000 axle passages, per year and per million gross tonnes
(docs/exports.md).

Conventions
-----------
- The model counts wheel passages on one rail. A rail sees one wheel per axle, so a wheel passage
  is an *axle passage*; every rate in an export is per ``AXLES_PER_RATE`` = 100,000 axle passages.
- Per year: rate x axles_per_day x 365 / AXLES_PER_RATE (config key ``traffic.axles_per_day``).
- Per MGT (million gross tonnes): rate x (1e6 / axle load [t]) / AXLES_PER_RATE, the axle load
  2 x static wheel load / g (two wheels per axle, one on each rail; rail.fleet.GRAVITY), or under a
  fleet its traffic-weighted mean axle load (rail.fleet.Fleet.mean_axle_load).
- A level growth rate in dB of amplitude is DB_PER_NEPER = 20 log10(e) times the rate of
  ln(amplitude).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .fleet import GRAVITY
from .growth import DB_PER_NEPER

__all__ = ["AXLES_PER_RATE", "DB_PER_NEPER", "DAYS_PER_YEAR", "Traffic", "traffic_of_wheel_load", "traffic_of"]

AXLES_PER_RATE = 100000  # every growth rate is stated per this many axle (wheel) passages on the rail
DAYS_PER_YEAR = 365.0


@dataclass(frozen=True)
class Traffic:
    """The traffic over the rail, to turn rates per axle passage into rates per year and per MGT.

    axles_per_day : axle passages per day over the rail (config ``traffic.axles_per_day``) [1/day], > 0
    axle_load_t   : mean load of the axles that pass [t], > 0
    """

    axles_per_day: float
    axle_load_t: float

    def __post_init__(self):
        for name, v in (("traffic.axles_per_day", self.axles_per_day), ("axle load (t)", self.axle_load_t)):
            if not (np.isfinite(v) and v > 0):
                raise ValueError(f"{name} = {v!r} is not allowed: it must be a finite number > 0.")

    @property
    def axles_per_year(self) -> float:
        """axles_per_day x 365 [1/year]."""
        return self.axles_per_day * DAYS_PER_YEAR

    @property
    def mgt_per_year(self) -> float:
        """Million gross tonnes per year, axles_per_year x axle load / 1e6 [Mt/year]."""
        return self.axles_per_year * self.axle_load_t / 1e6

    @property
    def axles_per_mgt(self) -> float:
        """Axle passages per million gross tonnes, 1e6 / axle load [1/Mt]."""
        return 1e6 / self.axle_load_t

    def per_year(self, rate_per_1e5_axles):
        """A rate per 100,000 axle passages as a rate per year of the traffic (same level unit)."""
        return np.asarray(rate_per_1e5_axles, dtype=float) * self.axles_per_year / AXLES_PER_RATE

    def per_mgt(self, rate_per_1e5_axles):
        """A rate per 100,000 axle passages as a rate per million gross tonnes (same level unit)."""
        return np.asarray(rate_per_1e5_axles, dtype=float) * self.axles_per_mgt / AXLES_PER_RATE

    def years(self, axle_passages):
        """Axle passages as years of the traffic [year]."""
        return np.asarray(axle_passages, dtype=float) / self.axles_per_year

    def mgt(self, axle_passages):
        """Axle passages as million gross tonnes [Mt]."""
        return np.asarray(axle_passages, dtype=float) / self.axles_per_mgt

    def attributes(self) -> dict:
        """The traffic and its definitions, for a dataset's attributes and an export's header."""
        return {"axles_per_day": float(self.axles_per_day), "axle_load_t": float(self.axle_load_t),
                "axles_per_year": self.axles_per_year, "mgt_per_year": self.mgt_per_year,
                "traffic_definition": ("per year = per axle passage x axles_per_day x 365; per MGT = per axle passage x "
                                       "1e6 / axle_load_t; axle load = 2 x static wheel load / 9.80665 m/s^2 (or the fleet's "
                                       "traffic-weighted mean axle load)")}


def traffic_of_wheel_load(axles_per_day: float, static_wheel_load: float) -> Traffic:
    """The traffic of one train type: axle load 2 P / g [t] from the static wheel load P [N].

    Parameters
    ----------
    axles_per_day : float
        Axle passages per day over the rail [1/day].
    static_wheel_load : float
        Static wheel load P [N], > 0.

    Returns
    -------
    Traffic
    """
    if not (np.isfinite(static_wheel_load) and static_wheel_load > 0):
        raise ValueError(f"wheels.static_load = {static_wheel_load!r} is not allowed: it must be a finite number > 0 (N).")
    return Traffic(float(axles_per_day), 2 * float(static_wheel_load) / GRAVITY / 1000.0)


def traffic_of(scn) -> Traffic:
    """The traffic of a scenario (rail.scenario.Scenario): its ``axles_per_day`` [1/day] (config
    ``traffic.axles_per_day``) and the axle load of its train [t], 2 x ``wheels.static_load`` [N] / g.

    Parameters
    ----------
    scn : rail.scenario.Scenario

    Returns
    -------
    Traffic
    """
    if scn.axles_per_day is None:
        raise ValueError(f"scenario {scn.name!r} has no traffic (traffic.axles_per_day): no rates per year or MGT.")
    return traffic_of_wheel_load(scn.axles_per_day, scn.wheels.static_load)
