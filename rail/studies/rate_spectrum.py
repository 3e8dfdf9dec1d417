"""The growth-rate spectrum over speed and wavelength (named target rate_spectrum): its dataset."""

from __future__ import annotations

import numpy as np
import xarray as xr

from ..contact import ReportNormal, hertz_half_length, normal_contact
from ..contact import wear_path as contact_wear_path
from ..growth_spectrum import RateSpectrum, rate_spectrum, settings_lines
from ..growth_spectrum.band import class_pair_spectrum
from ..growth_spectrum.creepage import has_creepage
from ..setup.io import data_var
from .datasets import sweep_coords
from .validity import creepage_model_text, validity_text

__all__ = ["spectrum_with_settings", "rate_spectrum_dataset", "spectrum_dataset_of", "model_mechanisms",
           "REPORT_VALID_PATCH_LENGTHS", "sweep_rate_spectrum", "growing_bands", "summary_markdown", "PASSAGES_PER_DB"]

PASSAGES_PER_DB = 100000  # the dB growth is stated per this many train passages
# The report's normal contact (point spring, Hertz patch with the local curvature) is taken as valid
# for wavelengths above this many patch lengths 2 a_0 (rail.contact.models.ReportNormal)
REPORT_VALID_PATCH_LENGTHS = ReportNormal.valid_patch_lengths


def spectrum_with_settings(scn, tables, settings: dict, progress=None) -> RateSpectrum:
    """The growth-rate spectrum of a spectrum scenario (rail.setup.build.spectrum_scenario) at the
    tables' speed, on the lines and with the probe and grids of ``settings`` (the keys of
    figures.rate_spectrum: shortest, longest, per_octave, eps, grid_phases; and a band {low, high,
    spacing} in Hz resolved at the settings' speeds, rail.growth_spectrum.settings_lines); ``progress`` as for
    rail.growth_spectrum.rate_spectrum.

    Parameters
    ----------
    scn : Scenario
        A spectrum scenario (rail.setup.build.spectrum_scenario).
    tables : MovingReceptance or tuple of MovingReceptance
        The receptance (Bloch) tables at the speed.
    settings : dict
        figures.rate_spectrum: shortest, longest [m], per_octave [-], eps [-], grid_phases [-], band [Hz].
    progress : file, optional
        Where progress lines go.

    Returns
    -------
    RateSpectrum
        Per line: wavelength [m] and complex rate per train passage [-].
    """
    s = settings
    lines = settings_lines(scn.L, scn.roughness.bays, scn.harmonics, s)
    if scn.cell is None and scn.roughness.bays > 2 and has_creepage(scn.material):
        # the linear method with dynamic creepage marches u_bar's basis of every class present at once: over 10 GB on
        # 8 bays at 40 m/s with the band's lines; one pair of classes at a time keeps it to a pair's (the same rates)
        return class_pair_spectrum(scn, tables, lines, eps=float(s["eps"]), grid_phases=int(s["grid_phases"]), check_lines=4,
                                   progress=progress)
    return rate_spectrum(scn, tables, lines, eps=float(s["eps"]), grid_phases=int(s["grid_phases"]), progress=progress)


def rate_spectrum_dataset(spectra: dict[float, RateSpectrum], L: float, wheels: int, contact_length: float | None = None,
                          normal=None, traffic=None, wear_path=None) -> xr.Dataset:
    """One dataset of the growth-rate spectra of one scenario at several speeds.

    Parameters
    ----------
    spectra : {speed [m/s]: RateSpectrum}
        On the same lines (rail.growth_spectrum.spectrum_lines).
    L : float
        Sleeper spacing [m].
    wheels : int
        Wheels of the train [-] (the rates are per train passage).
    contact_length : float, optional
        2 a_0, the Hertz patch length under the static load [m] (marked on the figures).
    normal : str or rail.contact.NormalContact, optional
        The normal-contact model or its name (one with a validity limit in patch lengths, the
        report's: valid above about ten patch lengths, stated in the attributes and shaded in the
        figure below that).
    wear_path : str or rail.contact.WearPath, optional
        Where the wear is deposited: 'wheel' or 'patch' (contact.wear_path), stated in the attributes as a
        value beside its description.
    traffic : rail.traffic.Traffic, optional
        For the growth per year and per MGT (growth_dB_per_year, growth_dB_per_MGT).

    Returns
    -------
    xr.Dataset
        growth_rate, drift, growth_dB_per_1e5_trains (per 100,000 passages of the whole train),
        growth_dB_per_1e5_axles (the export and figure convention, docs/exports.md), source, crossover_amplitude over (speed, wavelength).
    """
    from .exports import spectrum_rates

    V = sorted(spectra)
    first = spectra[V[0]]
    if any(not np.array_equal(spectra[v].line, first.line) for v in V):
        raise ValueError("the spectra must share their lines (one spectrum_lines call).")
    R = np.array([spectra[v].rate for v in V])
    g = -R.real
    src = np.array([spectra[v].source for v in V])
    with np.errstate(divide="ignore", invalid="ignore"):
        cross = np.where(src > 0, src / np.abs(R), np.nan)
    lam = first.wavelength
    rates = spectrum_rates(g, wheels, traffic)
    units = {"growth_dB_per_1e5_axles": ("dB per 100000 axle passages", "level change per 100,000 axle (wheel) passages of a small "
                                         "roughness at the wavelength (growth_dB_per_1e5_trains / wheels of the train)", {}),
             "growth_dB_per_year": ("1/year", "level change per year of the traffic (growth_dB_per_1e5_axles x axles_per_day x 365 / 1e5)",
                                    {"level_unit": "dB", "units_text": "dB/year"}),
             "growth_dB_per_MGT": ("1/Mt", "level change per million gross tonnes (growth_dB_per_1e5_axles x 1e6 / axle_load_t / 1e5)",
                                   {"level_unit": "dB", "units_text": "dB/Mt"})}
    return xr.Dataset(
        {
            **{k: data_var(("speed", "wavelength"), v, units[k][0], units[k][1], **units[k][2]) for k, v in rates.items()},
            "growth_rate": data_var(("speed", "wavelength"), g, "1",
                                "relative growth rate of the roughness amplitude per train passage, -Re R (> 0: grows)"),
            "growth_rate_other": data_var(("speed", "wavelength"), np.array([-spectra[v].rate_other.real for v in V]), "1",
                                      "growth rate of the other phase at a locked line (cosine and sine about the supports); "
                                      "at a free line the same as growth_rate"),
            "drift": data_var(("speed", "wavelength"), -R.imag, "rad",
                          "phase drift of the roughness per train passage, -Im R (the profile moves along the rail)"),
            "growth_dB_per_1e5_trains": data_var(("speed", "wavelength"), 20 * np.log10(np.e) * g * PASSAGES_PER_DB,
                                             f"dB per {PASSAGES_PER_DB} train passages",
                                             f"level change per {PASSAGES_PER_DB} passages of the whole train (all its wheels "
                                             "once) of a small roughness at the wavelength",
                                             reference_level="dB re the initial level"),
            "source": data_var(("speed", "wavelength"), src, "m",
                           "wear of the smooth rail at the line per train passage (amplitude 2|W0|; only on the one-bay comb L/k)"),
            "crossover_amplitude": data_var(("speed", "wavelength"), cross, "m",
                                        "roughness amplitude at which the feedback |R| Z equals the parametric source (comb lines; "
                                        "below it the supports' source dominates)"),
            "grid_spread": data_var(("speed", "wavelength"), np.array([spectra[v].grid_spread for v in V]), "1",
                                "half the spread of growth_rate over the contact grids averaged (the grid-tied error of one grid)"),
            "sideband_ratio": data_var(("speed", "wavelength"), np.array([spectra[v].sideband for v in V]), "1",
                                   "largest wear at the sidebands j +- N over the wear at j (coupling within the Bloch class; "
                                   "0 at locked lines)"),
            "fastest_wavelength": data_var("speed", lam[np.argmax(g, axis=1)], "m", "wavelength of the fastest growth"),
            "fastest_growth_dB_per_1e5_trains": data_var("speed", 20 * np.log10(np.e) * g.max(axis=1) * PASSAGES_PER_DB,
                                                     f"dB per {PASSAGES_PER_DB} train passages",
                                                     f"fastest growth per {PASSAGES_PER_DB} passages of the whole train"),
            "linearity": data_var("speed", np.array([spectra[v].linearity for v in V]), "1",
                              "largest |R(2 eps) / R(eps) - 1| over the lines checked"),
        },
        coords={
            "speed": data_var("speed", np.array(V, dtype=float), "m/s", "train speed"),
            "wavelength": data_var("wavelength", lam, "m", "roughness wavelength N L / j"),
            "line": data_var("wavelength", first.line, "1", f"line j of the {first.bays}-bay period"),
            "locked": data_var("wavelength", first.locked, "1",
                           "0 free line; 1 on the one-bay comb L/k; 2 on the half-comb 2L/(2k+1) (phase locked to the supports)"),
            "frequency": data_var(("speed", "wavelength"), np.array(V)[:, None] / lam[None, :], "Hz", "excitation frequency V / wavelength"),
        },
        attrs={"eps_m": first.eps, "bays": first.bays, "grid_phases": first.grid_phases,
               "method": "; ".join(f"{v:g} m/s: {spectra[v].method}" for v in V), "wheels": int(wheels), "sleeper_spacing_m": float(L),
               "passages": "growth_dB_per_1e5_trains, growth_rate, drift: per train passage (a train of n wheels counts once); "
                           "growth_dB_per_1e5_axles: per 100,000 axle (wheel) passages",
               **(traffic.attributes() if traffic is not None else {}),
               **({"contact_length_m": float(contact_length)} if contact_length else {}),
               **({"normal_contact": normal_contact(normal).name, "normal_contact_description": normal_contact(normal).description}
                  if normal is not None else {}),
               **(contact_wear_path(wear_path).attributes() if wear_path else {}),
               **({"report_model_valid_above_m": REPORT_VALID_PATCH_LENGTHS * float(contact_length),
                   "validity": f"the report's normal contact (point spring, local-curvature Hertz patch) holds for wavelengths above "
                               f"about {REPORT_VALID_PATCH_LENGTHS} patch lengths ({1e3 * REPORT_VALID_PATCH_LENGTHS * contact_length:.0f} mm); "
                               "below, use contact.normal: nonhertzian (docs/contact.md)"}
                  if normal is not None and normal_contact(normal).valid_patch_lengths and contact_length else {})},
    )


def spectrum_dataset_of(spectra: dict[float, RateSpectrum], scn) -> xr.Dataset:
    """rate_spectrum_dataset for a scenario: its sleeper spacing, wheels, static patch length and
    normal-contact model.

    Parameters
    ----------
    spectra : {speed [m/s]: RateSpectrum}
    scn : rail.scenario.Scenario

    Returns
    -------
    xr.Dataset
    """
    from ..traffic import traffic_of

    a0 = float(hertz_half_length(scn.wheels.static_load, scn.material.wheel_radius, scn.material))
    traffic = traffic_of(scn) if scn.axles_per_day else None
    ds = rate_spectrum_dataset(spectra, scn.L, len(scn.wheels.positions), 2 * a0, scn.contact_numerics.normal, traffic,
                               wear_path=scn.contact_numerics.path)
    creep = creepage_model_text(scn.material)
    if creep:
        ds.attrs["creepage_model"] = creep
    if getattr(scn, "track", None) is not None:  # marked on the frequency x speed map (rail.plotting.rate_map)
        from ..track import pinned_pinned_frequency

        ds.attrs["pinned_pinned_Hz"] = float(pinned_pinned_frequency(scn.track))
    ds.attrs.update(model_mechanisms(scn))
    return ds


def model_mechanisms(scn) -> dict:
    """The track and the model's choices of a spectrum, as values for its attributes and its figure
    (issue 57, item 8: a figure names the track and the mechanisms; issue 54: each choice a value beside
    its description): the pad stiffness [N/m] and rail.scenario.ModelChoices.attributes (normal_contact,
    wear_path, wheelset_model, rail_flexibility, friction_law, each with ``_description``).

    Parameters
    ----------
    scn : rail.scenario.Scenario

    Returns
    -------
    dict
        pad_stiffness_N_per_m [N/m] and the model choices' values and descriptions [-].
    """
    return {"pad_stiffness_N_per_m": float(scn.track.pad.stiffness), **scn.models.attributes()}


def growing_bands(wavelength, growth_rate):
    """The wavelength intervals where the growth rate is positive.

    Parameters
    ----------
    wavelength : ndarray
        Wavelengths of the lines [m], decreasing.
    growth_rate : ndarray
        Growth rate per passage at the lines [-].

    Returns
    -------
    list of (float, float)
        (longest, shortest) wavelength [m] of each run of consecutive lines with a positive rate.
    """
    out, start = [], None
    pos = np.asarray(growth_rate) > 0
    for i, p in enumerate(pos):
        if p and start is None:
            start = i
        if start is not None and (not p or i == len(pos) - 1):
            end = i if p else i - 1
            out.append((float(wavelength[start]), float(wavelength[end])))
            start = None
    return out


def summary_markdown(ds: xr.Dataset) -> str:
    """Where the rate is positive, per speed, and the fastest-growing wavelength (a Markdown table),
    then the result's validity (rail.studies.validity) in one line.

    Parameters
    ----------
    ds : xr.Dataset
        A spectrum dataset over speed (rate_spectrum_map).

    Returns
    -------
    str
        Markdown text.
    """
    rows = ["| speed (m/s) | wavelengths that grow (mm) | fastest (mm) | its growth (dB per 100,000 train passages) "
            "| its growth (dB per 100,000 axle passages) |",
            "|---|---|---|---|---|"]
    lam = ds["wavelength"].values
    for i, v in enumerate(ds["speed"].values):
        bands = growing_bands(lam, ds["growth_rate"].values[i])
        text = ", ".join(f"{1e3 * a:.3g}-{1e3 * b:.3g}" for a, b in bands) or "none"
        rows.append(f"| {v:g} | {text} | {1e3 * float(ds['fastest_wavelength'].values[i]):.3g} | "
                    f"{float(ds['fastest_growth_dB_per_1e5_trains'].values[i]):+.2f} | "
                    f"{float(ds['growth_dB_per_1e5_axles'].values[i][np.argmax(ds['growth_rate'].values[i])]):+.2f} |")
    validity = validity_text(ds.attrs)
    return "\n".join(rows) + "\n" + (f"\nValidity: {validity}\n" if validity else "")


def sweep_rate_spectrum(points: list, keys, values, indices, units) -> xr.Dataset:
    """The growth-rate spectra of a sweep study's points on its grid (one dimension per swept key).

    Parameters
    ----------
    points : list of xr.Dataset
        Each point's spectrum (rate_spectrum_dataset at the point's speed), on the same lines.
    keys : sequence of str
        Swept keys (dotted config keys or 'speed').
    values : sequence of sequence
        Values of each key.
    indices : sequence of sequence of int
        Grid index of each point.
    units : sequence of str
        The unit of each key, as the schema states it (rail.setup.config.schema_unit).

    Returns
    -------
    xr.Dataset
        growth_dB_per_1e5_trains, growth_dB_per_1e5_axles, growth_rate and drift over (swept keys...,
        wavelength); the fastest-growing wavelength and its growth per 100,000 train passages per grid point.
    """
    dims, coords = sweep_coords(keys, values, units)
    shape = tuple(len(v) for v in values)
    first = points[0]
    lam = first["wavelength"].values
    out = {name: np.full(shape + (lam.size,), np.nan) for name in ("growth_dB_per_1e5_trains", "growth_dB_per_1e5_axles", "growth_rate", "drift")}
    for ds, idx in zip(points, indices):
        if not np.array_equal(ds["wavelength"].values, lam):
            raise ValueError("the sweep's spectra must share their lines (the same figures.rate_spectrum).")
        for name in out:
            out[name][tuple(idx)] = ds[name].values[0]
    g = out["growth_dB_per_1e5_trains"]
    coords["wavelength"] = first["wavelength"]
    coords["locked"] = first["locked"]
    return xr.Dataset(
        {
            "growth_dB_per_1e5_trains": data_var(dims + ("wavelength",), g, f"dB per {PASSAGES_PER_DB} train passages",
                                             first["growth_dB_per_1e5_trains"].attrs["long_name"]),
            "growth_dB_per_1e5_axles": data_var(dims + ("wavelength",), out["growth_dB_per_1e5_axles"], "dB per 100000 axle passages",
                                            first["growth_dB_per_1e5_axles"].attrs["long_name"]),
            "growth_rate": data_var(dims + ("wavelength",), out["growth_rate"], "1", first["growth_rate"].attrs["long_name"]),
            "drift": data_var(dims + ("wavelength",), out["drift"], "rad", first["drift"].attrs["long_name"]),
            "fastest_wavelength": data_var(dims, lam[np.nanargmax(g, axis=-1)], "m", "wavelength of the fastest growth"),
            "fastest_growth_dB_per_1e5_trains": data_var(dims, np.nanmax(g, axis=-1), f"dB per {PASSAGES_PER_DB} train passages",
                                                     f"fastest growth per {PASSAGES_PER_DB} passages of the whole train"),
        },
        coords=coords,
        attrs={"swept_keys": list(keys)},
    )
