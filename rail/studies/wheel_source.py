"""The expected rail roughness under the wheels' roughness (issue 58): the growth-rate spectrum's lines with
the wheels' source Q, the level each line and band settles to, and the time from a ground rail to the
limit (rail.growth_spectrum.source; docs/wheel-source.md).

Inputs are the spectrum's dataset (rail.studies.rate_spectrum.rate_spectrum_dataset: growth_rate and drift
give the train's rate R = -(growth_rate + i drift) per train passage, ``source`` the supports' comb),
one wheel's own rate on the same lines (the wheel alone on the track, rail.chain.single_wheel; for a
one-wheel train the spectrum's own), the wheel's one-third-octave roughness, the ground rail's and the
limit. Everything is per train passage inside and per axle (wheel) passage, MGT and year outside, as
the spectrum's exports are.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from ..bands import wavelength_bands
from ..growth_spectrum import source as src
from ..noise.named import RoughnessSpectrum, named_spectrum
from ..setup.io import data_var

__all__ = ["RoughnessSpectrum", "named_spectrum", "source_dataset", "with_wheel_source", "SETTLE_WITHIN_DB"]

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

    bands = wavelength_bands(1.0, 0.00315)
    share, band = src.line_share(lam, period, bands.centre)
    nb = bands.centre.size
    sampled = np.array([np.any(band == b) for b in range(nb)])
    incoherent_inf = np.where(np.isfinite(S_inf), src.settled_mean_square(R, Q), np.inf)
    with np.errstate(invalid="ignore"):
        coherent_inf = S_inf - incoherent_inf
    settled_band = src.band_mean_square_from_lines(incoherent_inf, share, band, nb, coherent=np.nan_to_num(coherent_inf, nan=np.inf))
    wheels_band = src.band_mean_square_from_lines(incoherent_inf, share, band, nb)  # the wheels' part alone (the comb left out)
    wheel_band = 1e-12 * 10 ** (wheel.at(bands.centre) / 10)

    def level(ms):
        with np.errstate(divide="ignore", invalid="ignore"):
            return 10 * np.log10(np.asarray(ms, dtype=float) / 1e-12)

    per_axle = "per axle (wheel) passage"
    out = ds.assign(
        wheel_line_level_dB=data_var("wavelength", level(P), "dB re 1 um",
                                     f"the wheels' roughness on the line (its band's mean square spread evenly over the band's "
                                     f"wavenumbers): {wheel.label}"),
        wheel_source_dB=data_var(("speed", "wavelength"), level(Q), "dB re 1 um^2 per train passage",
                                 "Q: the expected mean square the wheels' roughness adds to the rail's line per train passage "
                                 "(sum over the wheels of abs(R_own)^2 P)"),
        settled_level_dB=data_var(("speed", "wavelength"), level(S_inf), "dB re 1 um",
                                  "the level the line settles to under the wheels' source and the supports' comb, Q / (1 - abs(1 - R)^2) "
                                  "+ abs(s / R)^2 / 2; inf where the line grows (no settled level)"),
        settle_axles=data_var(("speed", "wavelength"), settle, "1",
                              f"axle passages from a ground (zero) line to within {SETTLE_WITHIN_DB:g} dB of its settled level; inf where it grows"),
    )
    out = out.assign_coords(band=data_var("band", bands.centre, "m", "one-third-octave band centre wavelength (exact, 10^(-n/10) m)"),
                            band_nominal=data_var("band", bands.nominal, "m", "EN 15610 nominal band label"))
    out["wheel_band_level_dB"] = data_var("band", level(wheel_band), "dB re 1 um", f"the wheels' roughness per band: {wheel.label}")
    out["settled_band_level_dB"] = data_var(("speed", "band"), np.where(sampled, level(settled_band), np.nan), "dB re 1 um",
                                            "the band's settled level (the mean of its lines' settled densities times its width, and the comb); "
                                            "inf where a line in it grows; NaN where no line of the spectrum samples the band")
    out["settled_band_wheels_dB"] = data_var(("speed", "band"), np.where(sampled, level(wheels_band), np.nan), "dB re 1 um",
                                             "the band's settled level from the wheels' roughness alone (the supports' comb left out): "
                                             "what the wheels' source holds the rail at")
    attrs = {"wheel_roughness": wheel.label, "wheel_source_wheels": wheels,
             "wheel_source_transfer": "the spectrum's own rate (one wheel)" if rate_own is None else
             "each wheel alone on the track (rail.chain.single_wheel): the wheels' cross terms through the rail left out",
             "wheel_source_model": "S_{n+1} = abs(1 - R)^2 S_n + Q per train passage, Q = wheels abs(R_own)^2 P; the supports' "
                                   "comb coherent (rail.growth_spectrum.source)",
             "wheel_source_passages": "wheel_source_dB per train passage; settle_axles and axles_to_limit " + per_axle}
    if ground is not None and limit is not None:
        S0 = _line_power(ground, lam, period)
        from .bands import limit_tolerance

        lim_dB = limit.at(bands.centre)
        lim = 1e-12 * 10 ** ((lim_dB + np.nan_to_num(limit_tolerance(lim_dB), nan=0.0)) / 10)  # exceeded above its stated precision
        axles = np.full((R.shape[0], nb), np.inf)
        for i in range(R.shape[0]):
            def band_ms(n, i=i):
                n = np.asarray(n, dtype=float)[:, None]
                inc = src.expected_mean_square(n, S0[None, :], R[i][None, :], Q[i][None, :])
                coh = src.expected_mean_square(n, 0.0, R[i][None, :], 0.0, comb[i][None, :])
                return src.band_mean_square_from_lines(inc, share, band, nb, coherent=coh)
            axles[i] = src.passages_to_limit(band_ms, np.where(sampled, lim, np.nan), longest=LONGEST_SEARCH_AXLES / wheels) * wheels
        above = np.isfinite(lim) & sampled & (S0_band(S0, share, band, nb) > lim)  # a band that starts above its limit
        counted = np.where(above[None, :], np.inf, axles)  # the interval: the bands that start below their limit
        first = np.min(counted, axis=1)
        driver = np.where(np.isfinite(first), bands.nominal[np.argmin(counted, axis=1)], np.nan)
        out["starts_above_limit"] = data_var("band", above.astype(int), "1",
                                             "1: the ground rail starts above the limit in the band (axles_to_limit 0; left out of the interval)")
        out["start_band_level_dB"] = data_var("band", level(1e-12 * 10 ** (ground.at(bands.centre) / 10)), "dB re 1 um",
                                              f"the ground rail's roughness per band (the start): {ground.label}")
        out["limit_dB"] = data_var("band", limit.at(bands.centre), "dB re 1 um", f"the limit spectrum: {limit.label}")
        out["axles_to_limit"] = data_var(("speed", "band"), axles, "1",
                                         "axle passages from the ground rail until the band's expected level exceeds its limit "
                                         "(the expected spectrum with the wheels' source, never a decay extrapolated); inf: not "
                                         f"within {LONGEST_SEARCH_AXLES:.0e} axle passages")
        out["interval_axles"] = data_var("speed", first, "1", "axle passages from the ground rail to the first band over its limit "
                                         "(of the bands that start below it)")
        out["interval_band"] = data_var("speed", driver, "m", "the nominal band that reaches its limit first (NaN: none)")
        if traffic is not None:
            out["years_to_limit"] = data_var(("speed", "band"), axles / traffic.axles_per_year, "year",
                                             "years from the ground rail until the band's expected level exceeds its limit at the traffic")
            out["interval_years"] = data_var("speed", first / traffic.axles_per_year, "year",
                                             "years from the ground rail to the first band over its limit at the traffic")
        attrs["ground_rail"] = ground.label
        attrs["limit"] = limit.label
    out.attrs.update(attrs)
    return out


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


def settled_csv_text(ds: xr.Dataset) -> str:
    """The settled spectrum per speed and band as CSV, units in every column, the model in the header.

    Parameters
    ----------
    ds : xr.Dataset
        source_dataset's.

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
    has = "axles_to_limit" in ds
    if has:
        head.append(f"# from the ground rail {a['ground_rail']} to the limit {a['limit']} (the expected spectrum, never a decay extrapolated)")
    cols = ["speed_m_s", "band_nominal_m", "wheel_dB_re_1um", "settled_dB_re_1um", "settled_wheels_only_dB_re_1um"]
    if has:
        cols += ["ground_dB_re_1um", "limit_dB_re_1um", "axles_to_limit"] + (["years_to_limit"] if "years_to_limit" in ds else [])
    rows = [",".join(cols)]

    def cell(v, fmt="{:.2f}"):
        v = float(v)
        return "" if np.isnan(v) else ("inf" if np.isinf(v) and v > 0 else fmt.format(v))

    for i, V in enumerate(ds.speed.values):
        for b in range(ds.sizes["band"]):
            r = [f"{V:g}", f"{ds.band_nominal.values[b]:g}", cell(ds.wheel_band_level_dB.values[b]), cell(ds.settled_band_level_dB.values[i, b]),
                 cell(ds.settled_band_wheels_dB.values[i, b])]
            if has:
                n = ds.axles_to_limit.values[i, b]
                r += [cell(ds.start_band_level_dB.values[b]), cell(ds.limit_dB.values[b]), cell(n, "{:.4g}")]
                if "years_to_limit" in ds:
                    r.append(cell(ds.years_to_limit.values[i, b], "{:.4g}"))
            rows.append(",".join(r))
    return "\n".join(head + rows) + "\n"


def settled_summary_markdown(ds: xr.Dataset) -> str:
    """The settled spectrum in words: per speed, the highest settled band against the wheels' roughness there,
    the bands where a line grows, and the time from the ground rail to the limit with the band that sets it.

    Parameters
    ----------
    ds : xr.Dataset
        source_dataset's.

    Returns
    -------
    str
        Markdown.
    """
    a = ds.attrs
    out = [f"# The wheels' roughness as a source: {a['wheel_roughness']}", "",
           f"Model: {a['wheel_source_model']}; {a['wheel_source_transfer']}.", ""]
    for i, V in enumerate(ds.speed.values):
        lev = ds.settled_band_level_dB.values[i]
        nom = ds.band_nominal.values
        fin = np.isfinite(lev)
        grows = [f"{1e3 * x:g} mm" for x in nom[np.isinf(lev) & (lev > 0)]]
        line = f"- {V:g} m/s: "
        if fin.any():
            b = int(np.nanargmax(np.where(fin, lev, -np.inf)))
            gap = lev[b] - ds.wheel_band_level_dB.values[b]
            line += (f"highest settled band {1e3 * nom[b]:g} mm at {lev[b]:.1f} dB re 1 µm, {gap:+.1f} dB against the wheels' "
                     "roughness in that band")
        else:
            line += "no band settles"
        wl = ds.settled_band_wheels_dB.values[i] - ds.wheel_band_level_dB.values
        if np.isfinite(wl).any():
            b = int(np.nanargmax(np.where(np.isfinite(wl), wl, -np.inf)))
            line += (f"; the wheels' part alone (the supports' comb left out) is at most {wl[b]:+.1f} dB against the wheels' roughness "
                     f"(the {1e3 * nom[b]:g} mm band, {ds.settled_band_wheels_dB.values[i, b]:.1f} dB re 1 µm)")
        if grows:
            line += f"; a line grows (no settled level) in {', '.join(grows)}"
        if "interval_axles" in ds:
            n = float(ds.interval_axles.values[i])
            if np.isfinite(n):
                yrs = f", {float(ds.interval_years.values[i]):.3g} years" if "interval_years" in ds else ""
                line += (f"; from the ground rail the {1e3 * float(ds.interval_band.values[i]):g} mm band passes the limit first, "
                         f"after {n:.3g} axle passages{yrs}")
            else:
                line += "; from the ground rail no band that starts below its limit reaches it"
            if "starts_above_limit" in ds and ds.starts_above_limit.values.any():
                line += ("; the ground rail starts above the limit in "
                         + ", ".join(f"{1e3 * x:g} mm" for x in nom[ds.starts_above_limit.values == 1]) + " (left out)")
        out.append(line)
    return "\n".join(out) + "\n"
