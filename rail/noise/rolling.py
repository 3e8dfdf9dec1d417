"""Rolling noise of a traffic over a track by CNOSSOS-EU: the track, the vehicle classes, their flows,
and the chain of rail.noise.cnossos from the rail roughness to the sound power per metre of line.

Conventions are those of rail.noise.cnossos (SI at the interface, levels in dB, the 35 wavelength
and 24 frequency bands, the "energy" rule by default); the result holds every intermediate level so
that a user (and tests/test_noise.py) can follow eqs. (2.3.7), (2.3.8)-(2.3.10), (2.3.15), (2.3.2).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .cnossos import (check_speed, cnossos_frequency_bands, contact_filter, contact_filter_column,
                      horizontal_directivity, line_sound_power, rolling_sound_power, total_effective_roughness,
                      track_transfer, vehicle_transfer, vehicle_transfer_diameter, wavelength_index,
                      wavelength_to_frequency, wheel_roughness)
from .weighting import energy_sum, overall_level

__all__ = ["RollingNoise", "Track", "TrafficClass", "Vehicle", "fleet_traffic", "rolling_noise"]


@dataclass(frozen=True, slots=True)
class Track:
    """The track of CNOSSOS-EU's descriptor that rolling noise needs.

    sleeper : "monoblock", "biblock", "wooden" or "direct" (direct fastening on bridges)
    pad     : "soft", "medium", "hard" for concrete sleepers (pad_class from the stiffness), None else
    own     : the track's own transfer L_H,TR,own per band (rail.noise.own_track), 24 levels, or None

    ``own`` is in dB re 1 pW per axle for 0 dB re 1 um and replaces Table G-3a's; with None, Table G-3a's
    of the sleeper and pad is taken (otherwise they are not read).
    """

    sleeper: str = "monoblock"
    pad: str | None = "medium"
    own: tuple | None = None

    def __post_init__(self):
        if self.own is None:
            track_transfer(self.sleeper, self.pad)  # refuses an unknown sleeper or pad, naming it
        elif len(self.own) != 24 or not np.all(np.isfinite(np.asarray(self.own, dtype=float))):
            raise ValueError("own: the track's own transfer must be 24 finite levels (50 Hz .. 10 kHz, dB re 1 pW per axle).")

    def transfer(self):
        """L_H,TR of Table G-3a, or the track's own, [dB re 1 pW per axle], 24 bands."""
        return track_transfer(self.sleeper, self.pad) if self.own is None else np.array(self.own, dtype=float)


@dataclass(frozen=True, slots=True)
class Vehicle:
    """A vehicle class for rolling noise.

    name           : label
    axles          : N_a, axles per vehicle [-], > 0
    brake          : "cast_iron", "composite", "disc" (Table G-1a), or a tuple: 35-band wheel roughness [dB re 1 um]
    wheel_diameter : [m], > 0: chooses L_H,VEH (Table G-3b, nearest diameter) and A_3
    wheel_load     : static wheel load [N], > 0: chooses A_3 (Table G-2, nearest P D)
    freight        : whether the superstructure transfer of Table G-3c is added (freight wagons)
    """

    name: str
    axles: int = 4
    brake: str | tuple = "disc"
    wheel_diameter: float = 0.92
    wheel_load: float = 50e3
    freight: bool = False

    def __post_init__(self):
        rolling_sound_power(np.zeros(24), np.zeros(24), self.axles)  # refuses axles, naming it
        wheel_roughness(self.brake)
        contact_filter_column(self.wheel_load, self.wheel_diameter)


@dataclass(frozen=True, slots=True)
class TrafficClass:
    """A steady flow of one vehicle class: vehicles per hour at one speed.

    vehicle           : Vehicle
    vehicles_per_hour : Q [1/h], > 0
    speed             : v [m/s], within SPEED_MIN .. SPEED_MAX
    """

    vehicle: Vehicle
    vehicles_per_hour: float
    speed: float

    def __post_init__(self):
        line_sound_power(0.0, self.vehicles_per_hour, check_speed(self.speed, f"{self.vehicle.name}: speed"))


@dataclass(frozen=True, slots=True)
class RollingNoise:
    """Rolling noise of a traffic over a track (rolling_noise): per class c and frequency band f.

    frequency          : nominal band centres [Hz], 24
    roughness_total    : L_R,TOT per (class, band) [dB re 1 um]
    power_track        : L_W,0,TR per vehicle (class, band) [dB re 1 pW]
    power_vehicle      : L_W,0,VEH (+ SUP) per vehicle (class, band) [dB re 1 pW]
    power              : L_W,0 = track + vehicle per vehicle, with the horizontal directivity (class, band) [dB re 1 pW]
    line_power         : L'_W,eq,line per (class, band) [dB re 1 pW/m]
    line_power_total   : energy sum over the classes per band [dB re 1 pW/m]
    line_power_A       : overall A-weighted L'_W,eq,line of the traffic [dB(A) re 1 pW/m]
    line_power_class_A : overall A-weighted per class [dB(A) re 1 pW/m]
    power_A            : overall A-weighted L_W,0 per vehicle of each class [dB(A) re 1 pW]
    contact_columns    : Table G-2 column (kN, mm) used per class
    diameters          : Table G-3b diameter [mm] used per class
    rule               : interpolation rule ("energy" or "level")
    notes              : what was assumed (the held wheel-roughness bands)
    """

    frequency: np.ndarray
    roughness_total: np.ndarray
    power_track: np.ndarray
    power_vehicle: np.ndarray
    power: np.ndarray
    line_power: np.ndarray
    line_power_total: np.ndarray
    line_power_A: float
    line_power_class_A: np.ndarray
    power_A: np.ndarray
    contact_columns: tuple
    diameters: tuple
    rule: str
    notes: str


def rolling_noise(rail, track: Track, traffic, rule: str = "energy", phi: float = 90.0) -> RollingNoise:
    """Rolling noise of a traffic by CNOSSOS-EU from a rail roughness spectrum: per class, L_R,TOT on
    the wavelength bands (2.3.7), mapped onto the frequency bands at the class's speed, the sound power
    of the track and vehicle parts (2.3.8-2.3.10) energy-added, the horizontal directivity (2.3.15),
    the line power (2.3.2) and the energy sum over the traffic.

    Parameters
    ----------
    rail : array-like, shape (35,)
        Rail roughness L_r,TR [dB re 1 um], 2000 mm .. 0.8 mm (rail_roughness_on_bands).
    track : Track
    traffic : TrafficClass or sequence of TrafficClass
        At least one class.
    rule : str
        Wavelength-to-frequency rule, "energy" (default) or "level".
    phi : float
        Angle to the direction of travel [deg] (90: broadside, 0 dB).

    Returns
    -------
    RollingNoise

    Raises
    ------
    ValueError
        For no traffic, no rail roughness in a band a class's speed reads (naming the bands), or a
        bad argument (naming it).
    """
    classes = [traffic] if isinstance(traffic, TrafficClass) else list(traffic)
    if not classes or not all(isinstance(c, TrafficClass) for c in classes):
        raise ValueError("traffic must be one TrafficClass or a non-empty sequence of them: "
                         "without traffic there is no noise.")
    r = np.asarray(rail, dtype=float)
    if r.shape != (35,):
        raise ValueError(f"rail must hold the 35 bands 2000 mm .. 0.8 mm, not shape {r.shape}.")
    if not np.isfinite(r).any():
        raise ValueError("rail has no roughness level in any band: there is no roughness to make noise from.")
    if not math.isfinite(phi):
        raise ValueError(f"phi = {phi!r} is not allowed: it must be an angle in degrees.")
    nominal = cnossos_frequency_bands().nominal
    lrt, ptr, pveh, ptot, line, cols, dias = [], [], [], [], [], [], []
    held = False
    for c in classes:
        veh = c.vehicle
        col = contact_filter_column(veh.wheel_load, veh.wheel_diameter)
        dia = vehicle_transfer_diameter(veh.wheel_diameter)
        held |= isinstance(veh.brake, str) and wavelength_index(c.speed).min() < 0  # a band longer than 1000 mm is read
        total = wavelength_to_frequency(total_effective_roughness(r, wheel_roughness(veh.brake), contact_filter(col)),
                                        c.speed, rule)
        p_tr = rolling_sound_power(total, track.transfer(), veh.axles)
        p_veh = energy_sum(np.stack([rolling_sound_power(total, h, veh.axles)
                                     for h in vehicle_transfer(dia, veh.freight)]), axis=0)
        p = energy_sum(np.stack([p_tr, p_veh]), axis=0) + horizontal_directivity(phi)
        lrt.append(total), ptr.append(p_tr), pveh.append(p_veh), ptot.append(p), cols.append(col), dias.append(dia)
        line.append(line_sound_power(p, c.vehicles_per_hour, c.speed))
    line = np.array(line)
    total_line = energy_sum(line, axis=0)
    notes = ("Table G-1a's 1000 mm wheel roughness held for 1250-2000 mm, read at these speeds" if held
             else "wheel roughness within Table G-1a's 1000 mm .. 0.8 mm")
    return RollingNoise(frequency=nominal.astype(float), roughness_total=np.array(lrt), power_track=np.array(ptr),
                        power_vehicle=np.array(pveh), power=np.array(ptot), line_power=line,
                        line_power_total=total_line,
                        line_power_A=float(overall_level(total_line, nominal)),
                        line_power_class_A=np.asarray(overall_level(line, nominal)),
                        power_A=np.asarray(overall_level(np.array(ptot), nominal)), contact_columns=tuple(cols),
                        diameters=tuple(dias), rule=rule, notes=notes)


def fleet_traffic(fleet, brakes, wheel_diameter: float, vehicles_per_hour: float | None = None) -> tuple:
    """A fleet's CNOSSOS-EU traffic classes: one per (vehicle type, speed class) of non-zero weight, in
    the fleet's order (vehicle-major, as rail.fleet.Fleet.classes).

    Class c = (vehicle v, speed s) runs at the speed v_s with N_a = the vehicle's axles (its positions),
    the wheel diameter ``wheel_diameter`` (every vehicle's: the growth model's wheels.radius), the wheel
    load its static_load, the wheel roughness of its brake, and Q_c = Q w_c vehicles per hour,
    w_c = share_v weight_s / (sum of shares x sum of weights) (the sums are 1 to rail.fleet.SUM_TOLERANCE;
    normalised so that sum_c w_c = 1 exactly). Q is the fleet's trains per hour, axles_per_day / 24 h /
    (mean axles per train), unless ``vehicles_per_hour`` is given; then sum_c Q_c N_a,c =
    axles_per_day / 24 h, the axles per hour of the growth run.

    Parameters
    ----------
    fleet : rail.fleet.Fleet
        The vehicle types (name, positions, static_load [N], share [-]) and speed classes (speeds [m/s], weights [-]).
    brakes : sequence of str
        The wheel roughness of each vehicle type, a Table G-1a brake type ("cast_iron", "composite", "disc").
    wheel_diameter : float
        Wheel diameter [m], > 0 (Table G-3b's diameter and, with the load, Table G-2's column).
    vehicles_per_hour : float, optional
        Trains per hour Q [1/h] of the whole fleet (default: the fleet's trains_per_day / 24).

    Returns
    -------
    classes : tuple of TrafficClass
        Each vehicle named '<vehicle> at <speed> m/s' (the rail.fleet.FleetClass label); Q_c [1/h], speed [m/s].
    shares : tuple of float
        w_c [-], summing to 1.

    Raises
    ------
    ValueError
        A class speed outside CNOSSOS-EU's 7.94 .. 100 m/s (naming fleet.speeds, the vehicle and the
        range); a brake per vehicle missing; a bad brake or load (naming it).
    """
    brakes = tuple(brakes)
    if len(brakes) != len(fleet.vehicles):
        raise ValueError(f"brakes holds {len(brakes)} names for {len(fleet.vehicles)} vehicle types: give one per vehicle.")
    total = sum(v.share for v in fleet.vehicles) * sum(fleet.speeds.weights)
    q = fleet.trains_per_day / 24.0 if vehicles_per_hour is None else float(vehicles_per_hour)
    classes, shares = [], []
    for v, brake in zip(fleet.vehicles, brakes):
        for speed, ws in zip(fleet.speeds.speeds, fleet.speeds.weights):
            w = v.share * ws / total
            if w > 0:
                check_speed(float(speed), f"fleet.speeds: the class speed of {v.name}")
                veh = Vehicle(f"{v.name} at {speed:.4g} m/s", axles=v.axles, brake=brake, wheel_diameter=float(wheel_diameter),
                              wheel_load=float(v.static_load))
                classes.append(TrafficClass(veh, float(q * w), float(speed)))
                shares.append(float(w))
    return tuple(classes), tuple(shares)
