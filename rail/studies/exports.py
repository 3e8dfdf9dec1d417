"""Exports in the form practice reads (docs/exports.md): the narrow-band levels of a growth run, the
growth-rate spectrum, and the one-third-octave roughness for rolling-noise tools (TWINS, CNOSSOS-EU).

Conventions (rail.traffic): levels in dB re 1 µm rms; growth in dB per 100,000 axle (wheel)
passages, and per year and per MGT with the traffic; a frequency axis f = V / lambda at the
scenario's speed; a quantity that has no value is an empty cell with its reason, never -inf.
The band export of a growth run is rail.studies.bands.band_csv_text.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..bands import NOMINAL_TOLERANCE, NOMINAL_WAVELENGTHS_M, ThirdOctaveBands, exact_centres, exact_edges, wavelength_bands
from ..traffic import AXLES_PER_RATE, DB_PER_NEPER, Traffic
from . import bands as band_view
from .bands import RATE_FLOOR_DB, band_mean_square, empty_band_reasons
from .validity import validity_text

__all__ = ["ROLLING_NOISE_WAVELENGTHS_M", "rolling_noise_bands", "rolling_noise_levels", "combined_roughness",
           "wheel_levels_on_bands", "spectrum_on_bands", "rolling_noise_csv_text", "BandOutputs", "band_outputs",
           "narrow_band_csv_text", "spectrum_csv_text", "spectrum_rates"]

# Nominal centre wavelengths [m] of the one-third-octave bands CNOSSOS-EU tabulates rail and wheel
# roughness in (Directive (EU) 2015/996, Annex II sec. 2.3 and Appendix G, Table G-1: 2000 mm down
# to 0.8 mm), the exact centres 10^(-n/10) m for n = -3..31; the EN 15610 labels (rail.bands)
# inside 1 m .. 3.15 mm. (Table G-1 prints 125, 12.5, 3.15 and 1.25 mm as 120, 12, 3.2 and 1.2 mm.)
ROLLING_NOISE_WAVELENGTHS_M = np.concatenate([[2.0, 1.6, 1.25], NOMINAL_WAVELENGTHS_M, [0.0025, 0.002, 0.0016, 0.00125, 0.001, 0.0008]])


def rolling_noise_bands() -> ThirdOctaveBands:
    """The one-third-octave wavelength bands of the rolling-noise export, 2000 mm .. 0.8 mm.

    Returns
    -------
    ThirdOctaveBands
        Exact centres 10^(-n/10) m, n = -3..31, edges at 10^(+-1/20) of the centre (rail.bands.exact_edges).
    """
    n = np.arange(-3, 32)
    lower, upper = exact_edges(n, "m")  # the one edge rule (rail.bands)
    return ThirdOctaveBands(centre=exact_centres(n, "m"), nominal=ROLLING_NOISE_WAVELENGTHS_M.copy(), lower=lower, upper=upper, unit="m")


def rolling_noise_levels(Z, period: float, min_lines: int = 1):
    """One-third-octave rail roughness levels L_r [dB re 1 µm] of a periodic roughness, 2000 mm .. 0.8 mm.

    The processing of rail.studies.bands (lines of the period summed per band, no window, no
    averaging needed: the profile is periodic and known exactly).

    Parameters
    ----------
    Z : ndarray, shape (2J + 1,)
        Roughness coefficients [m] over the period (j = -J..J).
    period : float
        N L [m].
    min_lines : int
        Lines a band must hold to be resolved [-].

    Returns
    -------
    level : ndarray, shape (35,)
        L_r = 10 log10(mean square / (1 µm)^2); NaN where the band has no level.
    reasons : ndarray of str
        Why a band is empty ('' where it has a level).
    """
    Z = np.asarray(Z)
    bands = rolling_noise_bands()
    ms, resolved = band_mean_square(Z, period, bands, min_lines)
    J = (Z.shape[-1] - 1) // 2
    level = np.where(ms > 0, 10 * np.log10(np.where(ms > 0, ms, 1.0) / 1e-12), np.nan)
    return level, empty_band_reasons(bands, period, period / J, resolved, ms[None, :], min_lines)


def wheel_levels_on_bands(wavelength, level, source: str = "wheel roughness") -> np.ndarray:
    """A wheel roughness spectrum (rail.roughness.read_third_octave_spectrum) on the rolling-noise
    bands: each wavelength must name one of them (within 1.5 % of its nominal label or exact centre,
    rail.bands.NOMINAL_TOLERANCE); bands it does not give are NaN.

    Parameters
    ----------
    wavelength : array-like
        Band centre wavelengths [m].
    level : array-like
        Wheel roughness levels [dB re 1 µm].
    source : str
        Named in an error (the file).

    Returns
    -------
    ndarray, shape (35,)
        [dB re 1 µm] per band of rolling_noise_bands.

    Raises
    ------
    ValueError
        Naming the wavelength and the nearest band when it names none, or a band given twice.
    """
    bands = rolling_noise_bands()
    out = np.full(len(bands.centre), np.nan)
    for v, lv in zip(np.asarray(wavelength, dtype=float), np.asarray(level, dtype=float)):
        off = np.minimum(np.abs(v / bands.nominal - 1), np.abs(v / bands.centre - 1))
        k = int(np.argmin(off))
        if off[k] > NOMINAL_TOLERANCE:
            raise ValueError(f"{source}: wavelength {v:g} m is not a one-third-octave band centre: the nearest band is "
                             f"{bands.nominal[k]:g} m ({100 * (v / bands.nominal[k] - 1):+.1f} %); give the nominal centres "
                             f"2 m .. 0.8 mm or the exact 10^(-n/10) m, within {100 * NOMINAL_TOLERANCE:g} %.")
        if np.isfinite(out[k]):
            raise ValueError(f"{source}: wavelength {v:g} m names the band {bands.nominal[k]:g} m again.")
        out[k] = lv
    return out


def spectrum_on_bands(wavelength, level) -> np.ndarray:
    """An input spectrum (the initial roughness's) on the rolling-noise bands: a wavelength within
    rail.bands.NOMINAL_TOLERANCE of a band's nominal label or exact centre gives its level; other
    wavelengths are left out (a spectrum input may use any centres).

    Parameters
    ----------
    wavelength, level : array-like
        Band centres [m] and levels [dB re 1 µm].

    Returns
    -------
    ndarray, shape (35,)
        [dB re 1 µm]; NaN where the input gives no level.
    """
    bands = rolling_noise_bands()
    out = np.full(len(bands.centre), np.nan)
    for v, lv in zip(np.asarray(wavelength, dtype=float), np.asarray(level, dtype=float)):
        off = np.minimum(np.abs(v / bands.nominal - 1), np.abs(v / bands.centre - 1))
        k = int(np.argmin(off))
        if off[k] <= NOMINAL_TOLERANCE:
            out[k] = lv
    return out


def combined_roughness(rail_dB, wheel_dB):
    """Combined wheel and rail roughness per band, the energy sum 10 log10(10^(L_r/10) + 10^(L_w/10))
    [dB re 1 µm] (CNOSSOS-EU 2.3.2 before its contact filter; the wheel and rail roughness are
    incoherent). NaN where either is NaN.

    Parameters
    ----------
    rail_dB, wheel_dB : array-like
        Rail and wheel roughness levels per band [dB re 1 µm].

    Returns
    -------
    ndarray
    """
    r, w = np.asarray(rail_dB, dtype=float), np.asarray(wheel_dB, dtype=float)
    return 10 * np.log10(10 ** (r / 10) + 10 ** (w / 10))


def _cell(v, fmt=".4g") -> str:
    text = f"{v:{fmt}}" if np.isfinite(v) else ""
    return text[1:] if text.startswith("-") and float(text) == 0 else text  # no "-0.00" for a level of -1e-15 dB


def _quoted(text: str) -> str:
    return '"' + text.replace('"', "'") + '"' if text else ""


def rolling_noise_csv_text(level, reasons, period: float, shortest: float, speed: float, state: str,
                           wheel_dB=None, wheel_source: str = "", grinding: str = "", validity: str = "",
                           floor_dB: float | None = None, input_dB=None, input_source: str = "") -> str:
    """The roughness export for rolling-noise tools: one row per one-third-octave wavelength band
    from 2000 mm to 0.8 mm, the first two columns (wavelength in mm, L_r in dB re 1 µm) the form
    CNOSSOS-EU (Table G-1) and TWINS (roughness level per third-octave wavelength band) take.

    Parameters
    ----------
    level : ndarray, shape (35,)
        Rail roughness levels (rolling_noise_levels) [dB re 1 µm].
    reasons : ndarray of str
        Why a band is empty.
    period, shortest : float
        The record: roughness period N L and its shortest wavelength [m].
    speed : float
        Train speed for the frequency column [m/s].
    state : str
        Which roughness this is (e.g. 'after 600,000 axle passages').
    wheel_dB : ndarray, optional
        Wheel roughness per band [dB re 1 µm]: adds the combined wheel + rail column. Without it the
        export is rail-only and says so.
    wheel_source : str
        Where the wheel roughness comes from (stated in the header).
    grinding : str
        The grinding interval with its band (rail.studies.bands.grinding_interval_text), for the header.
    validity : str
        The result's validity (rail.studies.datasets.validity_text of its growth run), for the header.
    floor_dB : float, optional
        A band the model gives below it [dB re 1 µm] is left out, with its reason (rail.studies.bands:
        its level is growth from nothing).
    input_dB : ndarray, shape (35,), optional
        The initial roughness's input spectrum on these bands (spectrum_on_bands): fills the bands
        outside the model's range (longer than N L, shorter than its shortest wavelength); the column
        source says which level came from where. Without it those bands are left out.
    input_source : str
        The input spectrum's file, for the header.

    Returns
    -------
    str
    """
    bands = rolling_noise_bands()
    level = np.asarray(level, dtype=float).copy()
    reasons = np.asarray(reasons, dtype=object).copy()
    source = np.where(np.isfinite(level), "model", "").astype(object)
    if floor_dB is not None:
        low = np.isfinite(level) & (level < floor_dB)
        for b in np.nonzero(low)[0]:
            reasons[b] = (f"below the floor: the model gives {level[b]:.1f} dB re 1 um < {floor_dB:g} dB re 1 um, growth from "
                          "nothing; left out")
            level[b], source[b] = np.nan, ""
    outside = np.array([str(r).startswith("not resolved") for r in reasons])
    if input_dB is not None:
        input_dB = np.asarray(input_dB, dtype=float)
        fill = outside & np.isfinite(input_dB)
        level[fill], source[fill] = input_dB[fill], "input spectrum"
        reasons[fill] = ""
        for b in np.nonzero(outside & ~fill)[0]:
            reasons[b] = str(reasons[b]) + "; the input spectrum gives no level in the band"
    model = source == "model"
    head = [
        "# rail roughness for rolling-noise tools (TWINS, CNOSSOS-EU L_r per one-third octave band of wavelength, 2000 mm .. 0.8 mm)",
        f"# roughness: {state}; levels L = 10 log10(mean square / (1 um)^2), dB re 1 um rms",
        f"# processing: the computed profile is periodic over N L = {period:.4g} m and known exactly as its Fourier lines "
        "2 pi j / (N L); a band's mean square is the sum of its lines' mean squares (Parseval, no window, no averaging "
        "over records needed); band edges at 10^(+-1/20) of the exact centre 10^(-n/10) m (rail/studies/bands.py)",
        f"# record: length N L = {period:.4g} m, shortest wavelength {1e3 * shortest:.3g} mm; bands from the model: "
        + (f"{1e3 * bands.nominal[model].max():g} mm .. {1e3 * bands.nominal[model].min():g} mm"
           if model.any() else "none")
        + "; other bands empty (reason in empty_reason) or filled as the next line says",
        "# bands outside the model's range (longer than N L or shorter than its shortest wavelength): "
        + (f"filled from the input spectrum {input_source or ''} (the initial roughness, column source = input spectrum) where it "
           "gives a level, otherwise left out" if input_dB is not None else "left out (empty; the initial roughness is no spectrum "
                                                                              "to fill them from)")
        + (f"; bands the model gives below {floor_dB:g} dB re 1 um (growth from nothing) left out" if floor_dB is not None else ""),
        f"# frequency_Hz = V / centre wavelength at V = {speed:g} m/s",
        f"# grinding interval: {grinding or 'not computed for this roughness'}",
        f"# validity: {validity or 'not stated'}",
    ]
    cols = ["wavelength_mm", "rail_roughness_dB_re_1um"]
    if wheel_dB is not None:
        wheel_dB = np.asarray(wheel_dB, dtype=float)
        comb = combined_roughness(level, wheel_dB)
        head.append(f"# wheel roughness: {wheel_source or 'given'}; combined = 10 log10(10^(L_rail/10) + 10^(L_wheel/10)), "
                    "no contact filter applied; empty where the rail or the wheel has no level in the band")
        cols += ["wheel_roughness_dB_re_1um", "combined_roughness_dB_re_1um"]
    else:
        head.append("# rail-only export: the configuration gives no wheel roughness, so no combined wheel + rail roughness")
    cols += ["source", "centre_wavelength_m", "frequency_Hz", "empty_reason"]
    rows = [",".join(cols)]
    for b in range(len(bands.centre)):
        cells = [f"{1e3 * bands.nominal[b]:g}", _cell(level[b], ".2f")]
        if wheel_dB is not None:
            cells += [_cell(wheel_dB[b], ".2f"), _cell(comb[b], ".2f")]
        cells += [str(source[b]), f"{bands.centre[b]:.8g}", _cell(speed / bands.centre[b], ".6g"), _quoted(str(reasons[b]))]
        rows.append(",".join(cells))
    return "\n".join(head + rows) + "\n"


def narrow_band_csv_text(growth, L: float, traffic: Traffic | None = None, grinding: str = "") -> str:
    """The narrow-band levels of a growth run (rail.studies.datasets.growth): one row per line of the
    period (wavelength N L / j), its frequency V / lambda, its level at every saved count and its
    growth rates. Empty cells where a line has no roughness (e.g. the smooth rail at the start).

    Parameters
    ----------
    growth : xarray.Dataset
    L : float
        Sleeper spacing [m].
    traffic : rail.traffic.Traffic, optional
        For the rates per year and per MGT.
    grinding : str
        The grinding interval with its band (rail.studies.bands.grinding_interval_text), for the header.

    Returns
    -------
    str
    """
    N = int(growth.attrs.get("bays", 1))
    V = float(growth.attrs.get("speed_m_per_s", np.nan))
    j = growth["harmonic"].values
    lam = N * L / j
    n = growth["passage"].values
    lev = growth["level"].values
    if "growth_dB_per_1e5_axles" in growth:
        rate, amp = growth["growth_dB_per_1e5_axles"].values, growth["amplitude_growth_um_per_1e5_axles"].values
    else:  # a growth file written before the one convention: exponential_rate per passage, m per 10,000 passages
        rate = DB_PER_NEPER * growth["exponential_rate"].values * AXLES_PER_RATE
        amp = growth["amplitude_growth_rate"].values * 1e6 * AXLES_PER_RATE / 1e4
    head = ["# narrow-band roughness levels of a growth run (rail.studies.datasets.growth; docs/exports.md)",
            f"# lines 2 pi j / (N L) of the roughness period N L = {N * L:.4g} m; frequency_Hz = V / wavelength at V = {V:g} m/s",
            "# levels: rms of each line, dB re 1 um; empty cell: no roughness at that line and count",
            f"# growth rates: at the last save from the law (straight line or exponential in amplitude) that fits the line, as for the bands, "
            f"dB per {AXLES_PER_RATE:,} axle passages (wheel passages on the rail)"
            + (f"; per year and per MGT with {traffic.axles_per_day:g} axles/day and axle load {traffic.axle_load_t:.4g} t"
               if traffic is not None else "; no traffic given"),
            "# empty growth rate: the line has no roughness, or its straight-line fit ends at zero amplitude",
            f"# grinding interval (one-third-octave bands against the limit): {grinding or 'not computed'}",
            f"# validity: {validity_text(growth.attrs) or 'not stated'}"]
    cols = ["line_j", "wavelength_m", "frequency_Hz"] + [f"level_dB_re_1um_at_{int(p)}_axle_passages" for p in n]
    cols += ["growth_dB_per_1e5_axles"] + (["growth_dB_per_year", "growth_dB_per_MGT"] if traffic is not None else [])
    cols += ["amplitude_growth_um_per_1e5_axles"]
    rows = [",".join(cols)]
    for i in range(len(j)):
        cells = [str(int(j[i])), f"{lam[i]:.8g}", _cell(V / lam[i], ".8g")] + [_cell(v, ".3f") for v in lev[:, i]]
        cells.append(_cell(rate[i]))
        if traffic is not None:
            cells += [_cell(float(traffic.per_year(rate[i]))), _cell(float(traffic.per_mgt(rate[i])))]
        cells.append(_cell(amp[i]))
        rows.append(",".join(cells))
    return "\n".join(head + rows) + "\n"


def spectrum_rates(growth_rate_per_train, axles_per_train: float, traffic: Traffic | None = None) -> dict:
    """A growth-rate spectrum's rates in the export convention.

    Parameters
    ----------
    growth_rate_per_train : array-like
        Relative growth rate of the amplitude per train passage, -Re R [-].
    axles_per_train : float
        Axles (wheels on the rail) per train passage [-].
    traffic : rail.traffic.Traffic, optional

    Returns
    -------
    dict
        'growth_dB_per_1e5_axles' = 20 log10(e) g 1e5 / axles_per_train, and with the traffic
        'growth_dB_per_year', 'growth_dB_per_MGT'.
    """
    g = np.asarray(growth_rate_per_train, dtype=float)
    if not (np.isfinite(axles_per_train) and axles_per_train > 0):
        raise ValueError(f"axles_per_train = {axles_per_train!r} is not allowed: it must be a finite number > 0.")
    d = DB_PER_NEPER * g * AXLES_PER_RATE / axles_per_train
    out = {"growth_dB_per_1e5_axles": d}
    if traffic is not None:
        out["growth_dB_per_year"] = traffic.per_year(d)
        out["growth_dB_per_MGT"] = traffic.per_mgt(d)
    return out


def spectrum_csv_text(ds) -> str:
    """The growth-rate spectrum (rail.studies.rate_spectrum.rate_spectrum_dataset) as CSV: one row
    per (speed, wavelength) with the frequency V / lambda and the growth in dB per 100,000 axle
    passages (and per year and per MGT where the dataset holds them).

    Parameters
    ----------
    ds : xarray.Dataset

    Returns
    -------
    str
    """
    a = ds.attrs
    rate_cols = [c for c in ("growth_dB_per_1e5_axles", "growth_dB_per_year", "growth_dB_per_MGT") if c in ds]
    head = ["# growth-rate spectrum of a small roughness on the smooth rail (rail.growth_spectrum; docs/exports.md)",
            f"# rates: dB per {AXLES_PER_RATE:,} axle passages (wheel passages on the rail; a train passage is "
            f"{a.get('wheels', '?')} axles)" + (f", per year and per MGT with {a['axles_per_day']:g} axles/day and axle load "
                                                f"{a['axle_load_t']:.4g} t" if "growth_dB_per_year" in ds else "; no traffic given"),
            "# frequency_Hz = speed / wavelength; growth_rate_per_train = -Re R, relative amplitude growth per train passage",
            "# locked: 0 free line, 1 on the one-bay comb L/k, 2 on the half-comb 2L/(2k+1)",
            "# grinding interval: none here (the spectrum is the growth rate of a small roughness, not a roughness against a "
            "limit); see the band export of a growth run, V<speed>_bands.csv",
            f"# validity: {validity_text(a) or 'not stated'}"]
    cols = ["speed_m_per_s", "wavelength_m", "frequency_Hz"] + rate_cols + ["growth_rate_per_train", "locked"]
    rows = [",".join(cols)]
    lam = ds["wavelength"].values
    for i, v in enumerate(ds["speed"].values):
        for k in range(len(lam)):
            cells = [f"{v:g}", f"{lam[k]:.8g}", _cell(float(ds["frequency"].values[i, k]), ".8g")]
            cells += [_cell(float(ds[c].values[i, k])) for c in rate_cols]
            cells += [_cell(float(ds["growth_rate"].values[i, k]), ".6g"), str(int(ds["locked"].values[k]))]
            rows.append(",".join(cells))
    return "\n".join(head + rows) + "\n"


@dataclass(frozen=True)
class BandOutputs:
    """The band view of a growth run and its three exports (band_outputs).

    data              : xarray.Dataset of rail.studies.bands.bands_dataset
    bands_csv         : the band export (rail.studies.bands.band_csv_text)
    narrow_csv        : the narrow-band export (narrow_band_csv_text)
    rolling_noise_csv : the roughness for rolling-noise tools at the last save (rolling_noise_csv_text)
    """

    data: object
    bands_csv: str
    narrow_csv: str
    rolling_noise_csv: str


def band_outputs(growth, L: float, settings: dict, name: str, *, limit=None, traffic: Traffic | None = None, wheel=None,
                 initial_spectrum=None, floor_dB: float = RATE_FLOOR_DB) -> BandOutputs:
    """Bands, growth per band, grinding interval and the exports of any growth dataset: a one-train run
    (results/growth/<scenario>/V<speed>.nc) or a fleet run (results/fleet/<scenario>/growth.nc) alike;
    the one code path of the workflow, the command line and the API.

    Parameters
    ----------
    growth : xarray.Dataset
        A growth result (rail.studies.datasets.growth): Z_real, Z_imag, level per saved passage count.
    L : float
        Sleeper spacing [m].
    settings : dict
        figures.bands of the configuration: longest, shortest [m], min_lines [-].
    name : str
        The scenario, for the exports' headers.
    limit : (wavelength [m], level [dB re 1 µm]), optional
        The limit spectrum (rail.roughness.read_limit_spectrum).
    traffic : rail.traffic.Traffic, optional
        Rates per year and per MGT, the interval in years and MGT.
    wheel : (wavelength [m], level [dB re 1 µm], source), optional
        Wheel roughness for the combined roughness of the rolling-noise export.
    initial_spectrum : (wavelength [m], level [dB re 1 µm], source), optional
        The initial roughness's input spectrum: fills the rolling-noise bands outside the model's range.
    floor_dB : float
        Bands below it at the last save are not ranked and left out of the rolling-noise export
        [dB re 1 µm].

    Returns
    -------
    BandOutputs
    """
    from .validity import validity_text as _validity

    tob = wavelength_bands(float(settings["longest"]), float(settings["shortest"]))
    min_lines = int(settings["min_lines"])
    ds = band_view.bands_dataset(growth, L, tob, min_lines, limit, traffic=traffic, floor_dB=floor_dB)
    grinding = ds.attrs["grinding_interval_text"]
    narrow = narrow_band_csv_text(growth, L, traffic, grinding)
    period = int(growth.attrs.get("bays", 1)) * L
    Z = growth["Z_real"].values[-1] + 1j * growth["Z_imag"].values[-1]
    level, reasons = rolling_noise_levels(Z, period, min_lines)
    wheel_dB = wheel_levels_on_bands(wheel[0], wheel[1], source=wheel[2]) if wheel is not None else None
    input_dB = spectrum_on_bands(initial_spectrum[0], initial_spectrum[1]) if initial_spectrum is not None else None
    rolling = rolling_noise_csv_text(level, reasons, period, period / ((Z.size - 1) // 2), float(ds.attrs["speed_m_per_s"]),
                                     f"scenario {name}{' under its fleet (frequency at its mean speed)' if 'fleet_speeds' in growth.attrs else ''}"
                                     f" after {band_view.readable_count(growth['passage'].values[-1])} axle passages "
                                     "(the last save of the growth run)", wheel_dB=wheel_dB,
                                     wheel_source=wheel[2] if wheel is not None else "", grinding=grinding,
                                     validity=_validity(growth.attrs), floor_dB=floor_dB, input_dB=input_dB,
                                     input_source=initial_spectrum[2] if initial_spectrum is not None else "")
    return BandOutputs(ds, band_view.band_csv_text(ds), narrow, rolling)
