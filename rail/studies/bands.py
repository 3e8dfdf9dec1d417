"""One-third-octave roughness bands (EN 15610 form), growth per band, and the grinding interval.

Processing choices for a computed roughness, which is periodic over N L and known exactly as the
coefficients Z_j of its Fourier series (rail.interaction.Roughness):

* Centre wavelengths: the exact base-ten third-octave series lambda_n = 10^(-n/10) m (1 m, 0.794 m,
  ..., 3.16 mm), labelled by EN 15610's nominal values (1, 0.8, 0.63, ... m). Band edges
  lambda_n 10^(+-1/20), so neighbouring bands meet and partition the wavelength axis (rail.bands:
  the one edge rule, IEC 61260-1, and its wavelength_bands).
* No window: a periodic profile over its own period has no leakage, so a band's mean square is the
  sum of the mean squares of the lines 2 pi j / (N L) inside it, 2 abs(Z_j)^2 (Parseval; a line on an
  edge belongs to the band with the shorter wavelengths). This replaces the measured-profile
  steps of EN 15610 (spike removal, curvature processing, windowed spectra), which a computed
  profile does not need.
* A band is resolved when it holds at least ``min_lines`` lines (default 1; configurable): a band
  longer than the period or shorter than the shortest wavelength L / K holds none. Unresolved bands
  are marked (NaN level and resolved = 0), never filled.
* Levels in dB re 1 um rms: L = 10 log10(mean square / (1e-6 m)^2).
* A line on a band edge belongs to the band with the shorter wavelengths (rail.bands.in_band,
  the rule the spectrum synthesis uses too, so a spectrum start is analysed back to its levels).

Rates that mean something (issue 45): a band whose level at the last save is below the floor
RATE_FLOOR_DB = -30 dB re 1 um (0.03 um rms; docs/studies.md says why) keeps its numbers but is
marked ``ranked = 0`` with its reason (``rate_note``): its dB rate is the growth of a roughness from
nothing (a band at -60 dB growing linearly shows several dB per 100,000 axles whatever its size) and
is ranked neither by the grinding interval nor in the figures. The same holds for a band that *started*
below the floor (its level at the first save, or no roughness there) and has grown above it by the last
save (issue 57, item 8): grown from nothing, it grows linearly from the supports' source (the new
roughness barely changes the force, docs/studies.md), so its dB rate is the same for every such band
and says nothing; its amplitude rate does. Its dB rate is kept in the dataset, marked, and left empty in
the band CSV; where its law is the straight line, that line in amplitude counts toward the grinding
interval.

The grinding interval says how far it is extrapolated (issue 57, item 8): the factor of the interval
over the computed (last saved) passages, in the attributes, the CSV header and the figure title, flagged
beyond EXTRAPOLATION_FLAG_FACTOR. A band that decays (its law's rate not above zero, or its amplitude
falling over the last saved interval: no feedback growth, no source) or whose growth is not
distinguished from zero (its law's rate below twice its standard error) sets no interval: "not
reached", with the reason per band (limit_note).

A limit is exceeded when a band's level is strictly above it to the limit's stated precision: by
more than half a unit of its last stated decimal (limit_tolerance: 17.1 is exceeded above 17.15 dB;
17.100 against 17.1 is not exceeded).

Growth per band (rail.growth.band_growth): from the rms amplitude a(n) of each band at the saved
passage counts n, a straight line a = a0 + r n (amplitude growth, um per 1e5 axle passages) and an
exponential a = a0 exp(g n) (e-folding rate g per 1e5 axle passages) are both fitted by least
squares with their standard errors; the one with the smaller residual relative to the band's
amplitude is reported as the band's growth law, and the level growth rate in dB per 1e5 axle
passages is that law's rate at the last save (docs/exports.md). The grinding interval is the number
of axle passages (and, with the traffic, days, years and MGT) until the first band's level,
extrapolated with its own growth law, reaches the limit spectrum.
"""

from __future__ import annotations

import numpy as np

from ..growth import DB_PER_NEPER, BandGrowth, band_growth
# the bands and their rule are rail.bands's; ThirdOctaveBands and third_octave_bands (= wavelength_bands)
# stay importable from here
from ..bands import NOMINAL_WAVELENGTHS_M, ThirdOctaveBands, in_band, nominal_band
from ..bands import wavelength_bands as third_octave_bands
from .validity import VALIDITY_ATTRS, validity_text

__all__ = ["NOMINAL_WAVELENGTHS_M", "ThirdOctaveBands", "third_octave_bands", "band_mean_square", "band_levels", "RATE_FLOOR_DB",
           "limit_tolerance", "ranked_bands", "BandGrowth", "band_growth", "EXTRAPOLATION_FLAG_FACTOR", "grinding_interval",
           "empty_band_reasons", "bands_dataset", "grinding_interval_text", "extrapolation_text", "band_csv_text", "write_band_csv",
           "sweep_band_map", "readable_count"]

# The level below which a band's growth rate is not ranked [dB re 1 um] (module docstring; docs/studies.md)
RATE_FLOOR_DB = -30.0
# A grinding interval more than this many times the computed passages is flagged as an extrapolation [-]
EXTRAPOLATION_FLAG_FACTOR = 10.0
# A band's growth counts toward the interval only when its law's rate exceeds this many standard errors [-]
GROWTH_SIGNIFICANCE = 2.0

# NOMINAL_WAVELENGTHS_M: EN 15610 nominal centre wavelengths (m) of the exact series 10^(-n/10) m,
# n = 0..25 (rail.bands; rail.roughness reads the limit spectrum and checks it against them)


def readable_count(x: float, digits: int = 3) -> str:
    """A count for a title or a header: ``digits`` significant figures with thousands separators
    (82,300 rather than 8.23e+04); 'never' for inf.

    Parameters
    ----------
    x : float
        The count [-] (passages, axles, years or MGT: in the unit the caller writes beside it).
    digits : int
        Significant figures.

    Returns
    -------
    str
    """
    if not np.isfinite(x):
        return "never" if x > 0 else "nan"
    if x == 0:
        return "0"
    r = float(f"{x:.{digits}g}")
    if abs(r) >= 10 ** (digits - 1):
        return f"{int(round(r)):,}"
    return f"{r:,.{max(digits - 1 - int(np.floor(np.log10(abs(r)))), 0)}f}"


def band_mean_square(Z, period: float, bands: ThirdOctaveBands, min_lines: int = 1):
    """Mean square of the roughness in each band, and whether the band is resolved.

    Parameters
    ----------
    Z : ndarray, shape (..., 2J + 1)
        Roughness coefficients Z_j [m] over the period (j = -J..J).
    period : float
        N L [m].
    bands : ThirdOctaveBands
    min_lines : int
        Lines 2 pi j / (N L) a band must hold to count as resolved [-].

    Returns
    -------
    ms : ndarray, shape (..., bands)
        Mean square [m^2]; NaN where not resolved.
    resolved : ndarray of bool, shape (bands,)
    """
    Z = np.asarray(Z)
    J = (Z.shape[-1] - 1) // 2
    j = np.arange(1, J + 1)
    lam = period / j
    power = 2 * np.abs(Z[..., J + 1 :]) ** 2
    ms = np.full(Z.shape[:-1] + (len(bands.centre),), np.nan)
    resolved = np.zeros(len(bands.centre), dtype=bool)
    for b, (lo, hi) in enumerate(zip(bands.lower, bands.upper)):
        inside = in_band(lam, lo, hi)
        if inside.sum() >= min_lines:
            resolved[b] = True
            ms[..., b] = power[..., inside].sum(axis=-1)
    return ms, resolved


def band_levels(Z, period: float, bands: ThirdOctaveBands, min_lines: int = 1):
    """Third-octave band levels of a periodic roughness (module docstring: the processing).

    Parameters
    ----------
    Z : ndarray, shape (..., 2J + 1)
        Roughness coefficients [m].
    period : float
        N L [m].
    bands : ThirdOctaveBands
    min_lines : int
        Lines a band must hold to be resolved [-].

    Returns
    -------
    level : ndarray, shape (..., bands)
        [dB re 1 µm]; NaN for unresolved bands (a band with zero roughness gives -inf).
    resolved : ndarray of bool
    """
    ms, resolved = band_mean_square(Z, period, bands, min_lines)
    with np.errstate(divide="ignore"):
        return 10 * np.log10(ms / 1e-12), resolved


def limit_tolerance(limit_dB) -> np.ndarray:
    """Half a unit of the last decimal each limit level states [dB], read from its shortest text
    (17.1 -> 0.05, 17 -> 0.5, 17.25 -> 0.005): a level exceeds the limit when it is above it by more.

    Parameters
    ----------
    limit_dB : array-like
        Limit levels [dB re 1 µm]; NaN where there is none.

    Returns
    -------
    ndarray
        [dB]; NaN where the limit is NaN.
    """
    out = []
    for v in np.atleast_1d(np.asarray(limit_dB, dtype=float)):
        if not np.isfinite(v):
            out.append(np.nan)
            continue
        text = np.format_float_positional(float(v), trim="-")  # the shortest text that reads back as v
        decimals = len(text.split(".")[1]) if "." in text else 0
        out.append(0.5 * 10.0 ** -decimals)
    return np.array(out)


def ranked_bands(ms_last, floor_dB: float = RATE_FLOOR_DB, ms_first=None):
    """Which bands' growth rates are ranked, and why not where they are not: a band below the floor at
    the last save, or one that started below it (grown from nothing: its dB rate is the linear growth
    from the supports' source, module docstring), is not ranked.

    Parameters
    ----------
    ms_last : ndarray, shape (bands,)
        Band mean squares at the last save [m^2] (NaN where the band is not resolved).
    floor_dB : float
        The floor [dB re 1 µm] (RATE_FLOOR_DB).
    ms_first : ndarray, shape (bands,), optional
        Band mean squares at the first save [m^2]; default: not checked.

    Returns
    -------
    ranked : ndarray of bool
    note : ndarray of str
        '' where ranked.
    """
    ms_last = np.asarray(ms_last, dtype=float)
    ranked = np.zeros(ms_last.shape, dtype=bool)
    note = []
    for b, m in enumerate(ms_last):
        if not np.isfinite(m):
            note.append("no level at the last save")
            continue
        if not m > 0:
            note.append("no roughness in the band at the last save")
            continue
        level = 10 * np.log10(m / 1e-12)
        if level < floor_dB:
            note.append(f"below the floor: {level:.1f} dB re 1 um at the last save < {floor_dB:g} dB re 1 um; its dB rate is "
                        "growth from nothing, not ranked")
            continue
        if ms_first is not None:
            m0 = float(ms_first[b])
            start = 10 * np.log10(m0 / 1e-12) if m0 > 0 else -np.inf
            if not start >= floor_dB:
                began = "no roughness in the band" if not m0 > 0 else f"{start:.1f} dB re 1 um"
                note.append(f"grown from nothing: {began} at the first save (below the floor {floor_dB:g} dB re 1 um) to "
                            f"{level:.1f} dB re 1 um at the last; its dB rate is linear growth from the supports' source, not a "
                            "feedback rate: not ranked (its amplitude rate counts: a straight line in amplitude, it counts toward the "
                            "grinding interval)")
                continue
        ranked[b] = True
        note.append("")
    return ranked, np.array(note, dtype=str)


def grinding_interval(passages, ms, growth: BandGrowth, limit_dB, per_day: float | None = None, ranked=None):
    """Passages (and days) until the first band exceeds the limit, with its band.

    A band exceeds its limit when its level is above it by more than limit_tolerance (the limit's
    stated precision); only the ranked bands (ranked_bands) count.

    Parameters
    ----------
    passages : ndarray, shape (n,)
        Saved passage counts [-].
    ms : ndarray, shape (n, bands)
        Band mean squares [m^2].
    growth : BandGrowth
    limit_dB : ndarray, shape (bands,)
        Limit level per band [dB re 1 µm]; NaN where there is no limit.
    per_day : float, optional
        Wheel passages per day [1/day] (the traffic).
    ranked : ndarray of bool, optional
        The bands that count (default: every band).

    Returns
    -------
    dict
        'passages' (inf if no band exceeds its limit with growth), 'days', 'band' (index or -1),
        'already' (True if a ranked band is above its limit at the start), 'each' (passages per band
        until it exceeds its limit, inf where not reached) and 'note' (per band, why not reached: the
        band decays, its growth is not distinguished from zero, ...; '' where reached).
    """
    n = np.asarray(passages, dtype=float)
    ms = np.asarray(ms, dtype=float)
    amp_last = np.sqrt(ms[-1])
    limit_dB = np.asarray(limit_dB, dtype=float)
    amp_lim = 1e-6 * 10 ** ((limit_dB + limit_tolerance(limit_dB)) / 20)  # exceeded: above it, to its precision
    ranked = np.ones(len(amp_lim), dtype=bool) if ranked is None else np.asarray(ranked, dtype=bool)
    best, band = np.inf, -1
    each = np.full(len(amp_lim), np.inf)
    notes = []
    with np.errstate(invalid="ignore"):
        already = bool(np.any(ranked & (np.sqrt(ms[0]) > amp_lim)))
    for b in range(len(amp_lim)):
        if not (ranked[b] and np.isfinite(amp_lim[b]) and np.isfinite(amp_last[b])):
            notes.append("no limit in the band" if ranked[b] and not np.isfinite(amp_lim[b]) else
                         "not ranked" if not ranked[b] else "no level at the last save")
            continue
        if amp_last[b] > amp_lim[b]:
            # reached within the run: between the saves around the crossing, ln(amplitude) linear
            amp = np.sqrt(ms[:, b])
            k = int(np.nonzero(amp > amp_lim[b])[0][0])
            if k == 0:
                t = n[0]
            else:
                y0, y1 = np.log(max(amp[k - 1], 1e-300)), np.log(amp[k])
                t = n[k - 1] + (n[k] - n[k - 1]) * (np.log(amp_lim[b]) - y0) / (y1 - y0)
        else:
            exponential = growth.law[b] == "exponential"
            rate = growth.exp_rate[b] if exponential else growth.linear_rate[b]
            error = growth.exp_error[b] if exponential else growth.linear_error[b]
            amp = np.sqrt(ms[:, b])
            if not rate > 0 or (amp.size > 1 and amp[-1] < amp[-2]):
                # no feedback growth and no source: extrapolating a decay gives no interval
                notes.append("not reached: the band decays (" + (f"its {growth.law[b]} rate is not above zero" if not rate > 0 else
                             "its amplitude falls over the last saved interval") + ")")
                continue
            if np.isfinite(error) and rate < GROWTH_SIGNIFICANCE * error:
                notes.append(f"not reached: its {growth.law[b]} growth is not distinguished from zero (rate below "
                             f"{GROWTH_SIGNIFICANCE:g} standard errors)")
                continue
            if exponential:
                t = n[-1] + np.log(amp_lim[b] / amp_last[b]) / rate * 1e5
            else:
                t = n[-1] + (amp_lim[b] - amp_last[b]) / rate * 1e5
        each[b] = float(t)
        notes.append("")
        if t < best:
            best, band = float(t), b
    return {"passages": best, "days": best / per_day if per_day else np.nan, "band": band, "already": already, "each": each,
            "note": np.array(notes, dtype=str)}


def empty_band_reasons(bands: ThirdOctaveBands, period: float, shortest: float, resolved, ms, min_lines: int = 1) -> np.ndarray:
    """Why a band has no level, per band ('' where it has one at every save).

    Parameters
    ----------
    bands : ThirdOctaveBands
    period : float
        N L, the roughness period [m] (the longest wavelength the record resolves).
    shortest : float
        The shortest wavelength of the record, N L / J [m].
    resolved : ndarray of bool, shape (bands,)
    ms : ndarray, shape (n, bands)
        Band mean squares at the saves [m^2].
    min_lines : int
        Lines a band must hold to be resolved [-] (band_mean_square).

    Returns
    -------
    ndarray of str, shape (bands,)
    """
    out = []
    ms = np.atleast_2d(np.asarray(ms, dtype=float))
    for b in range(len(bands.centre)):
        if not resolved[b]:
            if bands.lower[b] >= period:
                why = f"not resolved: the band is longer than the roughness period N L = {period:.4g} m"
            elif bands.upper[b] < shortest:
                why = f"not resolved: the band is shorter than the shortest wavelength of the record, {1e3 * shortest:.3g} mm"
            else:
                why = (f"not resolved: fewer than min_lines = {min_lines} of the wavelengths N L / j of the roughness period "
                       f"N L = {period:.4g} m fall in the band")
        else:
            zero = np.nonzero(~(ms[:, b] > 0))[0]
            why = (f"no roughness in the band at {len(zero)} of {ms.shape[0]} saves (e.g. the smooth rail at the start): "
                   "level empty there" if zero.size else "")
        out.append(why)
    return np.array(out, dtype=str)


def bands_dataset(growth, L: float, bands: ThirdOctaveBands, min_lines: int, limit=None, per_day: float | None = None,
                  traffic=None, floor_dB: float = RATE_FLOOR_DB):
    """The band view of a growth run (a dataset of rail.studies.datasets.growth).

    Rates follow one convention (rail.traffic, docs/exports.md): level growth in dB per 100,000 axle
    (wheel) passages, and per year and per MGT with the traffic.

    Parameters
    ----------
    growth : xarray.Dataset
        Growth result: Z_real, Z_imag per saved passage count; attribute bays (default 1).
    L : float
        Sleeper spacing [m].
    bands : ThirdOctaveBands
    min_lines : int
        Lines a band must hold to be resolved [-].
    limit : (wavelength [m], level [dB re 1 µm]) arrays, optional
        Limit spectrum; matched to the bands by rail.bands.nominal_band (within 1.5 % of a nominal
        label or exact centre; others are left out).
    per_day : float, optional
        Wheel passages per day on the rail [1/day] (when ``traffic`` is not given: days only).
    traffic : rail.traffic.Traffic, optional
        Axles per day and axle load: the rates per year and per MGT and the interval in years and MGT.
    floor_dB : float
        Bands below it at the last save are not ranked [dB re 1 µm] (ranked_bands).

    Returns
    -------
    xarray.Dataset
        Band levels per saved passage count (NaN where a band has no level, with the reason in
        ``empty_reason``; never -inf), resolved flags, growth rates with errors and the law, the
        limit and the grinding interval (attributes), the frequency V / lambda at the run's speed.
    """
    import xarray as xr

    from ..traffic import AXLES_PER_RATE
    from ..setup.io import data_var

    if traffic is not None:
        per_day = traffic.axles_per_day
    N = int(growth.attrs.get("bays", 1))
    Z = growth["Z_real"].values + 1j * growth["Z_imag"].values
    n = growth["passage"].values
    J = (Z.shape[-1] - 1) // 2
    ms, resolved = band_mean_square(Z, N * L, bands, min_lines)
    with np.errstate(divide="ignore"):
        level = np.where(ms > 0, 10 * np.log10(np.where(ms > 0, ms, 1.0) / 1e-12), np.nan)
    reasons = empty_band_reasons(bands, N * L, N * L / J, resolved, ms, min_lines)
    g = band_growth(n, ms)
    lim = np.full(len(bands.centre), np.nan)
    if limit is not None:
        for lw, lv in zip(*limit):  # the limit's bands as rail.roughness.read_limit_spectrum names them
            k = nominal_band(float(lw))
            hit = np.nonzero(bands.nominal == NOMINAL_WAVELENGTHS_M[k])[0] if k >= 0 else []
            if len(hit):
                lim[hit[0]] = lv
    ranked, rate_note = ranked_bands(ms[-1], floor_dB, ms_first=ms[0])
    # a band grown from nothing above the floor has no dB rate that means something, but its straight line in
    # amplitude (growth from the supports' source) does: it counts toward the grinding interval by that line
    grown = np.char.startswith(rate_note, "grown from nothing") & (g.law == "linear")
    gi = grinding_interval(n, ms, g, lim, per_day, ranked | grown)
    band = int(gi["band"])
    V = float(growth.attrs.get("speed_m_per_s", np.nan))
    dims = ("passage", "band")
    per_1e5 = f"per {AXLES_PER_RATE} axle passages"
    rates = {
        "growth_dB_per_1e5_axles": data_var("band", g.dB_rate, "dB per 100000 axle passages",
                                        "level growth rate of the band at the last save from its growth law: 20 log10(e) x "
                                        "efolding_rate_per_1e5_axles for an exponential, 20 log10(e) x amplitude rate / fitted amplitude for a "
                                        "straight line (falls as the amplitude grows)"),
        "growth_dB_per_1e5_axles_error": data_var("band", g.dB_error, "dB per 100000 axle passages", "standard error of growth_dB_per_1e5_axles"),
    }
    if traffic is not None:
        rates["growth_dB_per_year"] = data_var("band", traffic.per_year(g.dB_rate), "1/year",
                                           "level growth rate of the band per year of the traffic (growth_dB_per_1e5_axles x "
                                           "axles_per_day x 365 / 1e5)", level_unit="dB", units_text="dB/year")
        rates["growth_dB_per_MGT"] = data_var("band", traffic.per_mgt(g.dB_rate), "1/Mt",
                                          "level growth rate of the band per million gross tonnes (growth_dB_per_1e5_axles x "
                                          "1e6 / axle_load_t / 1e5)", level_unit="dB", units_text="dB/Mt")
    gi_attrs = {
        "grinding_interval_passages": float(gi["passages"]),
        "grinding_interval_days": float(gi["days"]),
        "grinding_interval_years": float(traffic.years(gi["passages"])) if traffic is not None else float("nan"),
        "grinding_interval_MGT": float(traffic.mgt(gi["passages"])) if traffic is not None else float("nan"),
        "grinding_interval_band_m": float(bands.nominal[band]) if band >= 0 else float("nan"),
        "computed_passages": float(n[-1]),
        # how far the interval lies beyond the computed passages: interval / last saved count (<= 1: within the run)
        "grinding_interval_extrapolation_factor": float(gi["passages"] / n[-1]) if np.isfinite(gi["passages"]) and n[-1] > 0 else float("nan"),
        "extrapolation_flag_factor": float(EXTRAPOLATION_FLAG_FACTOR),
        "extrapolation_definition": ("grinding_interval_extrapolation_factor = grinding_interval_passages / computed_passages (the last "
                                     "saved count): how far the interval extrapolates the fitted growth law beyond the computed run; "
                                     "flagged (grinding_interval_extrapolated = 1) above extrapolation_flag_factor"),
        "grinding_interval_definition": ("axle (wheel) passages until the first ranked band's level (or that of a band grown from "
                                         "nothing, by its straight line in amplitude), extrapolated with its own "
                                         "growth law (linear or exponential in amplitude), exceeds the limit (is above it by more "
                                         "than half a unit of the limit's last stated decimal); interpolated in ln amplitude "
                                         "between the saves when exceeded within the run; 0 and limit_exceeded_at_start = 1 when "
                                         "the initial roughness already exceeds the limit; inf when no band exceeds it; a band that "
                                         "decays (its law's rate not above zero, or its amplitude falling over the last saved "
                                         "interval) or whose rate is below twice its standard error sets none (limit_note)"),
        "limit_exceeded_at_start": int(gi["already"]),
    }
    gi_attrs["grinding_interval_extrapolated"] = int(bool(gi_attrs["grinding_interval_extrapolation_factor"] > EXTRAPOLATION_FLAG_FACTOR))
    decays = int(np.char.startswith(gi["note"], "not reached: the band decays").sum())
    flat = int(np.char.startswith(gi["note"], "not reached: its").sum())
    decay_text = f"{decays} ranked band{'s' if decays != 1 else ''} with a limit decay{'' if decays != 1 else 's'}" if decays else ""
    gi_attrs["bands_not_reached"] = ", ".join(t for t in (decay_text,
                                                          f"{flat} grow{'' if flat != 1 else 's'} indistinguishably from zero" if flat else "") if t)
    gi_attrs["grinding_interval_text"] = grinding_interval_text(gi_attrs, n[0], bool(np.isfinite(lim).any()))
    return xr.Dataset(
        {
            "level": data_var(dims, level, "dB re 1 um",
                          "one-third-octave band level of the roughness (rms); NaN where the band has no level (empty_reason)"),
            "resolved": data_var("band", resolved.astype(int), "1", "1 where the roughness period resolves the band (at least min_lines lines)"),
            "ranked": data_var("band", ranked.astype(int), "1", f"1 where the band's growth rate is ranked (grinding interval, "
                               f"figures): its level at the first and at the last save is at least the floor {floor_dB:g} dB re 1 um"),
            "rate_note": data_var("band", rate_note, "", "why the band's growth rate is not ranked ('' where it is)"),
            "empty_reason": data_var("band", reasons, "", "why the band has no level at some or all saves ('' where it has one at every save)"),
            **rates,
            "amplitude_growth_um_per_1e5_axles": data_var("band", g.linear_rate * 1e6, "um per 100000 axle passages",
                                                      "rms amplitude growth rate of the band (straight-line fit)"),
            "amplitude_growth_um_per_1e5_axles_error": data_var("band", g.linear_error * 1e6, "um per 100000 axle passages",
                                                            "standard error of the amplitude growth rate"),
            "efolding_rate_per_1e5_axles": data_var("band", g.exp_rate, "1 per 100000 axle passages",
                                                f"e-folding rate of the band's rms amplitude (exponential fit; x {DB_PER_NEPER:.4f} = dB)"),
            "efolding_rate_per_1e5_axles_error": data_var("band", g.exp_error, "1 per 100000 axle passages", "standard error of the e-folding rate"),
            "growth_law": data_var("band", g.law, "1", "the fit with the smaller misfit: linear or exponential"),
            "linear_misfit": data_var("band", g.linear_misfit, "1", "rms residual of the straight-line fit over the band's mean amplitude"),
            "exponential_misfit": data_var("band", g.exp_misfit, "1", "rms residual of the exponential fit over the band's mean amplitude"),
            "limit": data_var("band", lim, "dB re 1 um", "limit spectrum (NaN: no limit in the band)"),
            "limit_passages": data_var("band", gi["each"], "1", "axle passages until the band exceeds its limit (as the grinding "
                                       "interval, band by band); inf where not reached (limit_note)"),
            "limit_note": data_var("band", gi["note"], "", "why the band does not reach its limit ('' where it does): no limit, "
                                   "not ranked, the band decays, or its growth is not distinguished from zero"),
        },
        coords={
            "passage": data_var("passage", n, "1", "axle passages (wheel passages on the rail; a train of n axles counts n)"),
            "band": data_var("band", np.arange(len(bands.centre)), "1", "band index, longest wavelength first"),
            "centre_wavelength": data_var("band", bands.centre, "m", "exact centre wavelength 10^(-n/10) m"),
            "nominal_wavelength": data_var("band", bands.nominal, "m", "EN 15610 nominal centre wavelength"),
            "frequency": data_var("band", V / bands.centre, "Hz", f"excitation frequency V / centre wavelength at V = {V:g} m/s"),
            "days": data_var("passage", n / per_day if per_day else np.full(len(n), np.nan), "day", "days of traffic"),
            "years": data_var("passage", traffic.years(n) if traffic is not None else np.full(len(n), np.nan), "year", "years of traffic"),
            "mgt": data_var("passage", traffic.mgt(n) if traffic is not None else np.full(len(n), np.nan), "Mt", "million gross tonnes of traffic"),
        },
        attrs={
            **gi_attrs,
            **{k: growth.attrs[k] for k in VALIDITY_ATTRS if k in growth.attrs},  # the run's validity (rail.studies.validity)
            **{k: growth.attrs[k] for k in ("fleet_vehicles", "fleet_speeds") if k in growth.attrs},  # a fleet's run: its traffic
            "axles_per_day": float(per_day) if per_day else float("nan"),
            **({k: v for k, v in traffic.attributes().items() if k != "axles_per_day"} if traffic is not None else {}),
            "rate_convention": f"level growth in dB {per_1e5} (a wheel passage on the rail is an axle passage), per year and per MGT "
                               "with the traffic (docs/exports.md)",
            "bays": N,
            "period_m": float(N * L),
            "shortest_wavelength_m": float(N * L / J),
            "speed_m_per_s": V,
            "processing": "lines of the periodic profile summed per band (no window); rail/studies/bands.py",
            "rate_floor_dB_re_1um": float(floor_dB),
            "rate_floor_definition": ("a band whose level at the last save is below the floor, or whose level at the first save is "
                                      "(grown from nothing), is not ranked: its dB rate is the growth of a roughness from nothing, "
                                      "not a feedback rate (docs/studies.md)"),
        },
    )


def grinding_interval_text(attrs: dict, first: float, has_limit: bool) -> str:
    """The grinding interval in words for a title or a header, readable numbers (82,300, not 8.23e+04).

    Parameters
    ----------
    attrs : dict
        The grinding_interval_* attributes of bands_dataset.
    first : float
        The first saved passage count [-].
    has_limit : bool
        Whether a limit spectrum was given.

    Returns
    -------
    str
    """
    gi, band = attrs["grinding_interval_passages"], attrs["grinding_interval_band_m"]
    decaying = attrs.get("bands_not_reached", "")
    if not has_limit:
        return "no limit spectrum given"
    if attrs["limit_exceeded_at_start"] and gi <= first:
        return f"limit already exceeded by the initial roughness (the {1e3 * band:g} mm band)"
    if not np.isfinite(gi):
        return "not reached: no ranked band grows toward the limit" + (f" ({decaying})" if decaying else "")
    years, mgt, days = attrs["grinding_interval_years"], attrs["grinding_interval_MGT"], attrs["grinding_interval_days"]
    when = (f" ({years:.3g} years, {mgt:.3g} MGT)" if np.isfinite(years) and np.isfinite(mgt)
            else f" ({days:,.0f} days)" if np.isfinite(days) else "")
    text = f"limit exceeded after {readable_count(gi)} axle passages{when}, set by the {1e3 * band:g} mm band"
    return text + "; " + extrapolation_text(attrs)


def extrapolation_text(attrs: dict) -> str:
    """How far a finite grinding interval lies beyond the computed passages, in words: "reached within the
    computed 100,000 axle passages", "extrapolated x3.2 beyond the computed 100,000 axle passages", or,
    above the flag factor, "EXTRAPOLATED x870 beyond the computed 100,000 axle passages (flagged: more
    than x10)".

    Parameters
    ----------
    attrs : dict
        The attributes of bands_dataset (computed_passages, grinding_interval_extrapolation_factor,
        extrapolation_flag_factor).

    Returns
    -------
    str
        '' where the attributes do not state the factor.
    """
    if "grinding_interval_extrapolation_factor" not in attrs:
        return ""
    factor, done = float(attrs["grinding_interval_extrapolation_factor"]), float(attrs["computed_passages"])
    flag = float(attrs.get("extrapolation_flag_factor", EXTRAPOLATION_FLAG_FACTOR))
    if not np.isfinite(factor):
        return ""
    computed = f"the computed {readable_count(done)} axle passages"
    if factor <= 1:
        return f"reached within {computed}"
    if factor > flag:
        return f"EXTRAPOLATED x{readable_count(factor, 2)} beyond {computed} (flagged: more than x{flag:g})"
    return f"extrapolated x{readable_count(factor, 2)} beyond {computed}"


def band_csv_text(ds) -> str:
    """The band export (docs/exports.md): '#' header lines with the conventions, the traffic and the
    grinding interval with its band; one row per band with its wavelength, frequency V / lambda at the
    run's speed, the level at every saved passage count, the growth rates and the limit. A band with
    no level has an empty cell and its reason in the last column (never -inf).

    Parameters
    ----------
    ds : xarray.Dataset
        From bands_dataset.

    Returns
    -------
    str
    """
    n = ds["passage"].values
    a = ds.attrs
    fleet = "fleet_speeds" in a
    head = ["# one-third-octave band levels of the rail roughness and their growth (rail.studies.bands; docs/exports.md)",
            f"# {'fleet at mean ' if fleet else ''}speed {a['speed_m_per_s']:g} m/s; frequency_Hz = speed / centre wavelength; roughness "
            f"period {a['period_m']:.4g} m ({a['bays']} bays), shortest wavelength {1e3 * a['shortest_wavelength_m']:.3g} mm",
            *([f"# fleet: {a['fleet_vehicles']}; speeds {a['fleet_speeds']}; passages are axle passages of the fleet's traffic"]
              if fleet else []),
            "# levels in dB re 1 um (rms); rates: dB per 100,000 axle passages (wheel passages on the rail)"
            + (", dB/year and dB/MGT with the traffic" if "growth_dB_per_year" in ds else "; no traffic given: no rates per year or MGT"),
            f"# traffic: {a['axles_per_day']:g} axles/day" + (f", axle load {a['axle_load_t']:.4g} t, {a['mgt_per_year']:.4g} MGT/year"
                                                             if "axle_load_t" in a else ""),
            "# empty cell: the band has no level there (reason in the column empty_reason)",
            f"# ranked: 1 where the band's growth rate counts (grinding interval, figures); 0 where its level at the last save is below "
            f"the floor {a.get('rate_floor_dB_re_1um', RATE_FLOOR_DB):g} dB re 1 um, or started below it (grown from nothing): its dB rate is "
            "growth from nothing, not a feedback rate, and its dB rate cells are empty (reason in rate_note)"]
    head.append("# grinding interval: " + a["grinding_interval_text"])
    if "grinding_interval_extrapolation_factor" in a:
        factor = a["grinding_interval_extrapolation_factor"]
        head.append(f"# extrapolation: grinding_interval_extrapolation_factor={factor:.4g}" if np.isfinite(factor) else
                    "# extrapolation: grinding_interval_extrapolation_factor= (no finite interval)")
        head[-1] += (f" (interval / the computed {readable_count(a['computed_passages'])} axle passages; flagged above "
                     f"x{a['extrapolation_flag_factor']:g}{': FLAGGED' if a.get('grinding_interval_extrapolated') else ''})")
    head.append("# validity: " + (validity_text(a) or "not stated"))
    head.append("# " + "; ".join(f"{k}={a[k]:.6g}" if np.isfinite(a[k]) else f"{k}=" for k in
                                 ("grinding_interval_passages", "grinding_interval_years", "grinding_interval_MGT", "grinding_interval_band_m"))
                + " (axle passages, years, MGT, band in m; empty: no finite interval, see above)")
    cols = ["nominal_wavelength_m", "centre_wavelength_m", "frequency_Hz", "resolved"]
    cols += [f"level_dB_re_1um_at_{int(p)}_axle_passages" for p in n]
    rate_cols = [c for c in ("growth_dB_per_1e5_axles", "growth_dB_per_1e5_axles_error", "growth_dB_per_year", "growth_dB_per_MGT",
                             "amplitude_growth_um_per_1e5_axles") if c in ds]
    cols += rate_cols + ["growth_law", "ranked", "rate_note", "limit_dB_re_1um", "empty_reason"]

    def cell(v, fmt=".4g"):
        text = f"{v:{fmt}}" if np.isfinite(v) else ""
        return text[1:] if text.startswith("-") and float(text) == 0 else text  # no "-0.000" for a level of -1e-15 dB

    rows = [",".join(cols)]
    for b in range(ds.sizes["band"]):
        cells = [f"{ds['nominal_wavelength'].values[b]:g}", f"{ds['centre_wavelength'].values[b]:.8g}",
                 cell(float(ds["frequency"].values[b]), ".5g"), str(int(ds["resolved"].values[b]))]
        cells += [cell(v, ".3f") for v in ds["level"].values[:, b]]
        # a band grown from nothing or below the floor: its dB rate is no feedback rate, left empty (rate_note); its
        # amplitude rate stays
        no_dB = "ranked" in ds and not int(ds["ranked"].values[b])
        cells += ["" if no_dB and c.startswith("growth_dB") else cell(float(ds[c].values[b])) for c in rate_cols]
        note = str(ds["rate_note"].values[b]) if "rate_note" in ds else ""
        cells += [str(ds["growth_law"].values[b]), str(int(ds["ranked"].values[b])) if "ranked" in ds else "1",
                  '"' + note.replace('"', "'") + '"' if note else "", cell(float(ds["limit"].values[b]), "g"),
                  '"' + str(ds["empty_reason"].values[b]).replace('"', "'") + '"' if ds["empty_reason"].values[b] else ""]
        rows.append(",".join(cells))
    return "\n".join(head + rows) + "\n"


def write_band_csv(ds, path) -> None:
    """Write band_csv_text(ds) to ``path``.

    Parameters
    ----------
    ds : xr.Dataset
        A band dataset (rail.studies.bands).
    path : str or Path
        The CSV file.

    Returns
    -------
    None
    """
    with open(path, "w") as f:
        f.write(band_csv_text(ds))


def sweep_band_map(runs, keys, values, indices, units, L: float, bands: ThirdOctaveBands, min_lines: int = 1):
    """Band growth over the grid of a sweep study: a dimension per swept key and one for the band.

    Parameters
    ----------
    runs : list of xarray.Dataset
        Growth results of the grid points (rail.studies.datasets.growth), in the order of indices.
    keys, values, indices
        Swept keys, their values, and each run's grid index (rail.setup.config.expand_sweep).
    units : sequence of str
        The unit of each key, as the schema states it (rail.setup.config.schema_unit).
    L : float
        Sleeper spacing [m].
    bands : ThirdOctaveBands
    min_lines : int
        Lines a band must hold to be resolved [-].

    Returns
    -------
    xarray.Dataset
        growth_dB_per_1e5_axles [dB per 1e5 axle passages, at the last save from the band's law],
        amplitude_growth_um_per_1e5_axles [µm per 1e5 axle passages] and its error, the preferred law
        and the final band level [dB re 1 µm, NaN where empty] per grid point and band.
    """
    import xarray as xr

    from ..setup.io import data_var
    from .datasets import sweep_coords

    dims, coords = sweep_coords(keys, values, units)
    shape = tuple(len(v) for v in values) + (len(bands.centre),)
    rate, err, final, dB = np.full(shape, np.nan), np.full(shape, np.nan), np.full(shape, np.nan), np.full(shape, np.nan)
    law = np.full(shape, "", dtype=object)
    for run, idx in zip(runs, indices):
        N = int(run.attrs.get("bays", 1))
        Z = run["Z_real"].values + 1j * run["Z_imag"].values
        ms, _ = band_mean_square(Z, N * L, bands, min_lines)
        g = band_growth(run["passage"].values, ms)
        rate[tuple(idx)], err[tuple(idx)], law[tuple(idx)] = g.linear_rate * 1e6, g.linear_error * 1e6, g.law
        dB[tuple(idx)] = g.dB_rate
        final[tuple(idx)] = np.where(ms[-1] > 0, 10 * np.log10(np.where(ms[-1] > 0, ms[-1], 1.0) / 1e-12), np.nan)
    coords["nominal_wavelength"] = data_var("band", bands.nominal, "m", "EN 15610 nominal centre wavelength of the band")
    full = dims + ("band",)
    return xr.Dataset(
        {
            "growth_dB_per_1e5_axles": data_var(full, dB, "dB per 100000 axle passages",
                                            "level growth rate of the band at the last save from its growth law (bands_dataset)"),
            "amplitude_growth_um_per_1e5_axles": data_var(full, rate, "um per 100000 axle passages",
                                                      "rms amplitude growth rate of the band (straight-line fit)"),
            "amplitude_growth_um_per_1e5_axles_error": data_var(full, err, "um per 100000 axle passages", "standard error of the growth rate"),
            "growth_law": data_var(full, law.astype(str), "1", "the fit with the smaller misfit: linear or exponential"),
            "level": data_var(full, final, "dB re 1 um", "band level at the end of the run (NaN: the band has no level)"),
        },
        coords=coords,
        attrs={"swept_keys": list(keys)},
    )
