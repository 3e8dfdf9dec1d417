"""Traffic as a fleet: vehicle types at a spread of speeds, each (vehicle, speed) pair a class with
a weight (docs/traffic.md).

One *fleet passage* is one train drawn at random from the traffic: vehicle type v with probability
share_v, at speed class s with probability weight_s, independently. Its expected wear is

    dZ = sum_c w_c dZ_c,      w_c = share_v weight_s,

with dZ_c the wear of one passage of the train of class c (rail.chain.train_wear), so the class
weights are the traffic shares. Growth is linear in the wear per update, so a growth update that
applies h fleet passages applies h w_c passages of every class (rail.chain.fleet_wear).

Conventions
-----------
- Each wheel position of a vehicle is one axle: the model is one rail, and a rail sees one wheel
  per axle. ``creepage`` holds one signed value per axle (gamma_1 of eq 25: negative driven,
  positive braked, about zero trailing).
- Axle load = 2 x static wheel load / g (two wheels per axle, one on each rail), g = 9.80665 m/s^2.
- Speeds from a named distribution are discretised into equal-probability classes at their
  conditional means (speed_classes): each class carries weight 1 / n exactly, the discrete mean
  equals the distribution's mean for every n, and a normal distribution needs no truncation range.
  For a uniform distribution the rule coincides with equal-width classes at their centres.
- A vehicle's linearised Hertz spring scales with its load as k_H (P / P_0)^(1/3) (Hertz:
  k_H = dP/d delta is proportional to P^(1/3)), P_0 the load ``contact.hertz_stiffness`` is given
  for (``wheels.static_load``); the half-space loss slope of the spring is proportional to k_H
  (rail.halfspace.contact_loss_factor), a constant loss factor is kept.
- A vehicle that names the wheelset of each axle (``fleet.vehicles[*].wheelsets``: motored or trailer,
  a rail.creepage.wheelset.Wheelset each) runs each axle's contact with that wheelset's modes
  (rail.interaction.Wheels.wheelsets, read by rail.chain.wheel_material); a vehicle that names none
  runs the scenario's (the ``wheelset`` section: every axle the same, or the report's fixed creepage
  without it). The other wheel's choice (``wheelset.other_wheel``) and the rail's flexibility are the
  scenario's for every vehicle. A wheelset defined once and named by several axles or vehicles is one
  object, and its modes are computed once (Fleet.classes).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from .interaction import ContactSpring, Wheels
from .scenario import Scenario
from .creepage.wheelset import wheelset_modes

__all__ = ["GRAVITY", "SUM_TOLERANCE", "Vehicle", "SpeedClasses", "speed_classes", "normal_classes", "uniform_classes",
           "FleetClass", "Fleet", "vehicle_spring"]

GRAVITY = 9.80665  # m/s^2, standard gravity (axle load in tonnes)
SUM_TOLERANCE = 1e-6  # |sum - 1| accepted for shares and speed weights (YAML decimals such as 0.1 + 0.2 + 0.7)


def _unit_sum(name: str, values) -> None:
    """Refuse weights that are not finite, negative, or do not sum to 1 (to SUM_TOLERANCE)."""
    v = np.asarray(values, dtype=float)
    if v.size == 0:
        raise ValueError(f"{name} = [] is not allowed: give at least one value.")
    for i, x in enumerate(v):
        if not np.isfinite(x) or x < 0:
            raise ValueError(f"{name}[{i}] = {x!r} is not allowed: it must be a finite number in [0, 1].")
    if abs(v.sum() - 1) > SUM_TOLERANCE:
        raise ValueError(f"{name} = {[float(x) for x in v]} sums to {v.sum():.9g}: it must sum to 1 "
                         f"(within {SUM_TOLERANCE:g}).")


@dataclass(frozen=True)
class Vehicle:
    """One vehicle type of the traffic (config key ``fleet.vehicles``).

    name          : label
    positions     : m, position of each axle along the vehicle (one wheel on the modelled rail each)
    static_load   : N, > 0, static wheel load (half the axle load)
    unsprung_mass : kg, > 0, unsprung mass per wheel
    creepage      : -, one signed creepage per axle (eq 25; < 0 driven, > 0 braked, 0 trailing)
    share         : -, in [0, 1], the vehicle's share of the trains
    wheelsets     : one rail.creepage.wheelset.Wheelset per axle (motored or trailer), or None (every axle the scenario's)
    wheelset_names: one name per axle (a key of ``fleet.wheelsets``, or '' given in place), None with no wheelsets

    Without wheelsets every axle runs the scenario's ``wheelset`` section, or the report's fixed creepage.
    """

    name: str
    positions: tuple
    static_load: float
    unsprung_mass: float
    creepage: tuple
    share: float
    wheelsets: tuple | None = None
    wheelset_names: tuple | None = None

    def __post_init__(self):
        if len(self.positions) < 1 or len(set(self.positions)) != len(self.positions):
            raise ValueError(f"fleet vehicle '{self.name}': positions = {list(self.positions)} is not allowed: give at least "
                             "one axle, no two at one position.")
        if len(self.creepage) != len(self.positions):
            raise ValueError(f"fleet vehicle '{self.name}': creepage has {len(self.creepage)} values: it needs one per axle "
                             f"(positions has {len(self.positions)}).")
        for key in ("static_load", "unsprung_mass"):
            v = getattr(self, key)
            if not (np.isfinite(v) and v > 0):
                raise ValueError(f"fleet vehicle '{self.name}': {key} = {v!r} is not allowed: it must be a finite number > 0.")
        if not all(np.isfinite(c) and abs(c) < 1 for c in self.creepage):
            raise ValueError(f"fleet vehicle '{self.name}': creepage = {list(self.creepage)} is not allowed: each must be a "
                             "finite number in (-1, 1).")
        if not (np.isfinite(self.share) and 0 <= self.share <= 1):
            raise ValueError(f"fleet vehicle '{self.name}': share = {self.share!r} is not allowed: it must lie in [0, 1].")
        if self.wheelsets is not None and len(self.wheelsets) != len(self.positions):
            raise ValueError(f"fleet vehicle '{self.name}': wheelsets has {len(self.wheelsets)} entries: it needs one per axle "
                             f"(positions has {len(self.positions)}).")
        if (self.wheelset_names is None) != (self.wheelsets is None) or (
                self.wheelsets is not None and len(self.wheelset_names) != len(self.wheelsets)):
            raise ValueError(f"fleet vehicle '{self.name}': wheelset_names must give one name per entry of wheelsets.")

    @property
    def axles(self) -> int:
        """Axles of the vehicle (wheels on one rail) [-]."""
        return len(self.positions)

    @property
    def axle_load(self) -> float:
        """Axle load [t]: two wheels per axle, 2 static_load / g / 1000."""
        return 2 * self.static_load / GRAVITY / 1000

    def wheelsets_text(self) -> str:
        """', wheelsets [<name or 'own'> (motored|trailer), ...]' per axle, or '' for a vehicle on the scenario's wheelset."""
        if self.wheelsets is None:
            return ""
        axles = ", ".join(f"{n or 'own'} ({'motored' if ws.driven else 'trailer'})" for n, ws in zip(self.wheelset_names, self.wheelsets))
        return f", wheelsets [{axles}]"


@dataclass(frozen=True)
class SpeedClasses:
    """The traffic's speeds as discrete classes (config key ``fleet.speeds``).

    speeds  : m/s, > 0, one per class
    weights : -, >= 0, summing to 1: the share of the trains at each speed
    rule    : how they were obtained ('given', or the distribution and discretisation)
    """

    speeds: tuple
    weights: tuple
    rule: str = "given"

    def __post_init__(self):
        if len(self.speeds) != len(self.weights):
            raise ValueError(f"fleet.speeds: {len(self.speeds)} speeds but {len(self.weights)} weights: give one weight per speed.")
        for i, v in enumerate(self.speeds):
            if not (np.isfinite(v) and v > 0):
                raise ValueError(f"fleet.speeds.values[{i}] = {v!r} m/s is not allowed: it must be a finite number > 0.")
        _unit_sum("fleet.speeds.weights", self.weights)

    @property
    def mean(self) -> float:
        """Weighted mean speed [m/s]."""
        return float(np.dot(self.speeds, self.weights))


def normal_classes(mean: float, std: float, n: int) -> SpeedClasses:
    """A normal speed distribution as n equal-probability classes at their conditional means.

    Class i holds the probability between the quantiles i / n and (i + 1) / n; its speed is the
    mean of the distribution over that class, mean + std n (phi(z_i) - phi(z_i+1)), z_i =
    Phi^-1(i / n), phi and Phi the standard normal density and distribution. The discrete mean is
    the mean exactly; the discrete variance is below std^2 and tends to it as n grows.

    Parameters
    ----------
    mean : float
        Mean speed [m/s], > 0.
    std : float
        Standard deviation [m/s], >= 0.
    n : int
        Classes [-], >= 1.

    Returns
    -------
    SpeedClasses
    """
    if not (np.isfinite(std) and std >= 0):
        raise ValueError(f"fleet.speeds.std = {std!r} m/s is not allowed: it must be a finite number >= 0.")
    from scipy.special import ndtri  # here, not at the top: importing scipy costs jobs that do not use it about 0.7 s CPU

    z = ndtri(np.arange(n + 1) / n)  # -inf .. inf
    phi = np.exp(-0.5 * z ** 2) / np.sqrt(2 * np.pi)  # 0 at +-inf
    v = mean + std * n * (phi[:-1] - phi[1:])
    if n == 1:
        v = np.array([mean])
    if v[0] <= 0:
        raise ValueError(f"fleet.speeds: the normal distribution (mean {mean:g} m/s, std {std:g} m/s) in {n} classes gives a "
                         f"slowest class at {v[0]:.3g} m/s: every class must be > 0; reduce std or the classes.")
    return SpeedClasses(tuple(float(x) for x in v), tuple([1.0 / n] * n),
                        f"normal (mean {mean:g} m/s, std {std:g} m/s), {n} equal-probability classes at their conditional means")


def uniform_classes(low: float, high: float, n: int) -> SpeedClasses:
    """A uniform speed distribution on [low, high] as n equal-probability classes at their
    conditional means (the same as n equal-width classes at their centres).

    Parameters
    ----------
    low, high : float
        Bounds [m/s], 0 < low <= high.
    n : int
        Classes [-], >= 1.

    Returns
    -------
    SpeedClasses
    """
    if not (np.isfinite(low) and np.isfinite(high) and 0 < low <= high):
        raise ValueError(f"fleet.speeds.low = {low!r}, high = {high!r} m/s are not allowed: they must satisfy 0 < low <= high.")
    v = low + (high - low) * (np.arange(n) + 0.5) / n
    return SpeedClasses(tuple(float(x) for x in v), tuple([1.0 / n] * n),
                        f"uniform on [{low:g}, {high:g}] m/s, {n} equal-probability classes at their conditional means")


def speed_classes(spec: dict) -> SpeedClasses:
    """The speed classes of a ``fleet.speeds`` mapping: ``values`` with ``weights``, or ``distribution``
    'normal' (``mean``, ``std``) or 'uniform' (``low``, ``high``) with ``classes``.

    Parameters
    ----------
    spec : dict
        Speeds [m/s] and weights [-], or the distribution's parameters [m/s] and classes [-].

    Returns
    -------
    SpeedClasses
    """
    if "values" in spec:
        return SpeedClasses(tuple(float(v) for v in spec["values"]), tuple(float(w) for w in spec["weights"]))
    n = int(spec["classes"])
    if n < 1:
        raise ValueError(f"fleet.speeds.classes = {n} is not allowed: it must be an integer >= 1.")
    if spec["distribution"] == "normal":
        return normal_classes(float(spec["mean"]), float(spec["std"]), n)
    return uniform_classes(float(spec["low"]), float(spec["high"]), n)


def vehicle_spring(spring: ContactSpring, reference_load: float, load: float) -> ContactSpring:
    """The linearised Hertz spring of a wheel load, from the one given at a reference load.

    k_H is proportional to P^(1/3) (Hertz); the half-space loss slope eta_H / omega is proportional
    to k_H (rail.halfspace.contact_loss_factor, eta_H = -2 k_H Im w0); a constant loss factor is kept.

    Parameters
    ----------
    spring : ContactSpring
        At the reference load.
    reference_load, load : float
        Static wheel loads [N], > 0.

    Returns
    -------
    ContactSpring
        The spring itself when load == reference_load.
    """
    if load == reference_load:
        return spring
    s = (load / reference_load) ** (1 / 3)
    return ContactSpring(spring.hertz_stiffness * s, spring.loss_slope * s, spring.loss_factor)


@dataclass(frozen=True)
class FleetClass:
    """One (vehicle, speed) class of a fleet.

    vehicle  : the vehicle type's name
    speed    : m/s
    weight   : -, share_v weight_s, the class's share of the fleet passages
    scenario : the base scenario with the vehicle's wheels, spring and per-axle creepage, speeds (speed,)
    """

    vehicle: str
    speed: float
    weight: float
    scenario: Scenario

    @property
    def label(self) -> str:
        """'<vehicle> at <speed> m/s'."""
        return f"{self.vehicle} at {self.speed:.4g} m/s"


@dataclass(frozen=True)
class Fleet:
    """The traffic over the rail (config key ``fleet``; module docstring).

    vehicles      : the vehicle types, shares summing to 1
    speeds        : the speed classes, weights summing to 1
    axles_per_day : axle passages per day over the rail (config key ``traffic.axles_per_day``) [1/day]
    """

    vehicles: tuple
    speeds: SpeedClasses
    axles_per_day: float

    def __post_init__(self):
        if len(self.vehicles) < 1:
            raise ValueError("fleet.vehicles = [] is not allowed: give at least one vehicle type.")
        names = [v.name for v in self.vehicles]
        if len(set(names)) != len(names):
            raise ValueError(f"fleet.vehicles: the names {names} are not all different: give each vehicle type its own name.")
        _unit_sum("fleet.vehicles.share", [v.share for v in self.vehicles])
        if not (np.isfinite(self.axles_per_day) and self.axles_per_day > 0):
            raise ValueError(f"traffic.axles_per_day = {self.axles_per_day!r} is not allowed: it must be a finite number > 0.")

    @property
    def axles_per_train(self) -> float:
        """Mean axles per fleet passage, sum_v share_v n_v / sum_v share_v [-] (wheel passages on one rail;
        the shares sum to 1 only to SUM_TOLERANCE, and vehicles of n axles each give n exactly)."""
        return float(sum(v.share * v.axles for v in self.vehicles) / sum(v.share for v in self.vehicles))

    @property
    def mean_axle_load(self) -> float:
        """Mean load of the axles that pass [t]: sum_v share_v n_v Q_v / sum_v share_v n_v, Q_v = 2 P_v / g."""
        return float(sum(v.share * v.axles * v.axle_load for v in self.vehicles) / sum(v.share * v.axles for v in self.vehicles))

    @property
    def trains_per_day(self) -> float:
        """Fleet passages per day, axles_per_day / axles_per_train [1/day]."""
        return self.axles_per_day / self.axles_per_train

    @property
    def mgt_per_year(self) -> float:
        """Million gross tonnes per year: axles_per_day x 365 x mean axle load [t] / 1e6 [Mt/year]."""
        return self.axles_per_day * 365 * self.mean_axle_load / 1e6

    def classes(self, base: Scenario, reference_load: float | None = None) -> tuple:
        """The (vehicle, speed) classes, vehicle-major, each a Scenario with weight share_v weight_s.

        Parameters
        ----------
        base : Scenario
            The scenario everything else comes from (track, material, contact, wear, growth,
            roughness); its wheels give the radius and, by default, the reference load of the spring.
        reference_load : float, optional
            Static wheel load [N] the base scenario's contact spring is given for (default
            base.wheels.static_load).

        Returns
        -------
        tuple of FleetClass
            Classes of zero weight are left out.
        """
        P0 = base.wheels.static_load if reference_load is None else reference_load
        out, modes = [], {}
        for v in self.vehicles:
            own = None
            if v.wheelsets is not None:  # each axle's modes; a wheelset named by several axles or vehicles computed once
                for ws in v.wheelsets:
                    if id(ws) not in modes:
                        modes[id(ws)] = wheelset_modes(ws)
                own = tuple(modes[id(ws)] for ws in v.wheelsets)
            wheels = Wheels(v.unsprung_mass, base.wheels.radius, v.static_load, tuple(float(a) for a in v.positions),
                            tuple(float(c) for c in v.creepage), own)
            spring = vehicle_spring(base.spring, P0, v.static_load)
            # a vehicle with its own wheelsets reads none of the scenario's (the ``wheelset`` section): left out of its
            # material, so that nothing reads it as the class's and the class keys do not hash it
            material = base.material if own is None else dataclasses.replace(base.material, longitudinal=None)
            for speed, ws in zip(self.speeds.speeds, self.speeds.weights):
                w = v.share * ws
                if w > 0:
                    scn = dataclasses.replace(base, name=f"{base.name}:{v.name}@{speed:.6g}", wheels=wheels, spring=spring,
                                              material=material, speeds=(float(speed),))
                    out.append(FleetClass(v.name, float(speed), float(w), scn))
        return tuple(out)

    def attributes(self) -> dict:
        """The fleet's definitions and traffic units, for a dataset's attributes."""
        return {
            "fleet_vehicles": "; ".join(f"{v.name}: share {v.share:g}, {v.axles} axles at {list(v.positions)} m, wheel load "
                                        f"{v.static_load:g} N, unsprung mass {v.unsprung_mass:g} kg, creepage "
                                        f"{list(v.creepage)}{v.wheelsets_text()}" for v in self.vehicles),
            "fleet_speeds": f"{list(self.speeds.speeds)} m/s with weights {list(self.speeds.weights)} ({self.speeds.rule})",
            "fleet_passage": "one train drawn from the traffic (vehicle v with probability share_v, speed class s with "
                             "probability weight_s): the wear per fleet passage is sum_c w_c dZ_c, w_c = share_v weight_s",
            "axles_per_train": self.axles_per_train,
            "axles_per_day": self.axles_per_day,
            "trains_per_day": self.trains_per_day,
            "mean_axle_load_t": self.mean_axle_load,
            "axle_load_definition": "axle load = 2 x static wheel load / 9.80665 m/s^2 (two wheels per axle on two rails), t",
            "mgt_per_year": self.mgt_per_year,
            "mgt_definition": "MGT/year = axles_per_day x 365 x mean axle load [t] / 1e6",
        }
