"""The track's own transfer function: the rail's sound power per axle from the scenario's rail
receptance and EN 15461 decay rate, in place of CNOSSOS-EU's class average L_H,TR (issue 56;
docs/noise.md, "The track's own transfer").

The standard rolling-noise theory (Thompson, *Railway Noise and Vibration*, 2009, ch. 5 wheel/rail
interaction, ch. 6 track vibration and radiation, ch. 9 the whole model; TWINS), per frequency f
and per unit rms roughness r at one wheel/rail contact:

* contact force through the receptances at the contact, abs(F) = abs(r) / abs(alpha_W + alpha_R + alpha_C)
  (rail.interaction's eq. 21 for one wheel on a track without parametric excitation);
* the rail's velocity at the contact, v_0 = i omega alpha_R F;
* the rail's vibration decays away from the contact at Delta dB/m, abs(v(x))^2 = abs(v_0)^2 exp(-2 beta abs(x)),
  beta = Delta / (20 lg e) = Delta / 8.686 Np/m; both directions together,
  int exp(-2 beta abs(x)) dx = 1 / beta (decay_length). With the EN 15461 decay rate the integral is
  the estimator's own sum, 8.686 / Delta = 2 sum_n abs(A(x_n))^2 / abs(A(x_0))^2 dx_n (rail.decay), the
  near field included;
* the rail radiates as a line source, per metre W' = rho c (2 b) sigma(f) <v^2>, <v^2> the rail's
  mean-square vertical velocity; over the decay length
  W_rail = rho c (2 b) sigma <v_0^2> / beta = rho c (2 b) sigma abs(v_0)^2 / (2 beta) for an amplitude v_0
  (<v_0^2> = abs(v_0)^2 / 2; with the rms roughness of a band level, v_0 is an rms and <v_0^2> = abs(v_0)^2);
* two rails per axle, each excited by its own wheel with the same roughness, incoherent:
  W_axle = 2 W_rail; the level per axle for a roughness of 0 dB re 1 um is the own transfer,
  L_H,TR,own = 10 lg(W_axle(r = 1 um rms) / 1 pW), so that L_W,0,TR = L_R,TOT + L_H,TR,own + 10 lg N_a
  as eq. (2.3.8) with Table G-3a's L_H,TR.

Conventions
-----------
* SI: f in Hz, omega = 2 pi f in rad/s, receptances in m/N, displacement and force positive
  downwards on the rail (rail.track), a rigid wheel's receptance -1/(M omega^2) (rail.interaction).
* Levels: sound power dB re 1 pW per axle; roughness dB re 1 um rms (band level).
* Band averages: the frequencies of the decay rate (rail.decay.band_frequencies, equally spaced in
  each band); <v_0^2> sigma averaged over them; the rail receptance at the decay rate's excitation
  points (above a sleeper and at mid-span) and the power averaged over the two (a two-point estimate
  of the bay average); the decay rate of the "bay_sampled" positions (they integrate the
  bay-averaged response, rail.decay.decay_distances).

Model choices (stated, not fitted)
----------------------------------
* Wheel: a rigid mass, alpha_W = -1/(M omega^2), M = wheels.mass (rail.interaction's wheel). The
  vehicle's own radiation stays CNOSSOS-EU's L_H,VEH: only the track part is replaced.
* Contact spring: alpha_C = 1 / (k_H (1 + i eta_H)), the scenario's spring (contact.hertz_stiffness
  and its loss factor model, rail.interaction.ContactSpring). The contact filter is not
  applied again: L_R,TOT already holds A_3 (eq. 2.3.7).
* Radiation efficiency of the rail, vertical motion: a rigid circular cylinder oscillating
  transversely (a 2D line dipole) in free field, sigma(ka) = 2 / (pi ka abs(H_1'(ka))^2)
  (cylinder_radiation_ratio; Morse & Ingard, *Theoretical Acoustics*, 1968, sec. 7.3), with the
  radius a = 2 b / pi that gives the rail's high-frequency limit: every face radiates plane waves
  of its normal velocity, sum of v_n^2 dS over the section = v^2 (2 b) per metre, b the foot width
  (the section's horizontal projection, seen from above and below). b = 0.150 m (UIC60, EN 13674-1
  60E1), a = 95.5 mm, ka = 1 at 572 Hz; below, sigma falls as (pi / 2)(ka)^3 (30 dB per decade).
  Neither the ground nor the sleepers' baffling is modelled.
* Neglected: the sleepers' radiation (CNOSSOS-EU's L_H,TR holds it: it dominates a concrete
  sleeper track below about 500 Hz, Thompson ch. 6), the rail's lateral vibration and its
  radiation, the moving load (stationary receptances: the train speed is far below the rail's wave
  speeds above 100 Hz), the rail's cross-section deformation (the Timoshenko beam of rail.track
  holds to about 5 kHz, where the foot's flapping begins).

References
----------
D. J. Thompson, Railway Noise and Vibration: Mechanisms, Modelling and Means of Control, Elsevier,
2009, chapters 5, 6 and 9. P. M. Morse and K. U. Ingard, Theoretical Acoustics, McGraw-Hill, 1968,
section 7.3 (radiation from cylinders). EN 15461:2008+A1:2010 (track decay rate).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.special import h1vp

from ..decay import track_decay_rate
from ..track import stationary_receptance

__all__ = ["AIR_DENSITY", "SOUND_SPEED", "NEPER_DB", "RAILS_PER_AXLE", "UIC60_FOOT_WIDTH", "PER_BAND",
           "OwnTrackTransfer", "decay_length", "cylinder_radiation_ratio", "rail_radiation_efficiency",
           "rigid_wheel_receptance", "contact_force", "rail_sound_power", "own_track_transfer"]

AIR_DENSITY = 1.21  # rho [kg/m^3], air at 20 degC, 101.3 kPa
SOUND_SPEED = 343.0  # c [m/s], air at 20 degC
NEPER_DB = 20 * math.log10(math.e)  # 8.686 dB per neper of amplitude
RAILS_PER_AXLE = 2  # an axle's two wheels, each on its own rail
UIC60_FOOT_WIDTH = 0.150  # b [m], EN 13674-1 60E1 (UIC60) foot width
PER_BAND = 4  # frequencies per band of the own transfer's receptances and decay rate (docs/noise.md: its error)


def decay_length(decay_rate):
    """The rail's radiating length: int over x of exp(-2 beta abs(x)) dx = 1 / beta, both directions from
    the contact, beta = Delta / 8.686 Np/m.

    Parameters
    ----------
    decay_rate : array-like
        Track decay rate Delta [dB/m], > 0 (of the amplitude: abs(v(x)) falls by Delta dB per metre).

    Returns
    -------
    ndarray
        1 / beta = 8.686 / Delta [m].

    Raises
    ------
    ValueError
        For a decay rate that is not finite and > 0 (the length would be infinite or negative).
    """
    d = np.asarray(decay_rate, dtype=float)
    if not (np.all(np.isfinite(d)) and np.all(d > 0)):
        raise ValueError(f"decay_rate = {d.tolist()!r} dB/m is not allowed: a track decay rate must be finite and > 0.")
    return NEPER_DB / d


def cylinder_radiation_ratio(ka):
    """Radiation ratio of a rigid circular cylinder oscillating transversely (a 2D line dipole) in free
    field, sigma = 2 / (pi ka abs(H_1'(ka))^2), normalised by the mean-square normal velocity over its
    surface: (pi / 2)(ka)^3 for ka << 1, 1 for ka >> 1 (Morse & Ingard 1968, sec. 7.3).

    Parameters
    ----------
    ka : array-like
        Helmholtz number k a [-], > 0 (k = omega / c, a the radius).

    Returns
    -------
    ndarray
        sigma [-].
    """
    x = np.asarray(ka, dtype=float)
    return 2.0 / (np.pi * x * np.abs(h1vp(1, x)) ** 2)


def rail_radiation_efficiency(frequency, foot_width: float = UIC60_FOOT_WIDTH, sound_speed: float = SOUND_SPEED):
    """Radiation ratio of the rail's vertical vibration per metre, W' = rho c (2 b) sigma <v^2>: the
    oscillating cylinder of cylinder_radiation_ratio with the radius a = 2 b / pi whose high-frequency
    limit, rho c (pi a / 2) abs(v)^2 = rho c (2 b) <v^2>, is the rail section's (module docstring).

    Parameters
    ----------
    frequency : array-like
        f [Hz], > 0.
    foot_width : float
        b [m], > 0: the rail's foot width (UIC60: 0.150 m).
    sound_speed : float
        c [m/s], > 0.

    Returns
    -------
    ndarray
        sigma [-] of the rail's mean-square vertical velocity over the radiating width 2 b.
    """
    a = 2 * foot_width / np.pi
    return cylinder_radiation_ratio(2 * np.pi * np.asarray(frequency, dtype=float) * a / sound_speed)


def rigid_wheel_receptance(omega, mass: float):
    """Receptance of a rigid wheel, -1 / (M omega^2) (rail.interaction's wheel).

    Parameters
    ----------
    omega : array-like
        Angular frequency [rad/s], != 0.
    mass : float
        M [kg], > 0 (wheels.mass).

    Returns
    -------
    ndarray
        alpha_W [m/N].
    """
    w = np.asarray(omega, dtype=float)
    return -1.0 / (mass * w**2)


def contact_force(roughness, alpha_wheel, alpha_rail, alpha_contact):
    """Contact force amplitude from a roughness through the receptances at the contact,
    abs(F) = abs(r) / abs(alpha_W + alpha_R + alpha_C) (rail.interaction's eq. 21 for one wheel, no parametric
    excitation; Thompson 2009, ch. 5).

    Parameters
    ----------
    roughness : array-like
        abs(r), roughness amplitude or rms [m].
    alpha_wheel : array-like
        Wheel receptance at the contact [m/N].
    alpha_rail : array-like
        Rail point receptance at the contact [m/N].
    alpha_contact : array-like
        Contact spring receptance 1 / k_H [m/N].

    Returns
    -------
    ndarray
        abs(F) [N] (an amplitude for an amplitude, an rms for an rms).
    """
    return np.abs(np.asarray(roughness, dtype=float)) / np.abs(np.asarray(alpha_wheel) + np.asarray(alpha_rail)
                                                               + np.asarray(alpha_contact))


def rail_sound_power(velocity_mean_square, decay_rate, sigma, foot_width: float = UIC60_FOOT_WIDTH,
                     density: float = AIR_DENSITY, sound_speed: float = SOUND_SPEED):
    """Sound power of one rail radiating as a line source over its decay length,
    W = rho c (2 b) sigma <v_0^2> / beta, beta = Delta / 8.686 (module docstring).

    Parameters
    ----------
    velocity_mean_square : array-like
        <v_0^2>, the rail's mean-square vertical velocity at the contact [m^2/s^2] (abs(v_0)^2 / 2 for an
        amplitude v_0; abs(v_0)^2 for an rms).
    decay_rate : array-like
        Delta [dB/m], > 0.
    sigma : array-like
        Radiation ratio over the width 2 b [-] (rail_radiation_efficiency).
    foot_width : float
        b [m].
    density : float
        rho [kg/m^3] of air.
    sound_speed : float
        c [m/s] of air.

    Returns
    -------
    ndarray
        W [W].
    """
    return density * sound_speed * 2 * foot_width * np.asarray(sigma) * np.asarray(velocity_mean_square) * decay_length(decay_rate)


@dataclass(frozen=True)
class OwnTrackTransfer:
    """The track's own transfer function per one-third-octave band (own_track_transfer).

    frequency     : nominal band centres [Hz]
    transfer      : L_H,TR,own [dB re 1 pW per axle for 0 dB re 1 um], per band
    excitation    : the contact positions x_0 [m] from a support (above a sleeper, mid-span)
    decay_rate    : Delta [dB/m], (excitation, band), EN 15461 with the bay-sampled positions
    mobility_dB   : band mean of abs(i omega alpha_R)^2 at x_0 [dB re 1 (m/s/N)^2], (excitation, band)
    force_dB      : band mean of abs(F)^2 for 1 um rms [dB re 1 N^2], (excitation, band)
    velocity_dB   : band mean of <v_0^2> for 1 um rms [dB re 1 (m/s)^2], (excitation, band)
    sigma         : band mean of the rail's radiation ratio [-], per band
    power_rail_dB : W_rail at each x_0 for 1 um rms [dB re 1 pW], (excitation, band)
    per_band      : frequencies averaged per band [-]
    description   : the model in words (the dataset's attribute)
    """

    frequency: np.ndarray
    transfer: np.ndarray
    excitation: np.ndarray
    decay_rate: np.ndarray
    mobility_dB: np.ndarray
    force_dB: np.ndarray
    velocity_dB: np.ndarray
    sigma: np.ndarray
    power_rail_dB: np.ndarray
    per_band: int
    description: str


DESCRIPTION = ("own: the rail's sound power per axle from the scenario's track (rail.noise.own_track): contact force "
               "|r| / |alpha_W + alpha_R + alpha_C| (rigid wheel of wheels.mass, the scenario's damped contact spring, rail point receptance), "
               "rail velocity i omega alpha_R F, line source over the EN 15461 decay length 8.686/Delta (bay-sampled positions), "
               "radiation ratio of a transversely oscillating cylinder of radius 2b/pi (b = foot width 0.150 m), two rails per axle, "
               "averaged over the contact above a sleeper and at mid-span; sleepers and lateral vibration not included; "
               "L_H,TR,own = 10 lg(W_axle(1 um rms) / 1 pW)")


def own_track_transfer(track, wheel_mass: float, contact, f_min: float = 50.0, f_max: float = 10000.0,
                       per_band: int = PER_BAND, decay=None, foot_width: float = UIC60_FOOT_WIDTH) -> OwnTrackTransfer:
    """The track's own transfer function L_H,TR,own per one-third-octave band from f_min to f_max
    (module docstring): the rail receptance at the contact and the EN 15461 decay rate of the track
    model (rail.decay.track_decay_rate, both computed here unless ``decay`` is given).

    Parameters
    ----------
    track : rail.track.Track
        The scenario's track.
    wheel_mass : float
        M [kg], > 0 (wheels.mass): the rigid wheel's receptance -1/(M omega^2).
    contact : rail.interaction.ContactSpring
        The scenario's linearised Hertz spring k_H (1 + i eta_H(omega)) [N/m] (contact.hertz_stiffness
        with its loss factor model): alpha_C = 1 / (its stiffness).
    f_min, f_max : float
        Lowest and highest nominal band centre [Hz] (default 50 Hz .. 10 kHz: CNOSSOS-EU's 24 bands).
    per_band : int
        Frequencies averaged per band [-] (default PER_BAND = 4).
    decay : rail.decay.DecayRate, optional
        The track's decay rate on these bands, excited above a sleeper and at mid-span (computed with
        rail.decay.track_decay_rate(track, f_min=f_min, f_max=f_max, per_band=per_band) if not given;
        about 4 minutes for the 24 bands on one core).
    foot_width : float
        b [m] of the rail's radiation (UIC60: 0.150 m).

    Returns
    -------
    OwnTrackTransfer
        L_H,TR,own [dB re 1 pW per axle] per band and its pieces.

    Raises
    ------
    ValueError
        Naming the parameter for a wheel mass or foot width that is not finite and > 0, or a decay
        rate given on other bands.
    """
    for name, v in (("wheels.mass", wheel_mass), ("foot_width", foot_width)):
        if not (isinstance(v, (int, float, np.floating)) and math.isfinite(v) and v > 0):
            raise ValueError(f"{name} = {v!r} is not allowed: it must be a finite number > 0.")
    if decay is None:
        decay = track_decay_rate(track, f_min=f_min, f_max=f_max, per_band=per_band)
    nominal = decay.bands.nominal
    if not (np.isclose(nominal[0], f_min, rtol=0.03) and np.isclose(nominal[-1], f_max, rtol=0.03)):
        raise ValueError(f"decay: the decay rate is given on {nominal[0]:g} .. {nominal[-1]:g} Hz, not on the bands "
                         f"{f_min:g} .. {f_max:g} Hz asked for.")
    k = decay.schemes.index("bay_sampled") if "bay_sampled" in decay.schemes else 0
    rate = decay.decay_rate[k]  # (excitation, band)
    x0 = decay.excitation
    f = decay.frequencies  # (band, per_band)
    omega = 2 * np.pi * f
    alpha_r = np.empty((x0.size,) + f.shape, dtype=complex)
    for idx in np.ndindex(f.shape):
        alpha_r[(slice(None),) + idx] = stationary_receptance(x0, x0, omega[idx], track, rtol=1e-6)
    alpha_w = rigid_wheel_receptance(omega, wheel_mass)
    r = 1e-6  # 1 um rms
    force = contact_force(r, alpha_w, alpha_r, 1.0 / contact.stiffness(omega))  # rms [N], (excitation, band, per_band)
    mobility2 = np.abs(1j * omega * alpha_r) ** 2
    v2 = mobility2 * force**2  # <v_0^2> [m^2/s^2]
    sigma = rail_radiation_efficiency(f, foot_width)
    power = rail_sound_power((sigma * v2).mean(axis=-1), rate, 1.0, foot_width)  # W per rail, (excitation, band)
    axle = RAILS_PER_AXLE * power.mean(axis=0)
    return OwnTrackTransfer(frequency=np.asarray(nominal, dtype=float), transfer=10 * np.log10(axle / 1e-12), excitation=x0,
                            decay_rate=rate, mobility_dB=10 * np.log10(mobility2.mean(axis=-1)),
                            force_dB=10 * np.log10((force**2).mean(axis=-1)), velocity_dB=10 * np.log10(v2.mean(axis=-1)),
                            sigma=sigma.mean(axis=-1), power_rail_dB=10 * np.log10(power / 1e-12), per_band=int(decay.frequencies.shape[1]),
                            description=DESCRIPTION)
