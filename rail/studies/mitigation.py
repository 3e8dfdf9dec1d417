"""Which mitigation reduces the band near pinned-pinned (issue 55; config/studies/track_mitigation.yaml, docs/field.md
"Mitigation").

Each case's growth-rate spectrum (with the wheels' source: rail.studies.wheel_source) at a nominal speed V, on the
same lines for every case at that speed, and the mixtures a fleet makes of them:

* a speed spread: the weights w = 1/4, 1/2, 1/4 at V (1 - d), V, V (1 + d) (SPREAD), the default track's case
  computed at the three speeds;
* a driven-axle share s: the motored wheelset's case with the weight s, the trailer's with 1 - s (SHARES).

A fleet passage is one train drawn from the classes (rail.chain.fleet_wear): with one wheel per train (the default
train) the fleet's rate per axle passage on a line is sum_c w_c R_c, its supports' comb sum_c w_c s_c (fixed to the
rail: coherent), and its wheels' source sum_c w_c Q_c (each wheel a random phase); the expected mean square then obeys
S_{n+1} = a S_n + Q with a = sum_c w_c abs(1 - R_c)^2 = abs(1 - sum_c w_c R_c)^2 + O(R^2), and the rates per passage
here are below 1e-4 (an error below 1e-8 of a in the time to the limit). The band's peak, edges and width are
rail.growth_spectrum.band.band_edges' over 0.9-1.3 f_pp.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from ..growth_spectrum.band import band_edges
from ..setup.io import data_var

__all__ = ["BAND_WINDOW", "KINDS", "SHARES", "SPREAD", "SPREAD_WEIGHTS", "at_speed", "band_row", "header_text", "interval", "mitigation_rows",
           "mixture", "on_common_lines", "rows_csv_text", "rows_dataset", "rows_markdown", "traffic_axles_per_day", "verdict"]

SPREAD = 0.08  # the speed spread's relative step d: 1/4, 1/2, 1/4 of the trains at V (1 - d), V, V (1 + d)
SPREAD_WEIGHTS = (0.25, 0.5, 0.25)
SHARES = (0.0, 0.25, 0.5, 0.75, 1.0)  # the driven-axle shares
BAND_WINDOW = (0.9, 1.3)  # the band's window [f_pp]
KINDS = {"dampers": "rail dampers", "soft_pad": "soft pad", "stiff_pad": "stiff pad", "trailer": "trailer"}  # summary role: row


def at_speed(ds: xr.Dataset, speed: float) -> xr.Dataset:
    """One speed of a case's spectrum (with the wheels' source), as a dataset over that speed alone.

    Parameters
    ----------
    ds : xr.Dataset
        A case's spectrum over (speed, wavelength) (results/spectrum/<case>/rate_spectrum.nc).
    speed : float
        One of its speeds [m/s].

    Returns
    -------
    xr.Dataset
        Over (speed, wavelength) with the one speed.
    """
    V = ds.speed.values
    i = np.flatnonzero(np.isclose(V, speed, rtol=1e-9))
    if i.size != 1:
        raise ValueError(f"speed = {speed!r} m/s is not one of the spectrum's speeds {V.tolist()}.")
    return ds.isel(speed=[int(i[0])])


def mixture(parts, weights) -> xr.Dataset:
    """A fleet's spectrum of one-wheel trains from its classes' spectra on the same lines (module docstring).

    Parameters
    ----------
    parts : sequence of xr.Dataset
        Each class's spectrum at one speed (at_speed), every one with the same wavelengths, one wheel per train.
    weights : sequence of float
        The classes' shares of the traffic [-], >= 0, summing to 1.

    Returns
    -------
    xr.Dataset
        The first part's dataset with growth_rate, drift, growth_dB_per_1e5_axles and source the weighted sums, and
        wheel_source_dB the weighted sum of the parts' Q (where they carry it); attribute ``mixture`` says of what.
    """
    w = np.asarray(weights, dtype=float)
    if len(parts) != w.size or w.size == 0 or np.any(~np.isfinite(w)) or np.any(w < 0) or abs(w.sum() - 1) > 1e-12:
        raise ValueError(f"weights = {list(weights)!r} is not allowed: one share >= 0 per part ({len(parts)}), summing to 1.")
    lam = parts[0].wavelength.values
    for p in parts:
        if not np.array_equal(p.wavelength.values, lam):
            raise ValueError("the parts of a mixture must lie on the same lines (the same period and band at the nominal speed).")
        if int(p.attrs.get("wheels", 1)) != 1:
            raise ValueError(f"a part has {p.attrs.get('wheels')} wheels per train: the mixture here is of one-wheel trains.")
    out = parts[0].copy()
    # one wheel's own rate's magnitude for the wheels' source, Q = sum_c w_c abs(R_c)^2 P (rail.studies.wheel_source)
    own = np.sqrt(sum(wc * (p.growth_rate.values ** 2 + p.drift.values ** 2) for wc, p in zip(w, parts)))
    out["own_rate_abs"] = (("speed", "wavelength"), own, {"units": "1", "long_name": "sqrt(sum_c w_c abs(R_c)^2): the wheels' "
                                                          "source transfer of the mixture per train passage"})
    for name in ("growth_rate", "drift", "growth_dB_per_1e5_axles", "growth_dB_per_1e5_trains", "source"):
        if name in out:
            out[name] = (out[name].dims, sum(wc * p[name].values for wc, p in zip(w, parts)), out[name].attrs)
    if all("wheel_source_dB" in p for p in parts):
        Q = sum(wc * 10 ** (p["wheel_source_dB"].values / 10) for wc, p in zip(w, parts))
        with np.errstate(divide="ignore"):
            out["wheel_source_dB"] = (out["wheel_source_dB"].dims, 10 * np.log10(Q), out["wheel_source_dB"].attrs)
    out.attrs["mixture"] = "; ".join(f"{wc:g} x {p.attrs.get('scenario', '?')} at {float(p.speed.values[0]):g} m/s"
                                     for wc, p in zip(w, parts))
    return out


def interval(ds: xr.Dataset, spectra: dict, axles_per_day: float | None = None) -> dict:
    """The time from the ground rail to the limit of one speed's spectrum (or mixture) under the wheels' source
    (rail.studies.wheel_source.source_dataset on its lines: the bands its lines sample).

    Parameters
    ----------
    ds : xr.Dataset
        One speed's spectrum (at_speed or mixture), one wheel per train.
    spectra : dict
        rail.setup.inputs.wheel_source_spectra's (wheel, ground, limit).
    axles_per_day : float, optional
        The traffic [1/day], for the years.

    Returns
    -------
    dict
        interval_axles (inf: not within the search), interval_years (with a traffic), interval_band_mm (the nominal band
        that reaches its limit first; NaN: none) and settled_peak_band_dB (the settled level of the band holding the
        growth band's peak; inf where a line in it grows).
    """
    from .wheel_source import source_dataset

    own = ds["own_rate_abs"].values if "own_rate_abs" in ds else np.hypot(ds.growth_rate.values, ds.drift.values)
    keep = ds[["growth_rate", "drift", "source", "growth_dB_per_1e5_axles"]]
    keep.attrs = dict(ds.attrs)
    out = source_dataset(keep, spectra["wheel"], own.astype(complex), spectra["ground"], spectra["limit"])
    axles = float(out.interval_axles.values[0])
    band = float(out.interval_band.values[0])
    lam = ds.wavelength.values
    g = ds.growth_dB_per_1e5_axles.values[0]
    j = int(np.argmax(g))
    b = int(np.argmin(np.abs(np.log(out.band.values / lam[j]))))
    return {"interval_axles": axles, "interval_years": axles / (365.0 * axles_per_day) if axles_per_day else float("nan"),
            "interval_band_mm": 1e3 * band if np.isfinite(band) else float("nan"),
            "settled_peak_band_dB": float(out.settled_band_level_dB.values[0, b])}


def on_common_lines(*parts):
    """The spectra on the lines they all hold (the union of a spread case's speeds holds the lines of its nominal speed
    alone: a one-speed case's lines are a subset).

    Parameters
    ----------
    *parts : xr.Dataset
        Spectra of one period (attrs bays and sleeper_spacing_m equal).

    Returns
    -------
    tuple of xr.Dataset
        Each on the common lines, in its own order of wavelength.
    """
    period = {(int(p.attrs["bays"]), float(p.attrs["sleeper_spacing_m"])) for p in parts}
    if len(period) != 1:
        raise ValueError(f"the spectra lie on different periods {sorted(period)}: no common lines.")
    common = set(parts[0].line.values.tolist())
    for p in parts[1:]:
        common &= set(p.line.values.tolist())
    if not common:
        raise ValueError("the spectra hold no line in common.")
    return tuple(p.isel(wavelength=np.flatnonzero(np.isin(p.line.values, sorted(common)))) for p in parts)


def band_row(label: str, ds: xr.Dataset, nominal: float) -> dict:
    """The band near pinned-pinned of one spectrum at a nominal speed (the frequencies V / wavelength at it).

    Parameters
    ----------
    label : str
        The row's name.
    ds : xr.Dataset
        One speed's spectrum (at_speed or mixture).
    nominal : float
        The nominal speed V [m/s] the frequencies are taken at.

    Returns
    -------
    dict
        peak_Hz, peak_f_pp (the peak over f_pp), peak_wavelength_mm, peak_dB_per_1e5_axles, half_width_Hz, lines_growing
        (growing lines around the peak) and f_pp_Hz.
    """
    lam = ds.wavelength.values
    g = ds.growth_dB_per_1e5_axles.values[0]
    fpp = float(ds.attrs["pinned_pinned_Hz"])
    f = nominal / lam
    b = band_edges(f, g, low=BAND_WINDOW[0] * fpp, high=BAND_WINDOW[1] * fpp)
    return {"case": label, "speed_m_s": nominal, "f_pp_Hz": round(fpp, 1), "peak_Hz": round(b.peak_frequency, 1),
            "peak_f_pp": round(b.peak_frequency / fpp, 3), "peak_wavelength_mm": round(1e3 * nominal / b.peak_frequency, 2),
            "peak_dB_per_1e5_axles": round(float(b.peak_rate), 3),
            "half_width_Hz": round(float(b.half_width), 1) if b.peak_rate > 0 else float("nan"),
            "lines_growing": int(b.lines_growing)}


def verdict(rate: float, reference: float, tolerance: float = 0.05) -> str:
    """Whether a mitigation's band peak reduces the reference's (dB per 100,000 axles).

    Parameters
    ----------
    rate, reference : float
        The band's peak growth with and without the mitigation [dB per 100,000 axles].
    tolerance : float
        A change smaller than this [dB per 100,000 axles] is "no change" (the grids' spread near the band is about
        1.4 % of a rate, docs/dynamic-creepage.md).

    Returns
    -------
    str
        "removes the band" (it no longer grows), "reduces", "no change" or "increases".
    """
    if reference > 0 and rate <= 0:
        return "removes the band"
    if rate < reference - tolerance:
        return "reduces"
    if rate > reference + tolerance:
        return "increases"
    return "no change"


def mitigation_rows(spread: dict, cases: dict, spectra: dict | None = None, axles_per_day: float | None = None) -> list[dict]:
    """The study's rows per nominal speed: the default track, each mitigation, the speed spread and the driven shares.

    Parameters
    ----------
    spread : dict
        {nominal speed: the default track's spectrum at V (1 - SPREAD), V, V (1 + SPREAD)} (xr.Dataset over three speeds).
    cases : dict
        {(nominal speed, kind): spectrum at that speed}, kind one of KINDS' values ("dampers", "soft pad", "stiff pad",
        "trailer").

    spectra : dict, optional
        rail.setup.inputs.wheel_source_spectra's (wheel, ground, limit): each row's interval (interval's keys).
    axles_per_day : float, optional
        The traffic [1/day], for the years.

    Returns
    -------
    list of dict
        band_row's keys, and change_dB_per_1e5_axles (against the default), verdict, and where the spectra carry the
        wheels' source interval_axles (from the ground rail to the limit; inf: never) and interval_band_m.
    """
    rows = []
    for V in sorted(spread):
        ds = spread[V]
        speeds = np.sort(ds.speed.values)
        want = np.array([V * (1 - SPREAD), V, V * (1 + SPREAD)])
        if speeds.size != 3 or not np.allclose(speeds, want, rtol=5e-3):
            raise ValueError(f"the speed spread at {V:g} m/s needs the speeds {np.round(want, 1).tolist()} m/s, has {speeds.tolist()}.")
        base = at_speed(ds, speeds[1])
        variants = [("default track, every train at V", base)]
        for kind in ("rail dampers", "soft pad", "stiff pad"):
            if (V, kind) in cases:
                variants.append((kind, cases[(V, kind)]))
        variants.append((f"speed spread +-{100 * SPREAD:g} %", mixture([at_speed(ds, v) for v in speeds], SPREAD_WEIGHTS)))
        if (V, "trailer") in cases:
            for s in SHARES:
                part = mixture(list(on_common_lines(base, cases[(V, "trailer")])), [s, 1 - s])
                variants.append((f"driven axles {100 * s:g} %", part))
        ref = None
        for label, part in variants:
            row = band_row(label, part, V)
            ref = row["peak_dB_per_1e5_axles"] if ref is None else ref
            row["change_dB_per_1e5_axles"] = round(row["peak_dB_per_1e5_axles"] - ref, 3)
            row["verdict"] = "reference" if label.startswith("default") else verdict(row["peak_dB_per_1e5_axles"], ref)
            if spectra is not None:
                row.update(interval(part, spectra, axles_per_day))
            rows.append(row)
    return rows


def rows_dataset(rows: list[dict]) -> xr.Dataset:
    """The rows as a dataset over (row), with units.

    Parameters
    ----------
    rows : list of dict
        mitigation_rows'.

    Returns
    -------
    xr.Dataset
    """
    units = {"speed_m_s": ("m/s", "nominal train speed"), "f_pp_Hz": ("Hz", "the track's pinned-pinned frequency"),
             "peak_Hz": ("Hz", "the band's fastest-growing line near pinned-pinned, at the nominal speed"),
             "peak_f_pp": ("1", "the peak over the pinned-pinned frequency"),
             "peak_wavelength_mm": ("mm", "the peak's wavelength"),
             "peak_dB_per_1e5_axles": ("dB per 100000 axle passages", "the peak's growth rate (> 0 grows)"),
             "half_width_Hz": ("Hz", "the band's width at half its peak rate (NaN where nothing grows)"),
             "lines_growing": ("1", "growing lines around the peak"),
             "change_dB_per_1e5_axles": ("dB per 100000 axle passages", "the peak's change against the default track at the same speed"),
             "interval_axles": ("1", "axle passages from the ground rail to the first band over its limit under the wheels' source "
                                "(the bands the lines sample; inf: not within 1e12)"),
             "interval_years": ("year", "the interval in years at the traffic"),
             "interval_band_mm": ("mm", "the nominal band that reaches its limit first (NaN: none)"),
             "settled_peak_band_dB": ("dB re 1 um", "the settled level of the one-third-octave band holding the growth band's peak "
                                      "(inf: a line in it grows, no settled level)")}
    n = np.arange(len(rows))
    data = {k: data_var("row", np.array([r[k] for r in rows], dtype=float), *units[k]) for k in units if k in rows[0]}
    data["case"] = data_var("row", np.array([r["case"] for r in rows]), "1", "the mitigation")
    data["verdict"] = data_var("row", np.array([r["verdict"] for r in rows]), "1", "against the default track at the speed")
    return xr.Dataset(data, coords={"row": data_var("row", n, "1", "row of the study's table (mitigation.csv)")})


COLUMNS = [("case", "case", ""), ("speed_m_s", "speed_m_s", "{:g}"), ("f_pp_Hz", "f_pp_Hz", "{:.1f}"), ("peak_Hz", "peak_Hz", "{:.1f}"),
           ("peak_f_pp", "peak_over_f_pp", "{:.3f}"), ("peak_wavelength_mm", "peak_wavelength_mm", "{:.2f}"),
           ("peak_dB_per_1e5_axles", "peak_dB_per_1e5_axles", "{:+.3f}"), ("change_dB_per_1e5_axles", "change_dB_per_1e5_axles", "{:+.3f}"),
           ("half_width_Hz", "half_width_Hz", "{:.1f}"), ("lines_growing", "lines_growing", "{:d}"),
           ("interval_axles", "interval_axles", "{:.3g}"), ("interval_years", "interval_years", "{:.3g}"),
           ("interval_band_mm", "interval_band_mm", "{:g}"), ("settled_peak_band_dB", "settled_peak_band_dB_re_1um", "{:.1f}"),
           ("verdict", "verdict", "")]


def _cell(v, fmt):
    if not fmt:
        return str(v)
    if isinstance(v, float) and not np.isfinite(v):
        return "inf" if v > 0 else "nan" if np.isnan(v) else "-inf"
    return fmt.format(int(v) if fmt == "{:d}" else v)


def rows_csv_text(rows: list[dict], header: str) -> str:
    """The rows as CSV, units in every column name, the model in '#' lines first.

    Parameters
    ----------
    rows : list of dict
        mitigation_rows'.
    header : str
        The '#' lines' text (one line per line of it).

    Returns
    -------
    str
    """
    cols = [c for c in COLUMNS if c[0] in rows[0]]
    lines = [f"# {h}" for h in header.splitlines()] + [",".join(c[1] for c in cols)]
    for r in rows:
        lines.append(",".join(f'"{r[k]}"' if not fmt else _cell(r[k], fmt) for k, _, fmt in cols))
    return "\n".join(lines) + "\n"


def rows_markdown(rows: list[dict], header: str) -> str:
    """The rows as a markdown table per speed, after the header's text.

    Parameters
    ----------
    rows : list of dict
        mitigation_rows'.
    header : str
        Text before the tables.

    Returns
    -------
    str
    """
    cols = [c for c in COLUMNS if c[0] in rows[0] and c[0] not in ("speed_m_s", "f_pp_Hz")]
    out = [header, ""]
    for V in sorted({r["speed_m_s"] for r in rows}):
        fpp = next(r["f_pp_Hz"] for r in rows if r["speed_m_s"] == V)
        out += [f"## {V:g} m/s (f_pp {fpp:.0f} Hz)", "", "| " + " | ".join(c[1] for c in cols) + " |",
                "|" + "---|" * len(cols)]
        out += ["| " + " | ".join(_cell(r[k], fmt) for k, _, fmt in cols) + " |" for r in rows if r["speed_m_s"] == V]
        out.append("")
    return "\n".join(out)


def traffic_axles_per_day(cfg: dict) -> float | None:
    """The configuration's traffic, traffic.axles_per_day [1/day] (None without one).

    Parameters
    ----------
    cfg : dict
        A resolved configuration.

    Returns
    -------
    float or None
    """
    v = (cfg.get("traffic") or {}).get("axles_per_day")
    return None if v is None else float(v)


def header_text(cfg: dict) -> str:
    """The study's header: what it computes and the model it runs, as values (the keys' names and their settings).

    Parameters
    ----------
    cfg : dict
        The spread case's resolved configuration (the study's defaults).

    Returns
    -------
    str
        Two lines.
    """
    ws, wsrc = cfg.get("wheelset") or {}, cfg.get("wheel_source") or {}
    drive = "motored" if float(ws.get("motor_inertia", 0.0) or 0.0) > 0 else "trailer"
    apd = traffic_axles_per_day(cfg)
    model = (f"rail_flexibility = {(cfg.get('rail_flexibility') or {}).get('model', 'none')}, wheelset = {ws.get('model', 'none')} "
             f"({drive}), normal_contact = {cfg['contact']['normal']}, wear_path = {cfg['contact']['wear_path']}, "
             f"creepage = {float(cfg['contact']['creepage']):g}; wheel_source = {wsrc.get('roughness', 'none')}, "
             f"ground = {wsrc.get('ground', 'E')}, limit = {cfg['figures']['bands'].get('limit')}; "
             f"traffic = {'none' if apd is None else f'{apd:g} axles per day'}")
    return ("Mitigation study (issue 55, config/studies/track_mitigation.yaml): the band near pinned-pinned, growth rates in dB per "
            "100,000 axle passages, intervals from the ground rail to the limit\n" + model)
