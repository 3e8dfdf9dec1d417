"""The expected rail roughness under the wheels' roughness (issue 58): the growth-rate spectrum's lines with
the wheels' source Q, the level each line and band settles to, and the time from a ground rail to the
limit (rail.growth_spectrum.source; docs/wheel-source.md).

Inputs are the spectrum's dataset (rail.studies.rate_spectrum.rate_spectrum_dataset: growth_rate and drift
give the train's rate R = -(growth_rate + i drift) per train passage, ``source`` the supports' comb),
one wheel's own rate on the same lines (the wheel alone on the track, rail.chain.single_wheel; for a
one-wheel train the spectrum's own), the wheel's one-third-octave roughness, the ground rail's and the
limit. Everything is per train passage inside and per axle (wheel) passage, MGT and year outside, as
the spectrum's exports are.

Under a fleet (fleet_source_dataset): the fleet's spectrum (rail.studies.fleet.fleet_spectrum_dataset) with each
class's spectrum (R_c, the comb's s_c per passage of the class's train) and what each class file carries for the
source (class_source_arrays: each axle's own rate alone on the track, the vehicle's wheel roughness on the lines);
per fleet passage a = sum_c w_c abs(1 - R_c)^2 and Q = sum_c w_c Q_c (rail.growth_spectrum.source), per axle passage
outside (x the fleet's mean axles per train, as growth_dB_per_1e5_axles).
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from ..bands import wavelength_bands
from ..growth_spectrum import source as src
from ..noise.named import RoughnessSpectrum, named_spectrum
from ..setup.io import data_var
from ..traffic import Traffic

__all__ = ["RoughnessSpectrum", "named_spectrum", "source_dataset", "with_wheel_source", "SETTLE_WITHIN_DB", "axle_groups",
           "class_source_arrays", "fleet_source_dataset", "source_arrays_of", "with_fleet_source", "SOURCE_ARRAYS"]

SETTLE_WITHIN_DB = 1.0  # dB: a line has settled when within this of its settled level (passages_to_settle)
LONGEST_SEARCH_AXLES = 1e12  # the most axle passages the time to the limit is looked for over (about 140,000 years at 20,000 a day)


def S0_band(S0, share, band, nb):
    """The ground rail's band mean squares back from its line powers [m^2] (band_mean_square_from_lines).

    Parameters
    ----------
    S0 : ndarray
        Line mean squares [m^2].
    share, band : ndarray
        rail.growth_spectrum.source.line_share's.
    nb : int
        Bands [-].

    Returns
    -------
    ndarray
        [m^2].
    """
    return src.band_mean_square_from_lines(S0, share, band, nb)


def _line_power(spec: RoughnessSpectrum, lam, period: float):
    return src.wheel_line_power(lam, period, spec.centres, spec.levels)


def source_dataset(ds: xr.Dataset, wheel: RoughnessSpectrum, rate_own=None, ground: RoughnessSpectrum | None = None,
                   limit: RoughnessSpectrum | None = None, traffic=None) -> xr.Dataset:
    """The wheels' source, the settled spectrum and the time to the limit on a growth-rate spectrum's lines.

    Parameters
    ----------
    ds : xr.Dataset
        A growth-rate spectrum over (speed, wavelength) (rail.studies.rate_spectrum.rate_spectrum_dataset).
    wheel : RoughnessSpectrum
        The wheels' roughness [dB re 1 µm].
    rate_own : array_like, complex, (speed, wavelength), optional
        One wheel's own rate per passage of that wheel [-] (default: the spectrum's, exact for a one-wheel train).
    ground : RoughnessSpectrum, optional
        The ground rail's roughness, the start of the time to the limit [dB re 1 µm] (default: none, no interval).
    limit : RoughnessSpectrum, optional
        The limit spectrum [dB re 1 µm] (default: none, no interval).
    traffic : rail.traffic.Traffic, optional
        For the times in years and MGT.

    Returns
    -------
    xr.Dataset
        ``ds`` with the source's variables (module docstring): over (speed, wavelength) wheel_line_level_dB,
        wheel_source_dB, settled_level_dB, settle_axles; over (speed, band) wheel_band_level_dB,
        settled_band_level_dB, and with a ground rail and a limit start_band_level_dB, limit_dB, axles_to_limit
        (and years); over speed the interval and the band that sets it.
    """
    wheels = int(ds.attrs["wheels"])
    period = float(ds.attrs["bays"]) * float(ds.attrs["sleeper_spacing_m"])
    lam = ds.wavelength.values
    R = -(ds.growth_rate.values + 1j * ds.drift.values)  # per train passage (rail.growth_spectrum.probes.RateSpectrum.rate)
    own = R / 1.0 if rate_own is None else np.asarray(rate_own, dtype=complex)
    if own.shape != R.shape or not np.all(np.isfinite(own)):
        raise ValueError(f"rate_own: one wheel's rates must be finite on the spectrum's {R.shape} (speed, wavelength) lines.")
    if wheels > 1 and rate_own is None:
        raise ValueError(f"rate_own: a train of {wheels} wheels needs each wheel's own rate (the wheel alone on the track, "
                         "rail.chain.single_wheel); the train's rate holds the wheels' coherent interaction a wheel's roughness has not.")
    P = _line_power(wheel, lam, period)
    Q = src.source_power(own, P[None, :], wheels)
    comb = ds.source.values
    with np.errstate(divide="ignore"):
        S_inf = src.settled_mean_square(R, Q, comb)
        settle = src.passages_to_settle(R, SETTLE_WITHIN_DB) * wheels
    incoherent_inf = np.where(np.isfinite(S_inf), src.settled_mean_square(R, Q), np.inf)

    def band_ms_at(i, S0, share, band, nb):
        def band_ms(n):
            n = np.asarray(n, dtype=float)[:, None]
            inc = src.expected_mean_square(n, S0[None, :], R[i][None, :], Q[i][None, :])
            coh = src.expected_mean_square(n, 0.0, R[i][None, :], 0.0, comb[i][None, :])
            return src.band_mean_square_from_lines(inc, share, band, nb, coherent=coh)
        return band_ms

    out = ds.assign(
        wheel_line_level_dB=data_var("wavelength", _level(P), "dB re 1 um",
                                     f"the wheels' roughness on the line (its band's mean square spread evenly over the band's "
                                     f"wavenumbers): {wheel.label}"),
        wheel_source_dB=data_var(("speed", "wavelength"), _level(Q), "dB re 1 um^2 per train passage",
                                 "Q: the expected mean square the wheels' roughness adds to the rail's line per train passage "
                                 "(sum over the wheels of abs(R_own)^2 P)"),
        settled_level_dB=data_var(("speed", "wavelength"), _level(S_inf), "dB re 1 um",
                                  "the level the line settles to under the wheels' source and the supports' comb, Q / (1 - abs(1 - R)^2) "
                                  "+ abs(s / R)^2 / 2; inf where the line grows (no settled level)"),
        settle_axles=data_var(("speed", "wavelength"), settle, "1",
                              f"axle passages from a ground (zero) line to within {SETTLE_WITHIN_DB:g} dB of its settled level; inf where it grows"),
    )
    bands = wavelength_bands(1.0, 0.00315)
    out, attrs = _band_variables(out, "speed", lam, period, S_inf, incoherent_inf, band_ms_at, wheels,
                                 1e-12 * 10 ** (wheel.at(bands.centre) / 10), wheel.label, ground, limit, traffic)
    attrs.update({"wheel_roughness": wheel.label, "wheel_source_wheels": wheels,
                  "wheel_source_transfer": "the spectrum's own rate (one wheel)" if rate_own is None else
                  "each wheel alone on the track (rail.chain.single_wheel): the wheels' cross terms through the rail left out",
                  "wheel_source_model": "S_{n+1} = abs(1 - R)^2 S_n + Q per train passage, Q = wheels abs(R_own)^2 P; the supports' "
                                        "comb coherent (rail.growth_spectrum.source)",
                  "wheel_source_passages": "wheel_source_dB per train passage; settle_axles and axles_to_limit per axle (wheel) passage"})
    out.attrs.update(attrs)
    return out


def _level(ms):
    """[dB re 1 µm] of mean squares [m^2] (-inf at 0, inf at inf)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return 10 * np.log10(np.asarray(ms, dtype=float) / 1e-12)


def _band_variables(out: xr.Dataset, row, lam, period: float, S_inf, incoherent_inf, band_ms_at, axles_per_passage: float,
                    wheel_band, wheel_label: str, ground, limit, traffic):
    """The band variables of source_dataset and fleet_source_dataset: the settled band levels (with the comb, and the
    wheels' part alone) and, with a ground rail and a limit, the time to the limit per band and the interval.

    ``row`` names the leading dimension of S_inf and incoherent_inf (rows, lines) [m^2] ('speed'; None: one row, the
    fleet's, stored without it); band_ms_at(i, S0, share, band, nb) gives row i's band mean squares [m^2] after n passages
    (one train's or one fleet passage's: axles_per_passage [-] converts them to axle passages); wheel_band [m^2] per band.
    Returns the dataset and the attributes to add."""
    def dims(*rest):
        return (row, *rest) if row else rest

    def cut(v):
        return v if row else v[0]

    rows = S_inf.shape[0]
    bands = wavelength_bands(1.0, 0.00315)
    share, band = src.line_share(lam, period, bands.centre)
    nb = bands.centre.size
    sampled = np.array([np.any(band == b) for b in range(nb)])
    with np.errstate(invalid="ignore"):
        coherent_inf = S_inf - incoherent_inf
    settled_band = src.band_mean_square_from_lines(incoherent_inf, share, band, nb, coherent=np.nan_to_num(coherent_inf, nan=np.inf))
    wheels_band = src.band_mean_square_from_lines(incoherent_inf, share, band, nb)  # the wheels' part alone (the comb left out)
    out = out.assign_coords(band=data_var("band", bands.centre, "m", "one-third-octave band centre wavelength (exact, 10^(-n/10) m)"),
                            band_nominal=data_var("band", bands.nominal, "m", "EN 15610 nominal band label"))
    out["wheel_band_level_dB"] = data_var("band", _level(wheel_band), "dB re 1 um", f"the wheels' roughness per band: {wheel_label}")
    out["settled_band_level_dB"] = data_var(dims("band"), cut(np.where(sampled, _level(settled_band), np.nan)), "dB re 1 um",
                                            "the band's settled level (the mean of its lines' settled densities times its width, and the comb); "
                                            "inf where a line in it grows; NaN where no line of the spectrum samples the band")
    out["settled_band_wheels_dB"] = data_var(dims("band"), cut(np.where(sampled, _level(wheels_band), np.nan)), "dB re 1 um",
                                             "the band's settled level from the wheels' roughness alone (the supports' comb left out): "
                                             "what the wheels' source holds the rail at")
    attrs = {}
    if ground is None or limit is None:
        return out, attrs
    S0 = _line_power(ground, lam, period)
    from .bands import limit_tolerance

    lim_dB = limit.at(bands.centre)
    lim = 1e-12 * 10 ** ((lim_dB + np.nan_to_num(limit_tolerance(lim_dB), nan=0.0)) / 10)  # exceeded above its stated precision
    axles = np.full((rows, nb), np.inf)
    for i in range(rows):
        axles[i] = src.passages_to_limit(band_ms_at(i, S0, share, band, nb), np.where(sampled, lim, np.nan),
                                         longest=LONGEST_SEARCH_AXLES / axles_per_passage) * axles_per_passage
    above = np.isfinite(lim) & sampled & (S0_band(S0, share, band, nb) > lim)  # a band that starts above its limit
    counted = np.where(above[None, :], np.inf, axles)  # the interval: the bands that start below their limit
    first = np.min(counted, axis=1)
    driver = np.where(np.isfinite(first), bands.nominal[np.argmin(counted, axis=1)], np.nan)
    out["starts_above_limit"] = data_var("band", above.astype(int), "1",
                                         "1: the ground rail starts above the limit in the band (axles_to_limit 0; left out of the interval)")
    out["start_band_level_dB"] = data_var("band", _level(1e-12 * 10 ** (ground.at(bands.centre) / 10)), "dB re 1 um",
                                          f"the ground rail's roughness per band (the start): {ground.label}")
    out["limit_dB"] = data_var("band", limit.at(bands.centre), "dB re 1 um", f"the limit spectrum: {limit.label}")
    out["axles_to_limit"] = data_var(dims("band"), cut(axles), "1",
                                     "axle passages from the ground rail until the band's expected level exceeds its limit "
                                     "(the expected spectrum with the wheels' source, never a decay extrapolated); inf: not "
                                     f"within {LONGEST_SEARCH_AXLES:.0e} axle passages")
    out["interval_axles"] = data_var(dims(), cut(first), "1", "axle passages from the ground rail to the first band over its limit "
                                     "(of the bands that start below it)")
    out["interval_band"] = data_var(dims(), cut(driver), "m", "the nominal band that reaches its limit first (NaN: none)")
    if traffic is not None:
        out["years_to_limit"] = data_var(dims("band"), cut(axles / traffic.axles_per_year), "year",
                                         "years from the ground rail until the band's expected level exceeds its limit at the traffic")
        out["interval_years"] = data_var(dims(), cut(first / traffic.axles_per_year), "year",
                                         "years from the ground rail to the first band over its limit at the traffic")
    attrs["ground_rail"] = ground.label
    attrs["limit"] = limit.label
    return out, attrs


def with_wheel_source(ds: xr.Dataset, scn, tables, settings: dict, spectra: dict | None, progress=None) -> xr.Dataset:
    """A scenario's spectrum dataset with its wheels' source (source_dataset), or the dataset itself, untouched,
    without one (wheel_source.roughness none: every result as before the source existed).

    Parameters
    ----------
    ds : xr.Dataset
        The scenario's growth-rate spectrum at the tables' speed (rail.studies.rate_spectrum.spectrum_dataset_of).
    scn : rail.scenario.Scenario
        Its spectrum scenario (rail.setup.build.spectrum_scenario).
    tables : MovingReceptance or tuple of MovingReceptance
        The spectrum's receptance (Bloch) tables at the speed [m/N].
    settings : dict
        figures.rate_spectrum (the lines, rail.studies.rate_spectrum.spectrum_with_settings).
    spectra : dict or None
        rail.setup.inputs.wheel_source_spectra's (wheel, ground, limit).
    progress : file, optional
        Where the single wheel's spectrum tells its progress.

    Returns
    -------
    xr.Dataset
        With the source's variables; for a train of several wheels one wheel's own rate from the wheel alone on the
        track (rail.chain.single_wheel, the same lines and tables: a spectrum of one wheel, about 1 / wheels of the
        train's cost).
    """
    if spectra is None:
        return ds
    from .. import chain
    from ..traffic import traffic_of
    from .rate_spectrum import spectrum_with_settings

    own = None
    if len(scn.wheels.positions) > 1:
        one = spectrum_with_settings(chain.single_wheel(scn), tables, settings, progress=progress)
        if not np.array_equal(one.line, ds.line.values):
            raise ValueError("the single wheel's spectrum lies on other lines than the train's.")
        own = np.broadcast_to(one.rate, ds.growth_rate.shape)
    traffic = traffic_of(scn) if scn.axles_per_day else None
    limit = spectra["limit"]
    return source_dataset(ds, spectra["wheel"], own, spectra["ground"] if limit is not None else None, limit, traffic)


def axle_groups(scn) -> list[list[int]]:
    """The wheels of a train that wear alike alone on the track: grouped by their own creepage and wheelset (rail.chain.
    wheel_material), so that each group's own rate is computed once [wheel indices].

    Parameters
    ----------
    scn : rail.scenario.Scenario
        A fleet class's (or one train's) scenario.

    Returns
    -------
    list of list of int
        In the order of the wheels.
    """
    from .. import chain

    groups = {}
    for l in range(len(scn.wheels.positions)):
        m = chain.wheel_material(scn, l)
        groups.setdefault((m.creepage, id(m.longitudinal)), []).append(l)
    return list(groups.values())


def class_source_arrays(scn, tables, settings: dict, sp, wheel: RoughnessSpectrum | None, progress=None) -> dict:
    """What a fleet class's spectrum file carries for the wheels' source (rule fleet_class_spectrum): each axle's own
    rate alone on the track and the vehicle's wheel roughness on the lines; nothing without a source (the class file as
    before the source existed).

    Parameters
    ----------
    scn : rail.scenario.Scenario
        The class's spectrum scenario (rail.fleet.FleetClass.scenario).
    tables : MovingReceptance or tuple of MovingReceptance
        The class spectrum's receptance (Bloch) tables at its speed [m/N] (a fleet's shared tables hold offset 0).
    settings : dict
        The class spectrum's settings (figures.rate_spectrum, rail.studies.rate_spectrum.spectrum_with_settings).
    sp : rail.growth_spectrum.RateSpectrum
        The class's spectrum (rates per passage of its train).
    wheel : RoughnessSpectrum or None
        The vehicle's wheel roughness [dB re 1 µm] (rail.setup.inputs.wheel_source_spectra's ``vehicles``); None: no source.
    progress : file, optional

    Returns
    -------
    dict
        {} without a source; else wheel_rate_own (axles, lines) complex [-] per passage of that wheel (a one-axle
        vehicle: the spectrum's own rate; axles alike computed once, axle_groups), wheel_power (lines,) [m^2] (P_j),
        wheel_centres [m], wheel_levels [dB re 1 µm] and wheel_label.
    """
    if wheel is None:
        return {}
    from .. import chain
    from .rate_spectrum import spectrum_with_settings

    axles = len(scn.wheels.positions)
    own = np.empty((axles, len(sp.line)), dtype=complex)
    if axles == 1:
        own[0] = sp.rate
    else:
        for group in axle_groups(scn):
            one = spectrum_with_settings(chain.single_axle(scn, group[0]), tables, settings, progress=progress)
            if not np.array_equal(one.line, sp.line):
                raise ValueError("the single axle's spectrum lies on other lines than the class's.")
            own[group] = one.rate
    period = scn.roughness.bays * scn.L
    return {"wheel_rate_own": own, "wheel_power": _line_power(wheel, sp.wavelength, period), "wheel_centres": wheel.centres,
            "wheel_levels": wheel.levels, "wheel_label": np.array(wheel.label)}


def fleet_source_dataset(ds: xr.Dataset, fs, fleet, classes, period: float, arrays, ground: RoughnessSpectrum | None = None,
                         limit: RoughnessSpectrum | None = None) -> xr.Dataset:
    """The wheels' source under a fleet on its spectrum's lines: per fleet passage S_{n+1} = a S_n + Q, a = sum_c w_c
    abs(1 - R_c)^2, Q = sum_c w_c Q_c (rail.growth_spectrum.source), the supports' comb of every class with the
    draw's spread; the settled spectrum, the passages to settle and the time from a ground rail to the limit.

    Parameters
    ----------
    ds : xr.Dataset
        The fleet's spectrum (rail.studies.fleet.fleet_spectrum_dataset of ``fs``).
    fs : rail.growth_spectrum.FleetRateSpectrum
        Its classes' spectra (rates R_c and comb sources s_c per passage of the class's train) and weights w_c.
    fleet : rail.fleet.Fleet
        Its traffic: the mean axles per train convert fleet passages to axle passages (as the fleet's spectrum does).
    classes : sequence of rail.fleet.FleetClass
        The classes of ``fs``, in its order (their vehicles and axles).
    period : float
        N L, the lines' period [m].
    arrays : sequence of dict
        class_source_arrays of each class, in the order of fs.classes ({}: a vehicle without wheel roughness, Q_c = 0).
    ground, limit : RoughnessSpectrum, optional
        The ground rail and the limit [dB re 1 µm] (both: the time to the limit).

    Returns
    -------
    xr.Dataset
        ``ds`` with, over wavelength, wheel_source_dB (Q per fleet passage), decay_factor (a), settled_level_dB and
        settle_axles; over (class, wavelength) class_wheel_source_dB (Q_c per passage of the class's train) and
        class_wheel_line_level_dB (P_j); the band variables of source_dataset without a speed (one row: the fleet).
    """
    lam = ds.wavelength.values
    w = np.asarray(fs.weights, dtype=float)
    if not len(arrays) == len(classes) == len(fs.classes):
        raise ValueError(f"arrays: {len(arrays)} classes' source arrays and {len(classes)} classes for {len(fs.classes)} class "
                         "spectra: give one per class.")
    Rc = np.array([c.rate for c in fs.classes])
    sc = np.array([c.source for c in fs.classes])
    R = np.asarray(fs.total.rate)
    P = np.zeros(Rc.shape)
    Qc = np.zeros(Rc.shape)
    for i, (arr, c) in enumerate(zip(arrays, fs.classes)):
        if arr:
            if np.shape(arr["wheel_power"]) != lam.shape or np.shape(arr["wheel_rate_own"])[1:] != lam.shape:
                raise ValueError(f"class {fs.labels[i]}: its source arrays lie on other lines than the fleet's spectrum.")
            P[i] = arr["wheel_power"]
            Qc[i] = src.axle_source_power(arr["wheel_rate_own"], P[i])
    a = src.fleet_decay_factor(Rc, w)
    Q = src.fleet_source_power(Qc, w)
    apt = float(fleet.axles_per_train)
    with np.errstate(divide="ignore"):
        S_inf = src.settled_mean_square(R, Q, decay=a) + src.fleet_settled_comb(Rc, sc, w, R)
        settle = src.passages_to_settle(R, SETTLE_WITHIN_DB, decay=a) * apt
    incoherent_inf = np.where(np.isfinite(S_inf), src.settled_mean_square(R, Q, decay=a), np.inf)

    def band_ms_at(i, S0, share, band, nb):
        def band_ms(n):
            n = np.asarray(n, dtype=float)[:, None]
            inc = src.expected_mean_square(n, S0[None, :], R[None, :], Q[None, :], decay=a[None, :])
            coh = src.fleet_comb_mean_square(n, Rc[:, None, :], sc[:, None, :], w, R[None, :])
            return src.band_mean_square_from_lines(inc, share, band, nb, coherent=coh)
        return band_ms

    labels = {}
    for arr, c in zip(arrays, classes):
        labels.setdefault(c.vehicle, str(arr["wheel_label"]) if arr else "none")
    text = "; ".join(f"{v}: {label}" for v, label in labels.items())
    bands = wavelength_bands(1.0, 0.00315)
    counts = np.array([len(c.scenario.wheels.positions) for c in classes], dtype=float)
    band_ms = np.array([1e-12 * 10 ** (RoughnessSpectrum(arr["wheel_centres"], arr["wheel_levels"], "").at(bands.centre) / 10)
                        if arr else np.zeros(bands.centre.size) for arr in arrays])
    wheel_band = np.sum((w * counts)[:, None] * band_ms, axis=0) / np.sum(w * counts)  # over the axles that pass
    out = ds.assign(
        wheel_source_dB=data_var("wavelength", _level(Q), "dB re 1 um^2 per fleet passage",
                                 "Q = sum_c w_c Q_c: the expected mean square the wheels' roughness adds to the rail's line per fleet "
                                 "passage (one train drawn from the classes)"),
        decay_factor=data_var("wavelength", a, "1", "a = sum_c w_c abs(1 - R_c)^2: the share of the line's mean square a fleet "
                              "passage keeps (> 1: the line grows)"),
        class_wheel_source_dB=data_var(("class", "wavelength"), _level(Qc), "dB re 1 um^2 per train passage",
                                       "Q_c: the class's wheels' source per passage of its train (sum over its axles of "
                                       "abs(R_own)^2 P; -inf: no wheel roughness)"),
        class_wheel_line_level_dB=data_var(("class", "wavelength"), _level(P), "dB re 1 um",
                                           "the class's wheel roughness on the line (its band's mean square spread evenly over the band)"),
        settled_level_dB=data_var("wavelength", _level(S_inf), "dB re 1 um",
                                  "the level the line settles to under the fleet's wheels and the supports' comb, Q / (1 - a) plus "
                                  "the comb's; inf where the line grows (no settled level)"),
        settle_axles=data_var("wavelength", settle, "1", f"axle passages from a ground (zero) line to within {SETTLE_WITHIN_DB:g} dB "
                              "of its settled level; inf where it grows"),
    )
    traffic = Traffic(fleet.axles_per_day, fleet.mean_axle_load)
    out, attrs = _band_variables(out, None, lam, period, S_inf[None, :], incoherent_inf[None, :], band_ms_at, apt, wheel_band,
                                 f"the axle-weighted mean square of the vehicles' ({text})", ground, limit, traffic)
    attrs.update({"wheel_roughness": text, "wheel_source_wheels": apt,
                  "wheel_source_transfer": "each axle alone on the track with its own creepage and wheelset (rail.chain.single_axle): "
                                           "the wheels' cross terms through the rail left out",
                  "wheel_source_model": "S_{n+1} = a S_n + Q per fleet passage, a = sum_c w_c abs(1 - R_c)^2, Q = sum_c w_c Q_c, Q_c "
                                        "= sum over the class's axles of abs(R_own)^2 P; the supports' comb of every class coherent, "
                                        "taken in phase, its mean the fleet's rate and source, the draw's spread added "
                                        "(rail.growth_spectrum.source)",
                  "wheel_source_passages": f"wheel_source_dB per fleet passage; settle_axles and axles_to_limit per axle passage "
                                           f"(fleet passages x {apt:g} axles per train)"})
    out.attrs.update(attrs)
    return out


SOURCE_ARRAYS = ("wheel_rate_own", "wheel_power", "wheel_centres", "wheel_levels", "wheel_label")  # class_source_arrays's keys


def source_arrays_of(arrays) -> dict:
    """class_source_arrays's part of a class spectrum file (an opened .npz), or {} where it has none (no source).

    Parameters
    ----------
    arrays : mapping of name to ndarray
        The class file's arrays (rail.studies.fleet.spectrum_arrays and class_source_arrays; rates [-], P [m^2]).

    Returns
    -------
    dict
    """
    if "wheel_rate_own" not in arrays:
        return {}
    out = {k: np.asarray(arrays[k]) for k in SOURCE_ARRAYS}
    out["wheel_label"] = np.array(str(out["wheel_label"]))
    return out


def with_fleet_source(ds: xr.Dataset, fs, fleet, classes, tables: dict, settings: dict, spectra: dict | None, period: float,
                      progress=None) -> xr.Dataset:
    """A fleet's spectrum dataset with its wheels' source (class_source_arrays of every class, then fleet_source_dataset),
    or the dataset itself, untouched, without one (every vehicle's wheel roughness none).

    Parameters
    ----------
    ds : xr.Dataset
        rail.studies.fleet.fleet_spectrum_dataset of ``fs``.
    fs : rail.growth_spectrum.FleetRateSpectrum
    fleet : rail.fleet.Fleet
    classes : sequence of rail.fleet.FleetClass
    tables : dict
        {class speed [m/s]: its receptance (Bloch) tables} (rail.chain.fleet_tables).
    settings : dict
        The class spectra's settings (figures.rate_spectrum).
    spectra : dict or None
        rail.setup.inputs.wheel_source_spectra's (with ``vehicles``).
    period : float
        N L [m].
    progress : file, optional

    Returns
    -------
    xr.Dataset
    """
    if spectra is None:
        return ds
    arrays = [class_source_arrays(c.scenario, tables[c.speed], settings, sp, spectra["vehicles"].get(c.vehicle), progress)
              for c, sp in zip(classes, fs.classes, strict=True)]
    limit = spectra["limit"]
    return fleet_source_dataset(ds, fs, fleet, classes, period, arrays, spectra["ground"] if limit is not None else None, limit)


def _per_speed(ds: xr.Dataset) -> int:
    """1 for a one-train spectrum's source (over speed), 0 for a fleet's (fleet_source_dataset: one row, no speed) [-]."""
    return int("speed" in ds.settled_band_level_dB.dims)


def _row(ds: xr.Dataset, name: str):
    """A variable's values with a leading row per speed (a fleet's one row added)."""
    v = ds[name].values
    return v if _per_speed(ds) else v[None, ...]


def _row_labels(ds: xr.Dataset):
    """The rows' speeds [m/s] (a fleet's one row: NaN, its classes' speeds in its class coordinate)."""
    return ds.speed.values if _per_speed(ds) else np.array([np.nan])


def settled_csv_text(ds: xr.Dataset) -> str:
    """The settled spectrum per speed and band as CSV, units in every column, the model in the header (a fleet's: per
    band, no speed column, the fleet's classes in the header).

    Parameters
    ----------
    ds : xr.Dataset
        source_dataset's or fleet_source_dataset's.

    Returns
    -------
    str
        '# ' header lines, then speed_m_s, band_nominal_m, wheel_dB_re_1um, settled_dB_re_1um, and with a ground
        rail and a limit ground_dB_re_1um, limit_dB_re_1um, axles_to_limit, years_to_limit.
    """
    a = ds.attrs
    head = [f"# expected rail roughness under the wheels' roughness {a['wheel_roughness']} ({a['wheel_source_model']}; "
            f"{a['wheel_source_transfer']})",
            f"# {a['wheel_source_passages']}; settled: inf where a line in the band grows (no settled level), empty where no line samples the band"]
    if not _per_speed(ds):
        head.append("# under the fleet, one train drawn each passage from the classes " + "; ".join(
            f"{lab} (weight {w:.4g})" for lab, w in zip(ds.class_label.values, ds.class_weight.values)))
    has = "axles_to_limit" in ds
    if has:
        head.append(f"# from the ground rail {a['ground_rail']} to the limit {a['limit']} (the expected spectrum, never a decay extrapolated)")
    cols = ["speed_m_s"] * _per_speed(ds) + ["band_nominal_m", "wheel_dB_re_1um", "settled_dB_re_1um", "settled_wheels_only_dB_re_1um"]
    if has:
        cols += ["ground_dB_re_1um", "limit_dB_re_1um", "axles_to_limit"] + (["years_to_limit"] if "years_to_limit" in ds else [])
    rows = [",".join(cols)]

    def cell(v, fmt="{:.2f}"):
        v = float(v)
        return "" if np.isnan(v) else ("inf" if np.isinf(v) and v > 0 else fmt.format(v))

    for i, V in enumerate(_row_labels(ds)):
        for b in range(ds.sizes["band"]):
            r = [f"{V:g}"] * _per_speed(ds) + [f"{ds.band_nominal.values[b]:g}", cell(ds.wheel_band_level_dB.values[b]),
                                                cell(_row(ds, "settled_band_level_dB")[i, b]), cell(_row(ds, "settled_band_wheels_dB")[i, b])]
            if has:
                n = _row(ds, "axles_to_limit")[i, b]
                r += [cell(ds.start_band_level_dB.values[b]), cell(ds.limit_dB.values[b]), cell(n, "{:.4g}")]
                if "years_to_limit" in ds:
                    r.append(cell(_row(ds, "years_to_limit")[i, b], "{:.4g}"))
            rows.append(",".join(r))
    return "\n".join(head + rows) + "\n"


def settled_summary_markdown(ds: xr.Dataset) -> str:
    """The settled spectrum in words: per speed (a fleet: once), the highest settled band against the wheels' roughness
    there, the bands where a line grows, and the time from the ground rail to the limit with the band that sets it.

    Parameters
    ----------
    ds : xr.Dataset
        source_dataset's or fleet_source_dataset's.

    Returns
    -------
    str
        Markdown.
    """
    a = ds.attrs
    out = [f"# The wheels' roughness as a source: {a['wheel_roughness']}", "",
           f"Model: {a['wheel_source_model']}; {a['wheel_source_transfer']}.", ""]
    for i, V in enumerate(_row_labels(ds)):
        lev = _row(ds, "settled_band_level_dB")[i]
        nom = ds.band_nominal.values
        fin = np.isfinite(lev)
        grows = [f"{1e3 * x:g} mm" for x in nom[np.isinf(lev) & (lev > 0)]]
        line = f"- {V:g} m/s: " if _per_speed(ds) else "- under the fleet (one train drawn from its classes each passage): "
        if fin.any():
            b = int(np.nanargmax(np.where(fin, lev, -np.inf)))
            gap = lev[b] - ds.wheel_band_level_dB.values[b]
            line += (f"highest settled band {1e3 * nom[b]:g} mm at {lev[b]:.1f} dB re 1 µm, {gap:+.1f} dB against the wheels' "
                     "roughness in that band")
        else:
            line += "no band settles"
        wl = _row(ds, "settled_band_wheels_dB")[i] - ds.wheel_band_level_dB.values
        if np.isfinite(wl).any():
            b = int(np.nanargmax(np.where(np.isfinite(wl), wl, -np.inf)))
            line += (f"; the wheels' part alone (the supports' comb left out) is at most {wl[b]:+.1f} dB against the wheels' roughness "
                     f"(the {1e3 * nom[b]:g} mm band, {_row(ds, 'settled_band_wheels_dB')[i, b]:.1f} dB re 1 µm)")
        if grows:
            line += f"; a line grows (no settled level) in {', '.join(grows)}"
        if "interval_axles" in ds:
            n = float(_row(ds, "interval_axles")[i])
            if np.isfinite(n):
                yrs = f", {float(_row(ds, 'interval_years')[i]):.3g} years" if "interval_years" in ds else ""
                line += (f"; from the ground rail the {1e3 * float(_row(ds, 'interval_band')[i]):g} mm band passes the limit first, "
                         f"after {n:.3g} axle passages{yrs}")
            else:
                line += "; from the ground rail no band that starts below its limit reaches it"
            if "starts_above_limit" in ds and ds.starts_above_limit.values.any():
                line += ("; the ground rail starts above the limit in "
                         + ", ".join(f"{1e3 * x:g} mm" for x in nom[ds.starts_above_limit.values == 1]) + " (left out)")
        out.append(line)
    return "\n".join(out) + "\n"
