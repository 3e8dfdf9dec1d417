"""Rolling noise over traffic: the CNOSSOS-EU noise at every save of a growth run (one train or a
fleet), its change since the start, and grinding by noise (issue 56; docs/noise.md). The one code path
of the workflow (rules growth_noise and fleet_noise), the command line (railgrowth noise) and the API
(rail.app.api.noise).

Conventions
-----------
* The rail roughness on CNOSSOS-EU's 35 wavelength bands is the run's lines summed per band
  (rail.studies.bands.band_mean_square, as the rolling-noise export); a band the run does not
  resolve is filled (the input spectrum of a kind: spectrum start, else Table G-1b's ``fill``
  class), a resolved band where the rail is smooth is silence (-inf dB), never filled.
* The traffic of a one-train run is one vehicle class: the scenario's wheel (diameter 2 x
  wheels.radius, load wheels.static_load), figures.noise's axles, wheel roughness and flow, at the
  run's speed. A fleet's is one class per (vehicle type, speed class), rail.noise.rolling.fleet_traffic:
  its own speed, flow, axles, wheel load and brake; the line's levels are the energy sum over the
  classes (Annex II 2.3.2), per class and total in the dataset, the criteria on the total. The track
  is figures.noise's sleeper with the pad class of track.pad.stiffness (or the one named).
* Levels: roughness dB re 1 um, sound power dB re 1 pW, line sound power dB re 1 pW/m; the
  A-weighted totals in dB(A); changes in dB. Passages are axle (wheel) passages on the rail; years
  and MGT from the traffic (rail.traffic).
* Grinding by noise (rail.noise.grinding): (a) the rise of the A-weighted line sound power over the
  start, (b) its energy mean over the grinding cycle against a target, (c) the rms roughness over
  Grassie, Saxon & Smith's wavelength ranges; interpolated between saves, extrapolated (each band by
  its law, never a decay) at most figures.noise.extrapolation_max times the run's passages.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..noise import cnossos as cn
from ..noise import grinding as gr
from ..noise import own_track
from ..noise import rolling as rn
from ..noise.tables import SOURCES
from ..noise.weighting import a_weighting
from .bands import band_mean_square, readable_count

__all__ = ["NoiseOutputs", "CRITERIA", "noise_outputs", "noise_csv_text", "trip_text", "change_line"]

# the criteria, their names in the dataset's attributes and in words
CRITERIA = {"rise": "rise of the A-weighted line sound power over the start",
            "average": "cycle-averaged A-weighted line sound power",
            "band_rms": "rms roughness in a wavelength range (Grassie, Saxon & Smith 1999)"}


@dataclass(frozen=True)
class NoiseOutputs:
    """The noise over traffic of a growth run (noise_outputs).

    data  : xarray.Dataset (passage, frequency, wavelength, rms_range), units and long names on every variable
    csv   : the noise export (noise_csv_text)
    trips : {criterion: rail.noise.grinding.Trip}
    """

    data: object
    csv: str
    trips: dict


def _pad(cfg: dict, settings, own):
    """The track of a scenario's noise and how its pad class was chosen (own: the track's own transfer,
    rail.noise.own_track.OwnTrackTransfer, in place of Table G-3a's)."""
    pad, pad_rule = settings.pad_class, "figures.noise.pad_class"
    if own is not None:
        pad, pad_rule = None, "not used: the track's own transfer (figures.noise.track_transfer: own)"
    elif settings.sleeper in ("monoblock", "biblock") and pad is None:
        pad, pad_rule = cn.pad_class(cfg["track"]["pad"]["stiffness"]), "from track.pad.stiffness"
    elif settings.sleeper not in ("monoblock", "biblock"):
        pad, pad_rule = None, f"none ({settings.sleeper})"
    track = rn.Track(settings.sleeper, pad) if own is None else rn.Track(settings.sleeper, None, own=tuple(own.transfer))
    return track, pad_rule


def _vehicle_traffic(cfg: dict, settings, speed: float):
    """The one vehicle class of a one-train run and its flow: (classes, shares)."""
    per_day = (cfg.get("traffic") or {}).get("axles_per_day")
    q = settings.vehicles_per_hour
    if q is None:
        if not per_day:
            raise ValueError("no traffic: give traffic.axles_per_day or figures.noise.vehicles_per_hour.")
        q = float(per_day) / 24.0 / settings.axles_per_vehicle
    vehicle = rn.Vehicle("vehicle", axles=settings.axles_per_vehicle, brake=settings.wheel,
                         wheel_diameter=2 * float(cfg["wheels"]["radius"]), wheel_load=float(cfg["wheels"]["static_load"]))
    return (rn.TrafficClass(vehicle, float(q), speed),), (1.0,)


def _rail_dB(ms):
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(np.isfinite(ms), 10 * np.log10(np.where(np.isfinite(ms), np.maximum(ms, 0.0), 1.0) / 1e-12), np.nan)


def trip_text(trip, label: str, traffic, speed: float, unit: str) -> str:
    """A criterion's trip in words: when (axle passages, years, MGT), whether extrapolated and by what
    factor, and the band that drives it; or why it is not reached or not assessed.

    Parameters
    ----------
    trip : rail.noise.grinding.Trip
        The criterion's trip (its status, passages [-], threshold, extrapolation factor [-], note).
    label : str
        The criterion in words.
    traffic : rail.noise.Traffic or None
        Converts axle passages to years and MGT (None: no traffic given).
    speed : float
        Train speed [m/s].
    unit : str
        The threshold's unit (dB(A), um rms).

    Returns
    -------
    str
    """
    if trip.status == "not assessed":
        return f"{label}: not assessed ({trip.note})"
    if trip.status == "not reached":
        return f"{label} {trip.threshold:g} {unit}: not reached ({trip.note})"
    when = (f" ({float(traffic.years(trip.passages)):.3g} years, {float(traffic.mgt(trip.passages)):.3g} MGT)"
            if traffic is not None else "")
    how = {"at the start": "already at the start", "within the run": "within the run",
           "extrapolated": f"extrapolated {trip.extrapolation_factor:.3g} x the run's passages"}[trip.status]
    return f"{label} {trip.threshold:g} {unit}: tripped after {readable_count(trip.passages)} axle passages{when}, {how}; {trip.note}"


def _driver_text(trip, speed: float, fbands, wbands, limits, at: str = "") -> str:
    if trip.band_index < 0:
        return ""
    if trip.criterion == "band_rms":
        lo, hi, lim = limits[trip.range_index]
        return (f"driven by the {1e3 * lo:g}-{1e3 * hi:g} mm range (limit {1e6 * lim:g} um rms), its "
                f"{1e3 * wbands.nominal[trip.band_index]:g} mm band the largest")
    f = float(fbands.nominal[trip.band_index])
    why = "the loudest A-weighted band at the start" if trip.status == "at the start" else "its A-weighted power rose most"
    return (f"driven by the {f:g} Hz band ({why}; wavelength {1e3 * speed / fbands.centre[trip.band_index]:.3g} mm "
            f"at {at}{speed:g} m/s)")


def change_line(ds) -> str:
    """One line: the A-weighted line sound power at the start and the last save and its change, and
    the first noise criterion that trips (the run summary of railgrowth run and the growth_noise log).

    Parameters
    ----------
    ds : xr.Dataset
        The noise over traffic (rail.studies.noise): line_sound_power_A [dB(A) re 1 pW] per passage, the criteria's attributes.

    Returns
    -------
    str
    """
    n, L = ds["passage"].values, ds["line_sound_power_A"].values
    tripped = sorted((ds.attrs[f"grinding_noise_{c}_passages"], ds.attrs[f"grinding_noise_{c}_text"]) for c in CRITERIA
                     if ds.attrs.get(f"grinding_noise_{c}_status") in ("at the start", "within the run", "extrapolated"))
    first = f"first to trip: {tripped[0][1]}" if tripped else "no noise criterion trips"
    where = (f"fleet of {ds.sizes['traffic_class']} classes at {_speeds_text(ds)} m/s" if "fleet_speeds" in ds.attrs
             else f"{ds.attrs['speed_m_per_s']:g} m/s")
    return (f"noise (CNOSSOS-EU, {where}): L'_W,A {L[0]:.1f} dB(A) re 1 pW/m at the start, {L[-1]:.1f} at "
            f"{readable_count(n[-1])} axle passages, change {L[-1] - L[0]:+.2f} dB; {first}")


def _speeds_text(ds) -> str:
    v = sorted({float(x) for x in ds["class_speed"].values})
    return f"{v[0]:g}" if len(v) == 1 else f"{v[0]:g}-{v[-1]:g}"


def _cnossos_transfer(cfg: dict, settings):
    """Table G-3a's L_H,TR of the scenario's sleeper and pad class, or None where the pad has no class."""
    pad = settings.pad_class
    try:
        if settings.sleeper in ("monoblock", "biblock") and pad is None:
            pad = cn.pad_class(cfg["track"]["pad"]["stiffness"])
        return cn.track_transfer(settings.sleeper, pad if settings.sleeper in ("monoblock", "biblock") else None), pad
    except ValueError:
        return None, None


def noise_outputs(growth, cfg: dict, scn, name: str, settings, *, initial_spectrum=None, traffic=None,
                  own_transfer=None, fleet=None) -> NoiseOutputs:
    """The noise over traffic of a one-train or a fleet's growth run (module docstring).

    Parameters
    ----------
    growth : xarray.Dataset
        A growth result: Z_real, Z_imag per saved passage count; attributes speed_m_per_s, bays (a
        fleet's run: fleet_speeds as well, and speed_m_per_s its mean speed).
    cfg : dict
        The scenario's resolved configuration (wheels, track.pad, traffic, figures.bands.min_lines).
    scn : rail.scenario.Scenario
        Its sleeper spacing L.
    name : str
        The scenario, for the export's header.
    settings : rail.setup.build.NoiseSettings
    initial_spectrum : (wavelength [m], level [dB re 1 um], source), optional
        The initial roughness's input spectrum: fills the bands the run does not resolve.
    traffic : rail.traffic.Traffic, optional
        Years and MGT.
    own_transfer : rail.noise.own_track.OwnTrackTransfer, optional
        With figures.noise.track_transfer: own, the track's own transfer on the 24 bands (computed
        from scn's track, wheels.mass and contact spring if not given: about 4 minutes, the decay rate).
    fleet : rail.fleet.Fleet, optional
        The fleet of a fleet's growth run (rail.setup.build.fleet of cfg; required for one, refused for
        a one-train run): each (vehicle, speed) class a traffic class (rail.noise.rolling.fleet_traffic), the line's
        L'_W,eq,line the energy sum over them (Annex II 2.3.2), the grinding criteria on that total.

    Returns
    -------
    NoiseOutputs

    Raises
    ------
    ValueError
        A fleet run without its fleet; a speed (a fleet's class speed) outside CNOSSOS-EU's 7.94 .. 100 m/s;
        a pad stiffness without a class; no traffic; a band the speed reads with no level (naming it).
    """
    import xarray as xr

    from ..setup.io import data_var
    from .exports import spectrum_on_bands

    if "speed_m_per_s" not in growth.attrs:
        raise ValueError("the growth result has no attribute speed_m_per_s: give the dataset a growth run writes.")
    is_fleet = "fleet_speeds" in growth.attrs
    if is_fleet != (fleet is not None):
        raise ValueError("the growth result is a fleet's run but no fleet was given (rail.setup.build.fleet of its configuration)"
                         if is_fleet else "a fleet was given but the growth result is a one-train run (no attribute fleet_speeds).")
    if is_fleet:
        classes, shares = rn.fleet_traffic(fleet, settings.fleet_brakes, 2 * float(cfg["wheels"]["radius"]), settings.vehicles_per_hour)
        speed = float(growth.attrs["speed_m_per_s"])  # the fleet's mean speed: named in the texts only
    else:
        speed = cn.check_speed(float(growth.attrs["speed_m_per_s"]), "growth speed")
        classes, shares = _vehicle_traffic(cfg, settings, speed)
    own = None
    if settings.track_transfer == "own":
        own = own_transfer if own_transfer is not None else own_track.own_track_transfer(scn.track, scn.wheels.mass, scn.spring)
        if own.transfer.shape != (24,):
            raise ValueError(f"own_transfer holds {own.transfer.size} bands: the track's own transfer must cover the 24 bands "
                             "50 Hz .. 10 kHz (rail.noise.own_track.own_track_transfer's default range).")
    track, pad_rule = _pad(cfg, settings, own)
    wbands, fbands = cn.cnossos_wavelength_bands(), cn.cnossos_frequency_bands()
    period = int(growth.attrs.get("bays", 1)) * scn.L
    Z = growth["Z_real"].values + 1j * growth["Z_imag"].values
    ms, resolved = band_mean_square(Z, period, wbands, int(cfg["figures"]["bands"]["min_lines"]))
    if initial_spectrum is not None:
        fill_dB, fill_source = spectrum_on_bands(initial_spectrum[0], initial_spectrum[1]), f"input spectrum {initial_spectrum[2]}"
    elif settings.fill is not None:
        fill_dB, fill_source = cn.rail_roughness_class(settings.fill), f"CNOSSOS-EU Table G-1b class {settings.fill}"
    else:
        fill_dB, fill_source = np.full(35, np.nan), ""
    take = ~resolved & np.isfinite(fill_dB)
    fill_ms = np.where(take, 1e-12 * 10 ** (np.where(take, fill_dB, 0.0) / 10), np.nan)
    source = np.where(resolved, "model", np.where(take, fill_source, ""))
    n = growth["passage"].values.astype(float)
    trend = gr.band_trend(n, ms, fill_ms)
    nominal = fbands.nominal
    weight = a_weighting(nominal)

    def level_of(m):
        r = rn.rolling_noise(_rail_dB(m), track, classes, rule=settings.rule)
        return r.line_power_A, r.line_power_total + weight

    results = [rn.rolling_noise(_rail_dB(trend.mean_square(x)), track, classes, rule=settings.rule) for x in n]
    rail = np.array([_rail_dB(trend.mean_square(x)) for x in n])
    curve = gr.noise_curve(trend, level_of, settings.extrapolation_max)
    trips = {"rise": gr.trip_rise(trend, curve, level_of, settings.rise_dB)}
    if settings.average_target_dBA is not None:
        trips["average"] = gr.trip_average(trend, curve, settings.average_target_dBA)
    if settings.band_rms:
        trips["band_rms"] = gr.trip_band_rms(trend, curve, wbands.centre)

    def stack(field):  # per vehicle: (passage, frequency) for one train, (passage, traffic_class, frequency) for a fleet
        return np.array([getattr(x, field) if is_fleet else getattr(x, field)[0] for x in results])

    per_vehicle = ("passage", "traffic_class", "frequency") if is_fleet else ("passage", "frequency")

    line_A = np.array([x.line_power_A for x in results])
    limits = gr.GRASSIE_1999
    in_range = [gr.range_bands(wbands.centre, lo, hi) for lo, hi, _ in limits]
    rms = np.array([[math.sqrt(np.nansum(trend.mean_square(x)[m])) for m in in_range] for x in n])
    assessed = np.array([bool((m & trend.model).any()) for m in in_range])
    rms = np.where(assessed, rms, np.nan)
    years = traffic.years(n) if traffic is not None else np.full(n.size, np.nan)
    mgt = traffic.mgt(n) if traffic is not None else np.full(n.size, np.nan)
    units = {"rise": "dB", "average": "dB(A) re 1 pW/m", "band_rms": "m rms"}
    attrs = {}
    for c, label in CRITERIA.items():
        t = trips.get(c)
        if t is None:
            why = {"average": "no figures.noise.average_target_dBA given", "band_rms": "figures.noise.band_rms is false"}[c]
            t = gr.Trip(c, math.nan, math.nan, "not assessed", math.nan, -1, note=why)
            trips[c] = t
        drv = _driver_text(t, speed, fbands, wbands, limits, "the fleet's mean speed " if is_fleet else "")
        t_note = "; ".join(x for x in (drv, t.note) if x)
        shown = gr.Trip(t.criterion, t.threshold * (1e6 if c == "band_rms" else 1), t.passages, t.status, t.extrapolation_factor,
                        t.band_index, t.range_index, t_note)
        attrs.update({
            f"grinding_noise_{c}_threshold": float(t.threshold),
            f"grinding_noise_{c}_threshold_units": units[c],
            f"grinding_noise_{c}_passages": float(t.passages),
            f"grinding_noise_{c}_years": float(traffic.years(t.passages)) if traffic is not None else math.nan,
            f"grinding_noise_{c}_MGT": float(traffic.mgt(t.passages)) if traffic is not None else math.nan,
            f"grinding_noise_{c}_status": t.status,
            f"grinding_noise_{c}_extrapolation_factor": float(t.extrapolation_factor),
            f"grinding_noise_{c}_driver": drv,
            f"grinding_noise_{c}_text": trip_text(shown, label, traffic, speed, "um rms" if c == "band_rms" else units[c]),
        })
    attrs["grinding_noise_horizon_passages"] = float(curve.end)
    attrs["grinding_noise_definition"] = (
        "axle passages until the criterion is exceeded (strictly above): the bands' rms amplitudes interpolated in ln amplitude "
        "between the saves and the noise computed from them; beyond the last save each resolved band grown by its own law "
        "(rail.growth.band_growth, from its last level; a band whose rate is <= 0 held, never decayed) at most "
        f"{settings.extrapolation_max:g} x the run's passages (the factor stated); inf: not reached; NaN: not assessed "
        "(rail.noise.grinding)")
    g3a, g3a_pad = _cnossos_transfer(cfg, settings)
    transfer_vars = {"track_transfer": data_var("frequency", track.transfer(), "dB re 1 pW",
                                                "track transfer function per axle for a total effective roughness of 0 dB re 1 um "
                                                + ("(the track's own: rail.noise.own_track)" if own is not None else
                                                   f"L_H,TR (Table G-3a, {settings.sleeper}, pad {track.pad})"))}
    if own is not None:
        if g3a is not None:
            transfer_vars["track_transfer_cnossos"] = data_var(
                "frequency", g3a, "dB re 1 pW", f"Table G-3a's L_H,TR of the scenario's sleeper ({settings.sleeper}) and pad class "
                f"({g3a_pad}), for comparison (not used)")
        transfer_vars.update({
            "own_track_decay_rate": data_var(("contact_position", "frequency"), own.decay_rate, "dB/m",
                                             "vertical track decay rate Delta (EN 15461, bay-sampled positions; rail.decay) at the contact"),
            "own_track_force": data_var(("contact_position", "frequency"), own.force_dB, "dB re 1 N",
                                        "band mean of the contact force |F|^2 for a roughness of 1 um rms"),
            "own_track_rail_mobility": data_var(("contact_position", "frequency"), own.mobility_dB, "dB re 1 m/(s N)",
                                                "band mean of the rail's point mobility |i omega alpha_R|^2 at the contact"),
            "own_track_radiation_ratio": data_var("frequency", own.sigma, "1",
                                                  "rail radiation ratio sigma over the width 2 x foot width (band mean)"),
            "own_track_rail_power": data_var(("contact_position", "frequency"), own.power_rail_dB, "dB re 1 pW",
                                             "sound power of one rail for a roughness of 1 um rms, contact at the position"),
        })
    ds = xr.Dataset(
        {
            **transfer_vars,
            "rail_roughness": data_var(("passage", "wavelength"), rail, "dB re 1 um",
                                       "rail roughness level per CNOSSOS-EU wavelength band (NaN: no level; -inf: smooth)"),
            "rail_roughness_source": data_var("wavelength", source.astype(str), "",
                                              "where the band's rail roughness comes from ('model': the growth run)"),
            "total_effective_roughness": data_var(per_vehicle, stack("roughness_total"), "dB re 1 um",
                                                  "total effective roughness L_R,TOT (2.3.7) per frequency band"),
            "sound_power_track": data_var(per_vehicle, stack("power_track"), "dB re 1 pW",
                                          "rolling-noise sound power of the track per vehicle L_W,0,TR (2.3.8)"),
            "sound_power_vehicle": data_var(per_vehicle, stack("power_vehicle"), "dB re 1 pW",
                                            "rolling-noise sound power of the vehicle per vehicle L_W,0,VEH (2.3.9)"),
            "sound_power": data_var(per_vehicle, stack("power"), "dB re 1 pW",
                                    "rolling-noise sound power per vehicle, track + vehicle, broadside"),
            "line_sound_power": data_var(("passage", "frequency"), np.array([x.line_power_total for x in results]), "dB re 1 pW/m",
                                         "directional sound power per metre of line L'_W,eq,line (2.3.2) of the traffic: the energy "
                                         "sum over its classes, broadside"),
            "sound_power_A": data_var(per_vehicle[:-1], np.array([x.power_A if is_fleet else x.power_A[0] for x in results]),
                                      "dB(A) re 1 pW", "A-weighted rolling-noise sound power per vehicle"),
            "line_sound_power_class": data_var(("passage", "traffic_class", "frequency"), np.array([x.line_power for x in results]),
                                               "dB re 1 pW/m", "directional sound power per metre of line L'_W,eq,line of the class "
                                               "(2.3.2), broadside"),
            "line_sound_power_A_class": data_var(("passage", "traffic_class"), np.array([x.line_power_class_A for x in results]),
                                                 "dB(A) re 1 pW/m", "A-weighted sound power per metre of line of the class"),
            "line_sound_power_A": data_var("passage", line_A, "dB(A) re 1 pW/m",
                                           "A-weighted sound power per metre of line of the traffic"),
            "line_sound_power_A_change": data_var("passage", line_A - line_A[0], "dB",
                                                  "change of the A-weighted line sound power since the first save (the start)"),
            "line_sound_power_A_cycle_average": data_var("passage", curve.average[curve.saves], "dB(A) re 1 pW/m",
                                                         "energy mean of the A-weighted line sound power from the start to the save "
                                                         "(the grinding cycle's average, criterion b)"),
            "band_rms": data_var(("passage", "rms_range"), rms * 1e6, "um",
                                 "rms roughness over the wavelength range: sqrt of the sum of its bands' mean squares (NaN: not "
                                 "assessed, no band of the range is the model's)"),
            "band_rms_model_bands": data_var("rms_range", np.array([int((m & trend.model).sum()) for m in in_range]), "1",
                                             "bands of the range the growth run gives (the others filled: rail_roughness_source)"),
            "band_rms_bands": data_var("rms_range", np.array([int(m.sum()) for m in in_range]), "1",
                                       "CNOSSOS-EU bands of the range (exact centres in [low, high))"),
            "band_rms_limit": data_var("rms_range", np.array([lim for _, _, lim in limits]) * 1e6, "um",
                                       "rms limit of the range (Grassie, Saxon & Smith 1999)"),
        },
        coords={
            "passage": data_var("passage", n, "1", "axle passages (wheel passages on the rail)"),
            "years": data_var("passage", years, "year", "years of traffic"),
            "mgt": data_var("passage", mgt, "Mt", "million gross tonnes of traffic"),
            "frequency": data_var("frequency", nominal.astype(float), "Hz", "nominal one-third-octave centre frequency"),
            "a_weighting": data_var("frequency", weight, "dB", "A-weighting of the band (IEC 61672-1 Table 3)"),
            "wavelength": data_var("wavelength", wbands.nominal, "m", "CNOSSOS-EU nominal centre wavelength (Table G-1b)"),
            "centre_wavelength": data_var("wavelength", wbands.centre, "m", "exact centre wavelength 10^(-n/10) m"),
            **({"contact_position": data_var("contact_position", own.excitation, "m",
                                             "contact position x_0 from a sleeper (0: above a sleeper, L/2: mid-span)")}
               if own is not None else {}),
            **_class_coords(classes, shares),
            "rms_range_low": data_var("rms_range", np.array([lo for lo, _, _ in limits]), "m", "shortest wavelength of the range"),
            "rms_range_high": data_var("rms_range", np.array([hi for _, hi, _ in limits]), "m",
                                       "longest wavelength of the range (bands with exact centres in [low, high))"),
        },
        attrs={
            "method": "CNOSSOS-EU railway rolling noise, Directive 2002/49/EC Annex II 2.3 (2015/996, corrigendum 2018, "
                      "Delegated Directive (EU) 2021/1226); rail.noise, rail.studies.noise, docs/noise.md",
            "speed_m_per_s": speed, "vehicles_per_hour": float(sum(c.vehicles_per_hour for c in classes)),
            **(_fleet_attrs(growth, classes) if is_fleet else {"axles_per_vehicle": int(settings.axles_per_vehicle), "brake": settings.wheel}),
            "sleeper": settings.sleeper,
            "pad_class": str(track.pad), "pad_class_rule": pad_rule,
            "track_transfer": settings.track_transfer,
            "track_transfer_model": (own.description + (f"; {own.per_band} frequencies per band; the scenario's nominal track"
                                                        + (" (the cell's mean spacing)" if scn.cell is not None else ""))
                                     if own is not None else "cnossos: Table G-3a's L_H,TR of the sleeper and pad class"),
            "contact_filter_column_kN_mm": " | ".join(str(x) for x in results[0].contact_columns) if is_fleet
            else str(results[0].contact_columns[0]),
            "vehicle_transfer_diameter_mm": float(results[0].diameters[0]),
            "interpolation_rule": settings.rule, "directivity": "broadside (phi = 90 deg, psi = 0): 0 dB",
            "fill": fill_source or "none", "notes": results[0].notes, "bays": int(growth.attrs.get("bays", 1)),
            **({k: v for k, v in traffic.attributes().items()} if traffic is not None else {}),
            **attrs,
            **{f"source_{k.lower()}": v for k, v in SOURCES.items()},
        },
    )
    return NoiseOutputs(ds, noise_csv_text(ds, name), trips)


def _class_coords(classes, shares) -> dict:
    """The traffic classes' coordinates: vehicle, speed, flow, axles, wheel roughness, wheel load, share."""
    from ..setup.io import data_var

    def brake(c):
        return c.vehicle.brake if isinstance(c.vehicle.brake, str) else "spectrum"

    return {"traffic_class": data_var("traffic_class", np.arange(len(classes)), "1", "traffic class (vehicle type at a speed)"),
            "class_name": data_var("traffic_class", np.array([c.vehicle.name for c in classes]), "", "the class: vehicle type at speed"),
            "class_speed": data_var("traffic_class", np.array([c.speed for c in classes]), "m/s", "speed of the class"),
            "class_vehicles_per_hour": data_var("traffic_class", np.array([c.vehicles_per_hour for c in classes]), "1/h",
                                                "vehicles per hour Q of the class (2.3.2)"),
            "class_axles": data_var("traffic_class", np.array([c.vehicle.axles for c in classes]), "1", "axles per vehicle N_a"),
            "class_wheel_roughness": data_var("traffic_class", np.array([brake(c) for c in classes]), "",
                                              "wheel roughness L_r,VEH of the class (Table G-1a by brake type)"),
            "class_wheel_load": data_var("traffic_class", np.array([c.vehicle.wheel_load for c in classes]), "N",
                                         "static wheel load of the class (Table G-2's column with the diameter)"),
            "class_share": data_var("traffic_class", np.array(shares), "1", "share of the trains that are the class")}


def _fleet_attrs(growth, classes) -> dict:
    """A fleet's noise attributes: its definitions (the growth file's) and its classes in words."""
    return {"fleet_vehicles": growth.attrs.get("fleet_vehicles", ""), "fleet_speeds": growth.attrs["fleet_speeds"],
            "fleet_classes": " | ".join(f"{c.vehicle.name}: {c.vehicles_per_hour:.4g} vehicles/h of {c.vehicle.axles} axles, wheel "
                                        f"{c.vehicle.brake}, wheel load {c.vehicle.wheel_load:g} N" for c in classes),
            "axles_per_vehicle": "per class (fleet_classes: each vehicle's positions)",
            "brake": ", ".join(dict.fromkeys(str(c.vehicle.brake) for c in classes)) + " (per vehicle: fleet_classes)",
            "fleet_noise_definition": "each (vehicle, speed) class of the fleet a CNOSSOS-EU traffic class with its own speed, "
                                      "vehicles per hour, axles, wheel load and wheel roughness on the one rail roughness; "
                                      "L'_W,eq,line of the line the energy sum over the classes (Annex II 2.3.2); the grinding "
                                      "criteria on that total (rail.noise.rolling.fleet_traffic)"}


def _cell(v, fmt=".3f") -> str:
    return f"{v:{fmt}}" if np.isfinite(v) else ""


def noise_csv_text(ds, name: str) -> str:
    """The noise export: '#' header lines (method, speed, vehicle, track, traffic, the grinding criteria
    in words), one row per save with its axle passages, years and MGT, the A-weighted levels, their
    change, the cycle average, the band rms per range and the line sound power per frequency band;
    every column name carries its unit. An empty cell: no value (a range not assessed; no traffic).

    Parameters
    ----------
    ds : xr.Dataset
        The noise over traffic (rail.studies.noise).
    name : str
        The scenario's name.

    Returns
    -------
    str
        The CSV text.
    """
    a = ds.attrs
    fleet = "fleet_speeds" in a
    if fleet:
        cols_kN_mm = a["contact_filter_column_kN_mm"].split(" | ")
        what = [f"# a fleet: {ds.sizes['traffic_class']} traffic classes (vehicle type at a speed), the line's levels their energy sum "
                f"(CNOSSOS-EU Annex II 2.3.2); fleet speeds {a['fleet_speeds']}; {a['vehicles_per_hour']:.4g} vehicles/h in all, "
                f"vehicle transfer {a['vehicle_transfer_diameter_mm']:g} mm"]
        what += [f"# class {i}: {ds['class_name'].values[i]}, share {float(ds['class_share'].values[i]):.4g}, "
                 f"{float(ds['class_vehicles_per_hour'].values[i]):.4g} vehicles/h of {int(ds['class_axles'].values[i])} axles, "
                 f"wheel roughness {ds['class_wheel_roughness'].values[i]}, wheel load {float(ds['class_wheel_load'].values[i]):g} N, "
                 f"contact filter column {cols_kN_mm[i]} (kN, mm)" for i in range(ds.sizes["traffic_class"])]
        what.append("# every class on the one rail roughness and track")
    else:
        what = [f"# speed {a['speed_m_per_s']:g} m/s; {a['vehicles_per_hour']:.4g} vehicles/h of {a['axles_per_vehicle']} axles, wheel "
                f"roughness {a['brake']}, contact filter column {a['contact_filter_column_kN_mm']} (kN, mm), vehicle transfer "
                f"{a['vehicle_transfer_diameter_mm']:g} mm"]
    track = (f"track {a['sleeper']}, pad {a['pad_class']} ({a['pad_class_rule']})" if a.get("track_transfer", "cnossos") == "cnossos"
             else "track transfer: the track's own (rail receptance and EN 15461 decay rate, rail.noise.own_track)")
    head = [f"# rolling noise by CNOSSOS-EU at every save of the growth run of scenario {name} (rail.studies.noise; docs/noise.md)",
            *what[:-1], what[-1] + "; " + track,
            f"# rule {a['interpolation_rule']}; bands the run does not resolve: {a['fill']}; {a['directivity']}; {a['notes']}",
            "# levels: sound power dB re 1 pW, line sound power dB re 1 pW/m, A-weighted dB(A); passages are axle passages"
            + (f"; traffic {a['axles_per_day']:g} axles/day, axle load {a['axle_load_t']:.4g} t" if "axle_load_t" in a else "; no traffic")]
    head += [f"# grinding by noise: {a[f'grinding_noise_{c}_text']}" for c in CRITERIA]
    f = ds["frequency"].values
    lo, hi = ds["rms_range_low"].values, ds["rms_range_high"].values
    k = range(ds.sizes["traffic_class"]) if fleet else ()
    cols = ["axle_passages", "years", "MGT", "line_sound_power_A_dBA_re_1pW_per_m", "line_sound_power_A_change_dB",
            "line_sound_power_A_cycle_average_dBA_re_1pW_per_m"]
    cols += ([f"line_sound_power_A_class{i}_dBA_re_1pW_per_m" for i in k] + [f"sound_power_A_per_vehicle_class{i}_dBA_re_1pW" for i in k]
             if fleet else ["sound_power_A_per_vehicle_dBA_re_1pW"])
    cols += [f"band_rms_{1e3 * a_:g}_{1e3 * b_:g}mm_um" for a_, b_ in zip(lo, hi)]
    cols += [f"line_sound_power_{x:g}Hz_dB_re_1pW_per_m" for x in f]
    rows = [",".join(cols)]
    for i, p in enumerate(ds["passage"].values):
        cells = [f"{p:.0f}", _cell(float(ds["years"].values[i]), ".6g"), _cell(float(ds["mgt"].values[i]), ".6g"),
                 _cell(float(ds["line_sound_power_A"].values[i])), _cell(float(ds["line_sound_power_A_change"].values[i])),
                 _cell(float(ds["line_sound_power_A_cycle_average"].values[i]))]
        if fleet:
            cells += [_cell(float(v)) for v in ds["line_sound_power_A_class"].values[i]]
            cells += [_cell(float(v)) for v in ds["sound_power_A"].values[i]]
        else:
            cells.append(_cell(float(ds["sound_power_A"].values[i])))
        cells += [_cell(float(v), ".4g") for v in ds["band_rms"].values[i]]
        cells += [_cell(float(v)) for v in ds["line_sound_power"].values[i]]
        rows.append(",".join(cells))
    return "\n".join(head + rows) + "\n"
