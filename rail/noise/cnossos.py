"""Rolling noise by CNOSSOS-EU (Directive 2002/49/EC Annex II, section 2.3 and Appendix G).

From the rail roughness railgrowth predicts to the sound power of the traffic: the total effective
roughness (eq. 2.3.7), its wavelength-to-frequency mapping at the train speed, the rolling-noise
sound power of a vehicle from the track's and the vehicle's transfer functions (eqs. 2.3.8-2.3.10)
and the directional sound power per metre of line of a traffic (eq. 2.3.2, summed over the traffic).
The text implemented is Annex II as replaced by Commission Directive (EU) 2015/996, with the
corrigendum of 2018 (f = v / lambda with v in m/s) and the tables replaced by Delegated Directive
(EU) 2021/1226 (rail.noise.tables; docs/noise.md).

Conventions
-----------
* Units: SI at the interface (speed in m/s, wheel load in N, wheel diameter in m, pad stiffness in
  N/m); the tables' own units (mm, kN, MN/m) only inside the look-ups.
* Roughness levels in dB re 1 um (the project's convention, rail.traffic); sound power levels in
  dB re 1 pW; a sound power per metre of line in dB re 1 pW/m.
* Wavelength bands: the 35 one-third-octave bands of Tables G-1b and G-2, exact centres
  lambda_n = 10^(-n/10) m, n = -3..31 (2000 mm .. 0.8 mm), edges by rail.bands' one edge rule.
  Frequency bands: the 24 bands 50 Hz .. 10 kHz, exact centres f_m = 1000 Hz 10^(m/10), m = -13..10.
  The mapping uses exact centres: band m at speed v reads the wavelength v / f_m, at the fractional
  wavelength-band index n = 30 + m - 10 lg(v / (1 m/s)).
* The interpolation rule between the two wavelength bands the index falls between (weight w on the
  shorter, 1 - w on the longer; w is also the fraction of the frequency band's wavelength interval
  lying in the shorter band): "energy" (default) averages the mean squares, (1 - w) 10^(L_k/10) +
  w 10^(L_k+1/10); "level" averages the levels, (1 - w) L_k + w L_k+1. Both are linear in lg lambda;
  they agree at the band centres and on a flat spectrum and differ by up to 2.69 dB where the
  spectrum changes by 10 dB from one band to the next (docs/noise.md). The energy rule is the
  default because it conserves the mean square: a roughness that is uniform in lg lambda within
  each band puts exactly that mean square into the shifted band ("averaged energetically and
  proportionally" in 2.3.2's words).
* Order: L_R,TOT is formed on the wavelength bands (eq. 2.3.7, rail + wheel energy sum plus A_3)
  and then mapped onto the frequency bands, as the issue asks and NoiseModelling does.
* Range of validity: speeds v_min = 10^0.9 = 7.94 m/s (the 10 kHz band reads 0.8 mm) to v_max =
  100 m/s (the 50 Hz band reads 2000 mm); outside it the tables would be extrapolated and the speed
  is refused (check_speed). The wheel roughness table stops at 1000 mm: its value there is held for
  the three longer bands (every column of Table G-1a is flat at its long end), stated in the result.
* Directivity: the horizontal dipole of eq. 2.3.15; no vertical directivity (eq. 2.3.16) is
  applied, so the levels hold in the plane of the source (psi = 0, where it is 0 dB).

References
----------
Commission Directive (EU) 2015/996 of 19 May 2015 establishing common noise assessment methods
according to Directive 2002/49/EC, Annex, section 2.3 (railway noise) and Appendix G; corrigendum
OJ L 5, 10.1.2018; Commission Delegated Directive (EU) 2021/1226 of 21 December 2020, OJ L 269,
28.7.2021, p. 65.
"""

from __future__ import annotations

import math
import numpy as np

from ..bands import NOMINAL_TOLERANCE, ThirdOctaveBands, exact_centres, exact_edges
from ..bands import frequency_bands as _frequency_bands
from .tables import (
    CONTACT_FILTER,
    PAD_CLASSES_MN_PER_M,
    RAIL_ROUGHNESS,
    SUPERSTRUCTURE_TRANSFER,
    TRACK_TRANSFER,
    VEHICLE_TRANSFER,
    WAVELENGTH_LABELS_MM,
    WHEEL_ROUGHNESS,
)

__all__ = ["BRAKES", "FREQUENCY_INDICES", "RULES", "SLEEPERS", "SPEED_MAX", "SPEED_MIN",
           "WAVELENGTH_INDICES", "check_speed",
           "cnossos_frequency_bands", "cnossos_wavelength_bands", "contact_filter", "contact_filter_column",
           "horizontal_directivity", "line_sound_power", "pad_class", "rail_roughness_class",
           "rail_roughness_on_bands", "rolling_sound_power", "total_effective_roughness",
           "track_transfer", "vehicle_transfer", "vehicle_transfer_diameter", "wavelength_index",
           "wavelength_to_frequency", "wheel_roughness"]

WAVELENGTH_INDICES = np.arange(-3, 32)  # n of lambda_n = 10^(-n/10) m: 2000 mm .. 0.8 mm
FREQUENCY_INDICES = np.arange(-13, 11)  # m of f_m = 1000 Hz 10^(m/10): 50 Hz .. 10 kHz
SPEED_MIN = 10 ** 0.9  # [m/s] the 10 kHz band reads the 0.8 mm band's centre
SPEED_MAX = 100.0  # [m/s] the 50 Hz band reads the 2000 mm band's centre
RULES = ("energy", "level")
BRAKES = tuple(WHEEL_ROUGHNESS)  # cast_iron, composite, disc
SLEEPERS = ("monoblock", "biblock", "wooden", "direct")
_FREQUENCY_BANDS = _frequency_bands(50.0, 10000.0)


def cnossos_wavelength_bands() -> ThirdOctaveBands:
    """The 35 wavelength bands of Tables G-1b and G-2 (2000 mm .. 0.8 mm), longest first.

    Returns
    -------
    ThirdOctaveBands
        Exact centres 10^(-n/10) [m], n = -3..31, the tables' nominal labels [m] and the edges of
        rail.bands.exact_edges [m].
    """
    lower, upper = exact_edges(WAVELENGTH_INDICES, "m")
    return ThirdOctaveBands(centre=exact_centres(WAVELENGTH_INDICES, "m"),
                            nominal=np.array(WAVELENGTH_LABELS_MM) / 1000, lower=lower, upper=upper, unit="m")


def cnossos_frequency_bands() -> ThirdOctaveBands:
    """The 24 frequency bands of Tables G-3a..c (50 Hz .. 10 kHz), lowest first.

    Returns
    -------
    ThirdOctaveBands
        Exact centres 1000 Hz 10^(m/10) [Hz], m = -13..10, nominal labels and edges [Hz].
    """
    return _FREQUENCY_BANDS


def check_speed(speed, name: str = "speed") -> float:
    """A train speed within the range the tables cover without extrapolation, SPEED_MIN .. SPEED_MAX.

    Parameters
    ----------
    speed : float
        Train speed [m/s].
    name : str
        The parameter's name in the error.

    Returns
    -------
    float
        The speed [m/s].

    Raises
    ------
    ValueError
        Naming the parameter, its value and the range, for NaN, inf, a non-number or a speed outside it.
    """
    try:
        v = float(speed)
    except (TypeError, ValueError):
        raise ValueError(f"{name} = {speed!r} is not allowed: it must be a train speed in m/s.") from None
    if not (SPEED_MIN * (1 - 1e-12) <= v <= SPEED_MAX * (1 + 1e-12)):
        raise ValueError(f"{name} = {speed!r} m/s is not allowed: CNOSSOS-EU rolling noise is computed here for "
                         f"{SPEED_MIN:.2f} .. {SPEED_MAX:g} m/s ({3.6 * SPEED_MIN:.1f} .. {3.6 * SPEED_MAX:g} km/h), "
                         "where "
                         "the bands 50 Hz .. 10 kHz read wavelengths within the tables' 2000 mm .. 0.8 mm.")
    return v


def wavelength_index(speed):
    """Fractional wavelength-band index read by each frequency band at a speed: n = 30 + m - 10 lg(v),
    lambda = v / f_m = 10^(-n/10) m.

    Parameters
    ----------
    speed : float
        Train speed [m/s], within SPEED_MIN .. SPEED_MAX.

    Returns
    -------
    ndarray, shape (24,)
        n per frequency band 50 Hz .. 10 kHz [-], within -3 .. 31.
    """
    v = check_speed(speed)
    n = 30.0 + FREQUENCY_INDICES - 10 * math.log10(v)
    return np.clip(np.where(np.abs(n - np.round(n)) < 1e-9, np.round(n), n), -3, 31)


def wavelength_to_frequency(level, speed, rule: str = "energy"):
    """A level spectrum over the 35 wavelength bands mapped onto the 24 frequency bands at a speed,
    f = v / lambda with v in m/s (2.3.2 as corrected in 2018).

    Parameters
    ----------
    level : array-like, shape (..., 35)
        Levels [dB] per wavelength band, 2000 mm .. 0.8 mm on the last axis; -inf (no roughness)
        is allowed, NaN (no level) is not where the speed reads it.
    speed : float
        Train speed [m/s], within SPEED_MIN .. SPEED_MAX.
    rule : str
        "energy" (default: mean squares linear in lg lambda) or "level" (levels linear in lg lambda).

    Returns
    -------
    ndarray, shape (..., 24)
        Levels [dB] per frequency band, 50 Hz .. 10 kHz.

    Raises
    ------
    ValueError
        For another rule, a spectrum of another length, or NaN in a band the speed reads (naming
        the bands).
    """
    if rule not in RULES:
        raise ValueError(f"rule = {rule!r} is not allowed: it must be 'energy' or 'level'.")
    x = np.asarray(level, dtype=float)
    if x.shape[-1:] != (35,):
        raise ValueError("level must hold the 35 wavelength bands 2000 mm .. 0.8 mm on its last axis, "
                         f"not {x.shape[-1:]}.")
    q = wavelength_index(speed) + 3  # position on the 0..34 grid
    k = np.minimum(np.floor(q).astype(int), 33)
    w = q - k
    lo, hi = x[..., k], x[..., k + 1]
    used = np.unique(np.concatenate([k, (k + 1)[w > 0]]))
    empty = [WAVELENGTH_LABELS_MM[j] for j in used if np.isnan(x[..., j]).any()]
    if empty:
        raise ValueError(f"at {float(speed):g} m/s the bands 50 Hz .. 10 kHz read the wavelength bands "
                         f"{', '.join(f'{e:g}' for e in empty)} mm, which have no level: fill them "
                         "(rail_roughness_on_bands, fill=...).")
    if rule == "level":  # at w = 0 the band read alone (a silent neighbour, -inf, does not enter)
        with np.errstate(invalid="ignore"):
            return np.where(w == 0, lo, (1 - w) * lo + w * hi)
    with np.errstate(divide="ignore"):
        return 10 * np.log10((1 - w) * 10 ** (lo / 10) + w * 10 ** (hi / 10))


def total_effective_roughness(rail, wheel, contact):
    """Total effective roughness, eq. (2.3.7): L_R,TOT = 10 lg(10^(L_r,TR/10) + 10^(L_r,VEH/10)) + A_3,
    per wavelength band (rail and wheel roughness incoherent, energy sum; the contact filter added).

    Parameters
    ----------
    rail : array-like, shape (..., 35)
        Rail roughness L_r,TR [dB re 1 um].
    wheel : array-like, shape (35,)
        Wheel roughness L_r,VEH [dB re 1 um].
    contact : array-like, shape (35,)
        Contact filter A_3 [dB].

    Returns
    -------
    ndarray, shape (..., 35)
        L_R,TOT [dB re 1 um]; NaN where the rail roughness is NaN (an empty band stays empty).

    Raises
    ------
    ValueError
        If a spectrum is not of the 35 bands, or the wheel or the contact filter holds NaN.
    """
    r, wh, a3 = (np.asarray(v, dtype=float) for v in (rail, wheel, contact))
    for name, v in (("rail", r), ("wheel", wh), ("contact", a3)):
        if v.shape[-1:] != (35,):
            raise ValueError(f"{name} must hold the 35 wavelength bands 2000 mm .. 0.8 mm, not shape {v.shape}.")
    if np.isnan(wh).any() or np.isnan(a3).any():
        raise ValueError("the wheel roughness and the contact filter must have a level in every band (NaN given).")
    return 10 * np.log10(10 ** (r / 10) + 10 ** (wh / 10)) + a3


def wheel_roughness(brake):
    """Wheel roughness of Table G-1a on the 35 bands: the printed 32 bands (1000 mm .. 0.8 mm), the
    1000 mm value held for 2000, 1600 and 1250 mm (the table's columns are flat at their long end).

    Parameters
    ----------
    brake : str or array-like
        "cast_iron", "composite" or "disc" (non-tread braked), or a user's 35-band spectrum
        [dB re 1 um].

    Returns
    -------
    ndarray, shape (35,)
        L_r,VEH [dB re 1 um].

    Raises
    ------
    ValueError
        Naming ``brake`` for an unknown brake type, or a spectrum that is not 35 finite levels.
    """
    if isinstance(brake, str):
        if brake not in WHEEL_ROUGHNESS:
            raise ValueError(f"brake = {brake!r} is not allowed: Table G-1a gives {', '.join(BRAKES)} "
                             "(or give a 35-band wheel roughness spectrum in dB re 1 um).")
        col = WHEEL_ROUGHNESS[brake]
        return np.array((col[0],) * 3 + col)
    x = np.asarray(brake, dtype=float)
    if x.shape != (35,) or not np.isfinite(x).all():
        raise ValueError("brake: a wheel roughness spectrum must be 35 finite levels (2000 mm .. 0.8 mm), "
                         f"got shape {x.shape}.")
    return x


def rail_roughness_class(name: str):
    """Rail roughness of Table G-1b: "E" (EN ISO 3095:2013, well maintained and very smooth) or "M"
    (average network, normally maintained and smooth).

    Parameters
    ----------
    name : str
        "E" or "M".

    Returns
    -------
    ndarray, shape (35,)
        L_r,TR [dB re 1 um], 2000 mm .. 0.8 mm.

    Raises
    ------
    ValueError
        For another class (N and B carry no spectrum in Appendix G).
    """
    if name not in RAIL_ROUGHNESS:
        raise ValueError(f"rail roughness class = {name!r} is not allowed: Table G-1b gives 'E' and 'M' "
                         "(the classes N and B have no spectrum in Appendix G).")
    return np.array(RAIL_ROUGHNESS[name])


def contact_filter_column(wheel_load, wheel_diameter):
    """The column of Table G-2 for a wheel: the one whose wheel load times wheel diameter is nearest
    in ratio to the wheel's (this module's rule: the filter depends on lambda over the contact
    length, and a Hertz contact's length grows as (P D)^(1/3)).

    Parameters
    ----------
    wheel_load : float
        Static wheel load [N], > 0.
    wheel_diameter : float
        Wheel diameter [m], > 0.

    Returns
    -------
    tuple of float
        (wheel load [kN], wheel diameter [mm]) of the column.

    Raises
    ------
    ValueError
        Naming the parameter for a load or diameter that is not finite and > 0.
    """
    for name, v in (("wheel_load", wheel_load), ("wheel_diameter", wheel_diameter)):
        if not (isinstance(v, (int, float, np.floating)) and math.isfinite(v) and v > 0):
            raise ValueError(f"{name} = {v!r} is not allowed: it must be a finite number > 0 "
                             "(N for a load, m for a diameter).")
    pd = wheel_load / 1000 * wheel_diameter * 1000
    return min(CONTACT_FILTER, key=lambda k: abs(math.log(k[0] * k[1] / pd)))


def contact_filter(column):
    """Contact filter A_3 of Table G-2 on the 35 wavelength bands.

    Parameters
    ----------
    column : tuple of float
        (wheel load [kN], wheel diameter [mm]) of a column (contact_filter_column chooses one).

    Returns
    -------
    ndarray, shape (35,)
        A_3 [dB].

    Raises
    ------
    ValueError
        For a column the table does not have, listing those it has.
    """
    key = tuple(float(c) for c in column)
    if key not in CONTACT_FILTER:
        raise ValueError(f"contact filter column {column!r} is not in Table G-2: it gives "
                         "(wheel load kN, wheel diameter mm) "
                         f"{', '.join(str(k) for k in CONTACT_FILTER)}.")
    return np.array(CONTACT_FILTER[key])


def pad_class(stiffness) -> str:
    """Rail pad class of the track descriptor (Table [2.3.b], digit 3) from the pad's dynamic
    stiffness: soft 150 <= k < 250 MN/m, medium 250 <= k < 800 MN/m, hard 800 <= k <= 1000 MN/m
    (a stiffness on a shared edge goes to the stiffer class).

    Parameters
    ----------
    stiffness : float
        Pad dynamic stiffness per rail seat [N/m] (railgrowth's track.pad.stiffness).

    Returns
    -------
    str
        "soft", "medium" or "hard".

    Raises
    ------
    ValueError
        Naming track.pad.stiffness, its value and the classes' range for a stiffness outside
        150 .. 1000 MN/m (or not finite): Table G-3a has no class for it.
    """
    try:
        k = float(stiffness) / 1e6
    except (TypeError, ValueError):
        raise ValueError(f"track.pad.stiffness = {stiffness!r} is not allowed: it must be a stiffness in N/m."
                         ) from None
    lo, hi = PAD_CLASSES_MN_PER_M["soft"][0], PAD_CLASSES_MN_PER_M["hard"][1]
    if not (lo <= k <= hi):
        raise ValueError(f"track.pad.stiffness = {stiffness!r} N/m ({k:g} MN/m) has no CNOSSOS-EU pad class: "
                         "the classes "
                         f"cover {lo:g} .. {hi:g} MN/m (soft 150-250, medium 250-800, hard 800-1000 MN/m, 2021/1226); "
                         "name the class yourself (Track(pad='soft')) if you accept that track transfer.")
    for name, (a, b) in PAD_CLASSES_MN_PER_M.items():
        if a <= k < b:
            return name
    return "hard"


def track_transfer(sleeper: str, pad: str | None = None):
    """Track transfer function L_H,TR of Table G-3a.

    Parameters
    ----------
    sleeper : str
        "monoblock" or "biblock" (concrete, with a pad class), "wooden", or "direct" (direct
        fastening on bridges).
    pad : str, optional
        "soft", "medium" or "hard" for concrete sleepers; None for wooden and direct.

    Returns
    -------
    ndarray, shape (24,)
        L_H,TR [dB re 1 pW per axle for 0 dB re 1 um], 50 Hz .. 10 kHz.

    Raises
    ------
    ValueError
        Naming the parameter for an unknown sleeper or a pad class that does not go with it.
    """
    if sleeper not in SLEEPERS:
        raise ValueError(f"sleeper = {sleeper!r} is not allowed: it must be one of {', '.join(SLEEPERS)}.")
    key = (sleeper, pad if sleeper in ("monoblock", "biblock") else None)
    if sleeper in ("monoblock", "biblock") and pad not in PAD_CLASSES_MN_PER_M:
        raise ValueError(f"pad = {pad!r} is not allowed for {sleeper} sleepers: it must be 'soft', 'medium' or 'hard'.")
    if sleeper in ("wooden", "direct") and pad is not None:
        raise ValueError(f"pad = {pad!r} is not allowed for {sleeper}: Table G-3a has one column for it (pad=None).")
    return np.array(TRACK_TRANSFER[key])


def vehicle_transfer_diameter(wheel_diameter) -> float:
    """The wheel diameter of Table G-3b nearest in ratio to a wheel's (this module's rule).

    Parameters
    ----------
    wheel_diameter : float
        Wheel diameter [m], > 0.

    Returns
    -------
    float
        The tabulated diameter [mm]: 680, 840, 920 or 1200.

    Raises
    ------
    ValueError
        For a diameter that is not finite and > 0.
    """
    d = wheel_diameter
    if not (isinstance(d, (int, float, np.floating)) and math.isfinite(d) and d > 0):
        raise ValueError(f"wheel_diameter = {wheel_diameter!r} is not allowed: it must be a finite number > 0 in m.")
    return min(VEHICLE_TRANSFER, key=lambda d: abs(math.log(d / (1000 * wheel_diameter))))


def vehicle_transfer(diameter_mm: float, freight: bool = False):
    """Vehicle transfer L_H,VEH of Table G-3b (no wheel measure), with the superstructure transfer
    L_H,VEH,SUP of Table G-3c energy-added for a freight wagon (eq. 2.3.10).

    Parameters
    ----------
    diameter_mm : float
        A tabulated wheel diameter [mm]: 680, 840, 920 or 1200.
    freight : bool
        Whether the vehicle is a freight wagon (its superstructure radiates, Table G-3c).

    Returns
    -------
    list of ndarray, shape (24,)
        [L_H,VEH] or [L_H,VEH, L_H,VEH,SUP] [dB re 1 pW per axle for 0 dB re 1 um].

    Raises
    ------
    ValueError
        For a diameter the table does not have.
    """
    if float(diameter_mm) not in VEHICLE_TRANSFER:
        raise ValueError(f"wheel diameter {diameter_mm!r} mm is not in Table G-3b: it gives "
                         f"{', '.join(f'{d:g}' for d in VEHICLE_TRANSFER)} mm (vehicle_transfer_diameter chooses one).")
    out = [np.array(VEHICLE_TRANSFER[float(diameter_mm)])]
    if freight:
        out.append(np.array(SUPERSTRUCTURE_TRANSFER))
    return out


def rail_roughness_on_bands(wavelength, level, fill=None, fill_source: str = "fill spectrum"):
    """A rail roughness spectrum per one-third-octave wavelength band (railgrowth's own band centres,
    rail.studies.exports.rolling_noise_levels or rail.studies.bands) on the 35 CNOSSOS bands.

    The rule: each given centre must name one CNOSSOS band, within rail.bands.NOMINAL_TOLERANCE
    (1.5 %) of its nominal label or its exact centre 10^(-n/10) m (railgrowth's bands are these
    bands, so a level moves unchanged); a centre naming none, or a band named twice, is refused.
    A band given no level (absent or NaN) takes the level of ``fill`` if it has one and stays NaN
    otherwise (wavelength_to_frequency then names it if the speed reads it); never zero.

    Parameters
    ----------
    wavelength : array-like
        Band centre wavelengths [m].
    level : array-like
        Rail roughness [dB re 1 um] per band; NaN where the band has no level.
    fill : array-like, shape (35,), optional
        Levels [dB re 1 um] for the bands not given (e.g. the initial roughness's input spectrum,
        or Table G-1b's class M: rail_roughness_class("M")).
    fill_source : str
        How the fill is named in the returned sources.

    Returns
    -------
    level : ndarray, shape (35,)
        [dB re 1 um] per CNOSSOS band, 2000 mm .. 0.8 mm; NaN where neither gives a level.
    source : ndarray of str, shape (35,)
        "model" where the given spectrum sets the band, ``fill_source`` where the fill does, "" where
        the band is empty.

    Raises
    ------
    ValueError
        For a centre that names no band (naming the nearest), a band named twice, lengths that
        differ, or a fill that is not 35 levels.
    """
    bands = cnossos_wavelength_bands()
    lam, lv = np.atleast_1d(np.asarray(wavelength, dtype=float)), np.atleast_1d(np.asarray(level, dtype=float))
    if lam.shape != lv.shape:
        raise ValueError(f"wavelength and level differ in length ({lam.size} and {lv.size}).")
    out, source, named = np.full(35, np.nan), np.full(35, "", dtype=object), set()
    for v, x in zip(lam, lv):
        off = np.minimum(np.abs(v / bands.nominal - 1), np.abs(v / bands.centre - 1))
        k = int(np.argmin(off))
        if not np.isfinite(v) or off[k] > NOMINAL_TOLERANCE:
            raise ValueError(f"wavelength {v:g} m is not a one-third-octave band of CNOSSOS-EU's 2000 mm .. 0.8 mm: "
                             f"the nearest is {1000 * bands.nominal[k]:g} mm; give nominal labels or exact centres "
                             "10^(-n/10) m within "
                             f"{100 * NOMINAL_TOLERANCE:g} %.")
        if k in named:
            raise ValueError(f"wavelength {v:g} m names the band {1000 * bands.nominal[k]:g} mm again.")
        named.add(k)
        if np.isfinite(x):
            out[k], source[k] = x, "model"
    if fill is not None:
        f = np.asarray(fill, dtype=float)
        if f.shape != (35,):
            raise ValueError(f"fill must hold the 35 bands 2000 mm .. 0.8 mm, not shape {f.shape}.")
        take = np.isnan(out) & np.isfinite(f)
        out[take], source[take] = f[take], fill_source
    return out, source.astype(str)


def rolling_sound_power(roughness, transfer, axles):
    """Rolling-noise sound power of one part of a vehicle, eqs. (2.3.8)-(2.3.10):
    L_W,0 = L_R,TOT + L_H + 10 lg(N_a), N_a the vehicle's axles (N_a = 1: per axle).

    Parameters
    ----------
    roughness : array-like, shape (..., 24)
        L_R,TOT per frequency band [dB re 1 um].
    transfer : array-like, shape (24,)
        Transfer function L_H (track, vehicle or superstructure) [dB re 1 pW per axle].
    axles : float
        Axles of the vehicle N_a [-], > 0.

    Returns
    -------
    ndarray, shape (..., 24)
        L_W,0 [dB re 1 pW].

    Raises
    ------
    ValueError
        Naming axles if it is not a finite number > 0.
    """
    if not (isinstance(axles, (int, float, np.integer, np.floating)) and math.isfinite(axles) and axles > 0):
        raise ValueError(f"axles = {axles!r} is not allowed: it must be a number of axles per vehicle > 0.")
    return np.asarray(roughness, dtype=float) + np.asarray(transfer, dtype=float) + 10 * math.log10(axles)


def horizontal_directivity(phi):
    """Horizontal directivity of rolling noise, eq. (2.3.15): 10 lg(0.01 + 0.99 sin^2 phi), 0 dB
    broadside, -20 dB along the track.

    Parameters
    ----------
    phi : float
        Angle to the direction of travel [deg].

    Returns
    -------
    float
        Delta L_W,dir,hor [dB].
    """
    return 10 * math.log10(0.01 + 0.99 * math.sin(math.radians(phi)) ** 2)


def line_sound_power(sound_power, vehicles_per_hour, speed):
    """Sound power per metre of line of a steady flow of one vehicle class, eq. (2.3.2):
    L'_W,eq,line = L_W,0,dir + 10 lg(Q / (1000 v)), Q vehicles per hour and v in km/h, i.e.
    10 lg(Q / (3600 s/h v)) with v in m/s: the power of the vehicles per metre of track on average.

    Parameters
    ----------
    sound_power : array-like
        L_W,0,dir of one vehicle [dB re 1 pW].
    vehicles_per_hour : float
        Q [1/h], > 0.
    speed : float
        v [m/s], > 0.

    Returns
    -------
    ndarray
        L'_W,eq,line [dB re 1 pW/m].

    Raises
    ------
    ValueError
        Naming the parameter for a flow or speed that is not finite and > 0 (no traffic is refused:
        it has no level).
    """
    for name, v in (("vehicles_per_hour", vehicles_per_hour), ("speed", speed)):
        if not (isinstance(v, (int, float, np.integer, np.floating)) and math.isfinite(v) and v > 0):
            raise ValueError(f"{name} = {v!r} is not allowed: it must be a finite number > 0 "
                             f"({'vehicles per hour' if name != 'speed' else 'm/s'}).")
    return np.asarray(sound_power, dtype=float) + 10 * math.log10(vehicles_per_hour / (3600.0 * speed))
