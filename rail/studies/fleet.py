"""Datasets of growth under a fleet (rail.fleet, docs/traffic.md): the fleet's growth-rate spectrum with
each class's contribution, and a fleet growth run, both with the traffic in axles per day and million
gross tonnes per year and the rates per year as well as per passage."""

from __future__ import annotations

import dataclasses

import numpy as np
import xarray as xr

from .. import chain, interaction
from .validity import creepage_model_text
from ..fleet import Fleet
from ..bands import in_band, wavelength_bands
from ..growth_spectrum import FleetRateSpectrum, RateSpectrum
from ..traffic import Traffic
from . import datasets
from ..setup.io import data_var
from ..creepage.wheelset import hz_text
from .rate_spectrum import PASSAGES_PER_DB

__all__ = ["fleet_spectrum_dataset", "fleet_growth_dataset", "tables_by_speed", "spectrum_arrays", "spectrum_from_arrays",
           "DB_PER_NEPER", "wheelset_lines"]

DB_PER_NEPER = 20 * np.log10(np.e)  # dB of amplitude per unit of ln(amplitude)


def tables_by_speed(tables, speeds) -> dict:
    """{speed: table} of a fleet's tables read from files, each checked to be at its class speed exactly
    (a table at a rounded speed would silently serve a class at another).

    Parameters
    ----------
    tables : sequence of MovingReceptance or of tuples of them (Bloch tables)
    speeds : sequence of float
        The class speeds [m/s], one per table.

    Returns
    -------
    dict
    """
    tables, speeds = list(tables), [float(v) for v in speeds]
    if len(tables) != len(speeds):
        raise ValueError(f"{len(tables)} tables for {len(speeds)} class speeds: give one table per speed.")
    for tab, v in zip(tables, speeds):
        if chain.table_speed(tab) != v:
            raise ValueError(f"a table at {chain.table_speed(tab)!r} m/s was given for the class speed {v!r} m/s.")
    return dict(zip(speeds, tables))


def _modes_text(modes) -> str:
    """A wheelset's modes as results name them: its label and natural frequencies [Hz], or the report's fixed creepage."""
    if modes is None:
        return "the report's fixed creepage (no wheelset modes)"
    return f"{modes.label or 'wheelset'}, modes at {', '.join(hz_text(o / (2 * np.pi)) for o in modes.omega)} Hz"


def _chain_text(ws) -> str:
    """A wheelset's stated inertias [kg m^2], stiffnesses [N m/rad] and damping [-]."""
    drive = (f", J_m {ws.motor_inertia:g} kg m^2, k_c {ws.coupling_stiffness:g} N m/rad" if ws.driven else "")
    return (f"{ws.model}, J_w {ws.wheel_inertia:g} kg m^2, J_c {ws.centre_inertia:g} kg m^2, k_a {ws.axle_stiffness:g} N m/rad{drive}, "
            f"damping {ws.damping:g}")


def wheelset_lines(classes, fleet: Fleet, section_motored: bool = False) -> list[str]:
    """Which wheelset each vehicle's axles run, one line per vehicle, read from what its class's contacts run
    (rail.chain.wheel_material of each axle): the name of fleet.wheelsets it refers to (or 'its own' for one given
    in place), motored or trailer, the modes and the stated chain; or, for a vehicle that names none, the
    wheelset section's modes on every axle (or the report's fixed creepage), as before per-axle wheelsets.

    Parameters
    ----------
    classes : sequence of rail.fleet.FleetClass
        The fleet's classes (Fleet.classes); a vehicle's first class is read.
    fleet : rail.fleet.Fleet
    section_motored : bool
        Whether the wheelset section has a drive (wheelset.motor_inertia > 0): a vehicle that names no wheelsets
        then runs the motor on every axle, which its line says.

    Returns
    -------
    list of str
        '<vehicle>: <axles> <wheelset>; ...' [-].
    """
    first = {}
    for c in classes:
        first.setdefault(c.vehicle, c)
    out = []
    for v in fleet.vehicles:
        if v.name not in first:
            out.append(f"{v.name}: no class (share 0)")
            continue
        scn = first[v.name].scenario
        groups = {}  # one entry per wheelset object the axles run, in axle order
        for l in range(v.axles):
            ws = None if v.wheelsets is None else v.wheelsets[l]
            modes = chain.wheel_material(scn, l).longitudinal
            groups.setdefault((id(ws), id(modes)), (ws, modes, v.wheelset_names[l] if v.wheelset_names else "", []))[3].append(l)
        parts = []
        for ws, modes, name, axles in groups.values():
            which = (f"every axle ({v.axles})" if len(axles) == v.axles else
                     f"axle{'s' if len(axles) > 1 else ''} {', '.join(str(l + 1) for l in axles)} "
                     f"(at {', '.join(f'{v.positions[l]:g}' for l in axles)} m)")
            if ws is None:
                what = (f"the wheelset section's: {_modes_text(modes)}" if modes is not None else
                        "the report's fixed creepage (no wheelset section)")
                if modes is not None and section_motored:
                    what += (" (the section's motor on every axle of this vehicle: where some are trailers, name them in "
                             "fleet.vehicles[*].wheelsets)")
            else:
                label = f"wheelset '{name}'" if name else "its own wheelset"
                what = f"{label}, {'motored' if ws.driven else 'trailer'}: {_modes_text(modes)} ({_chain_text(ws)})"
            parts.append(f"{which} {what}")
        out.append(f"{v.name}: " + "; ".join(parts))
    return out


def spectrum_arrays(sp) -> dict:
    """A class's RateSpectrum as arrays (numpy.savez; spectrum_from_arrays reads it back exactly).

    Parameters
    ----------
    sp : rail.growth_spectrum.RateSpectrum

    Returns
    -------
    dict
        Its fields by name (operator left out when None; method as a string array).
    """
    out = {f.name: np.asarray(getattr(sp, f.name)) for f in dataclasses.fields(sp) if getattr(sp, f.name) is not None}
    out["method"] = np.array(str(sp.method))
    return out


def spectrum_from_arrays(arrays) -> "RateSpectrum":
    """The RateSpectrum of spectrum_arrays (a mapping such as an opened .npz).

    Parameters
    ----------
    arrays : mapping of name to ndarray
        As spectrum_arrays writes them: the RateSpectrum's fields by name (its wavelengths [m], rates per train
        passage [-], ...).

    Returns
    -------
    rail.growth_spectrum.RateSpectrum
    """

    kw = {}
    for f in dataclasses.fields(RateSpectrum):
        if f.name not in arrays:
            kw[f.name] = None
            continue
        v = np.asarray(arrays[f.name])
        kw[f.name] = (str(v) if f.name == "method" else int(v) if f.name in ("bays", "grid_phases")
                      else float(v) if v.ndim == 0 else v)
    return RateSpectrum(**kw)


def fleet_spectrum_dataset(fs: FleetRateSpectrum, fleet: Fleet, classes=None) -> xr.Dataset:
    """The growth-rate spectrum under a fleet, per fleet passage and per year, with each class kept.

    Parameters
    ----------
    fs : rail.growth_spectrum.FleetRateSpectrum
    fleet : rail.fleet.Fleet
        Its traffic (axles per day, axles per train) converts per-passage rates to per-year rates.
    classes : sequence of rail.fleet.FleetClass, optional
        The classes of ``fs``: the attribute ``fleet_wheelsets`` states which wheelset each vehicle's axles ran
        (wheelset_lines); left out without them.

    Returns
    -------
    xr.Dataset
        growth_rate, drift, growth_dB_per_1e5_trains (per fleet passage), growth_dB_per_1e5_axles, growth_dB_per_year,
        growth_dB_per_MGT over wavelength; class_growth_rate (per
        passage of the class's train) and class_contribution (w_c times it) over (class, wavelength).
    """
    t = fs.total
    g = -t.rate.real
    gc = np.array([-s.rate.real for s in fs.classes])
    trains_per_year = fleet.trains_per_day * 365
    d_axle = DB_PER_NEPER * g * PASSAGES_PER_DB / fleet.axles_per_train
    traffic = Traffic(fleet.axles_per_day, fleet.mean_axle_load)
    return xr.Dataset(
        {
            "growth_rate": data_var("wavelength", g, "1", "relative growth rate of the roughness amplitude per fleet passage, -Re R "
                                "(R = sum_c w_c R_c; > 0: grows)"),
            "growth_rate_other": data_var("wavelength", -t.rate_other.real, "1", "growth rate of the other phase at a locked line"),
            "drift": data_var("wavelength", -t.rate.imag, "rad", "phase drift of the roughness per fleet passage, -Im R"),
            "growth_dB_per_1e5_trains": data_var("wavelength", DB_PER_NEPER * g * PASSAGES_PER_DB, f"dB per {PASSAGES_PER_DB} train passages",
                                             f"level change per {PASSAGES_PER_DB} fleet passages (passages of whole trains of "
                                             "the fleet's mix) of a small roughness at the wavelength"),
            "growth_dB_per_1e5_axles": data_var("wavelength", d_axle, "dB per 100000 axle passages",
                                            "level change per 100,000 axle passages of the traffic of a small roughness at "
                                            "the wavelength (growth_dB_per_1e5_trains / axles_per_train)"),
            "growth_dB_per_MGT": data_var("wavelength", traffic.per_mgt(d_axle), "1/Mt",
                                      "level change per million gross tonnes of the traffic (growth_dB_per_1e5_axles x 1e6 / "
                                      "mean axle load [t] / 1e5)", level_unit="dB", units_text="dB/Mt"),
            "growth_rate_per_year": data_var("wavelength", g * trains_per_year, "1/year",
                                         "relative growth rate of the roughness amplitude per year of the traffic"),
            "growth_dB_per_year": data_var("wavelength", DB_PER_NEPER * g * trains_per_year, "1/year",
                                       "level change per year of the traffic of a small roughness at the wavelength",
                                       level_unit="dB", units_text="dB/year"),
            "grid_spread": data_var("wavelength", t.grid_spread, "1", "sum_c w_c of the classes' grid spreads (an upper bound)"),
            "class_growth_rate": data_var(("class", "wavelength"), gc, "1",
                                      "growth rate of each class alone per passage of its train (-Re R_c)"),
            "class_drift": data_var(("class", "wavelength"), np.array([-s.rate.imag for s in fs.classes]), "rad",
                                "phase drift of each class alone per passage of its train"),
            "class_contribution": data_var(("class", "wavelength"), fs.weights[:, None] * gc, "1",
                                       "the class's share of the fleet's growth rate per fleet passage, w_c (-Re R_c); sums to "
                                       "growth_rate at a free line (at a locked line the fleet's rate is the eigenvalue of the "
                                       "weighted sum of the 2 x 2 operators)"),
        },
        coords={
            "wavelength": data_var("wavelength", t.wavelength, "m", "roughness wavelength N L / j"),
            "line": data_var("wavelength", t.line, "1", f"line j of the {t.bays}-bay period"),
            "locked": data_var("wavelength", t.locked, "1", "0 free line; 1 on the one-bay comb; 2 on the half-comb"),
            "class": data_var("class", np.arange(len(fs.classes)), "1", "(vehicle, speed) class"),
            "class_label": data_var("class", np.array(fs.labels), "", "vehicle and speed of the class"),
            "class_speed": data_var("class", fs.speeds, "m/s", "train speed of the class"),
            "class_weight": data_var("class", fs.weights, "1", "w_c = share_v x weight_s, the class's share of the fleet passages"),
        },
        attrs={"eps_m": t.eps, "bays": t.bays, "grid_phases": t.grid_phases, "method": t.method,
               "passages": "per fleet passage: one train drawn from the traffic (docs/traffic.md)",
               "years": f"per year: x {trains_per_year:.6g} fleet passages a year (axles_per_day x 365 / axles_per_train)",
               **fleet.attributes(), **({} if classes is None else {"fleet_wheelsets": " | ".join(wheelset_lines(classes, fleet))})},
    )


def fleet_growth_dataset(classes, tables: dict, history, fleet: Fleet) -> xr.Dataset:
    """The growth dataset of a fleet run (rail.chain.grow_fleet): levels and profiles at every saved
    count of axle passages, that count in years of the traffic, and the traffic's units.

    The wheel forces are those of the heaviest-weighted class (attribute ``force_class``).

    Parameters
    ----------
    classes : sequence of rail.fleet.FleetClass
    tables : dict
        {speed: table} of the run.
    history : rail.growth.GrowthHistory
    fleet : rail.fleet.Fleet

    Returns
    -------
    xr.Dataset
    """
    main = max(classes, key=lambda c: c.weight)
    scn, table = main.scenario, tables[main.speed]
    bays = scn.roughness.bays

    def force(Z, x):
        return interaction.force_history(chain.solve_forces(scn, table, interaction.Roughness(Z, bays)), x)

    ds = datasets.growth(history, scn.track, fleet.speeds.mean, len(scn.wheels.positions), bays=bays, force=force)
    years = history.passages / fleet.axles_per_day / 365
    ds = ds.assign_coords(years=data_var("passage", years, "year", "years of the traffic (axle passages / axles_per_day / 365)"),
                          mgt=data_var("passage", years * fleet.mgt_per_year, "Mt", "million gross tonnes of traffic"))
    ds["passage"].attrs["long_name"] = "axle passages of the traffic (wheel passages on one rail)"
    ds["exponential_rate"].attrs["long_name"] += " (per axle passage of the traffic)"
    ds["exponential_rate_per_year"] = ds["exponential_rate"] * fleet.axles_per_day * 365
    ds["exponential_rate_per_year"].attrs = {"units": "1/year", "long_name": "e-folding rate of the rms amplitude per year of traffic"}
    # the move of the contact centre, for the heaviest-weighted class: reported, and flagged where it is
    # neglected (contact.wear_path: wheel) beyond rail.chain.SWEEP_ERROR_LIMIT, as for one train
    ds = datasets.with_contact_shift(ds, [chain.contact_shift(scn, table, Z) for Z in history.Z], chain.SWEEP_ERROR_LIMIT,
                                     scn.contact_numerics.path)
    ds.attrs.update({**fleet.attributes(), "force_class": main.label, "speed_m_per_s": fleet.speeds.mean,
                     "wheels": chain.fleet_wheels(classes), **scn.models.attributes()})
    if creepage_model_text(scn.material):  # the rail's flexibility and the friction law, shared by every class
        ds.attrs["creepage_model"] = creepage_model_text(scn.material)
    ds.attrs["fleet_wheelsets"] = " | ".join(wheelset_lines(classes, fleet))  # each vehicle's axles (rail.chain.wheel_material)
    if history.stopped:
        ds.attrs["stopped"] = history.stopped
    return ds


def band_rates(wavelength, rate, bands) -> np.ndarray:
    """Mean of the line rates in each one-third-octave band (NaN where a band holds no line: say so,
    do not fill it).

    Parameters
    ----------
    wavelength : ndarray
        Line wavelengths [m].
    rate : ndarray
        A rate per line (any unit) on the last axis.
    bands : rail.bands.ThirdOctaveBands

    Returns
    -------
    ndarray
        (..., band).
    """
    lam = np.asarray(wavelength)
    rate = np.asarray(rate, dtype=float)
    out = np.full(rate.shape[:-1] + (bands.centre.size,), np.nan)
    for b, (lo, hi) in enumerate(zip(bands.lower, bands.upper)):
        sel = in_band(lam, lo, hi)  # the one band rule (rail.bands)
        if sel.any():
            out[..., b] = rate[..., sel].mean(axis=-1)
    return out


def traffic_study_dataset(spectra, cases) -> xr.Dataset:
    """The traffic study's fleet spectra on one grid (drive, spread, wavelength), with their
    one-third-octave band means and the pinned-pinned band.

    Parameters
    ----------
    spectra : sequence of xr.Dataset
        fleet_spectrum_dataset of each case, all on the same lines, with the attribute
        pinned_pinned_wavelength_m (at the mean speed).
    cases : sequence of (drive, spread)
        One per spectrum [-].

    Returns
    -------
    xr.Dataset
        growth_dB_per_1e5_axles (drive, spread, wavelength) and band_growth_dB_per_1e5_axles (drive, spread, band)
        [dB per 100,000 axle passages]; attributes pinned_pinned_wavelength_m and pinned_pinned_band_m
        (the nominal centre of the band holding it).
    """
    drives = list(dict.fromkeys(d for d, _ in cases))
    spreads = sorted({float(s) for _, s in cases})
    lam = spectra[0]["wavelength"].values
    for ds in spectra:
        if not np.array_equal(ds["wavelength"].values, lam):
            raise ValueError("the traffic study's spectra must share their lines (one figures.rate_spectrum for every case).")
    g = np.full((len(drives), len(spreads), lam.size), np.nan)
    for ds, (d, s) in zip(spectra, cases):
        g[drives.index(d), spreads.index(float(s))] = ds["growth_dB_per_1e5_axles"].values
    if np.isnan(g).any():
        raise ValueError("the traffic study needs one spectrum for every (drive, spread).")
    bands = wavelength_bands(float(lam.max()), float(lam.min()))
    bands = bands.select((bands.upper > lam.min()) & (bands.lower < lam.max()))
    gb = band_rates(lam, g, bands)
    pp = float(spectra[0].attrs["pinned_pinned_wavelength_m"])
    ib = int(np.flatnonzero(in_band(pp, bands.lower, bands.upper))[0])  # the one band rule (rail.bands)
    first = spectra[0]
    return xr.Dataset(
        {
            "growth_dB_per_1e5_axles": data_var(("drive", "spread", "wavelength"), g, "dB per 100000 axle passages",
                                       "level change per 100,000 axle passages of the traffic of a small roughness"),
            "band_growth_dB_per_1e5_axles": data_var(("drive", "spread", "band"), gb, "dB per 100000 axle passages",
                                            "mean over the band's lines of the level change per 100,000 axle passages "
                                            "(NaN: no line in the band)"),
        },
        coords={
            "drive": data_var("drive", np.array(drives), "", "drive of the locomotive's axles (config/traffic_study.yaml)"),
            "spread": data_var("spread", np.array(spreads), "1", "speed spread s: speeds uniform on V (1 -+ s)"),
            "wavelength": data_var("wavelength", lam, "m", "roughness wavelength"),
            "band": data_var("band", bands.nominal, "m", "nominal centre wavelength of the one-third-octave band (EN 15610)"),
            "band_lower": data_var("band", bands.lower, "m", "band edge, shorter wavelength"),
            "band_upper": data_var("band", bands.upper, "m", "band edge, longer wavelength"),
        },
        attrs={"pinned_pinned_wavelength_m": pp, "pinned_pinned_band_m": float(bands.nominal[ib]),
               "pinned_pinned_frequency_Hz": float(first.attrs["pinned_pinned_frequency_Hz"]),
               "mean_speed_m_per_s": float(first.attrs["mean_speed_m_per_s"]),
               "axles_per_train": float(first.attrs["axles_per_train"]), "fleet_vehicles": first.attrs["fleet_vehicles"],
               "lines": int(lam.size), "bays": int(first.attrs["bays"]), "grid_phases": int(first.attrs["grid_phases"])},
    )


def traffic_summary_markdown(ds: xr.Dataset) -> str:
    """What the pinned-pinned band and the fastest-growing band do across the traffic study's cases
    (traffic_study_dataset), as a markdown page of numbers.

    Parameters
    ----------
    ds : xr.Dataset

    Returns
    -------
    str
    """
    pp_band = float(ds.attrs["pinned_pinned_band_m"])
    lam = ds["wavelength"].values
    rows = []
    for d in ds["drive"].values:
        for s in ds["spread"].values:
            b = ds["band_growth_dB_per_1e5_axles"].sel(drive=d, spread=s)
            g = ds["growth_dB_per_1e5_axles"].sel(drive=d, spread=s).values
            ifast = int(np.nanargmax(b.values))
            iline = int(np.argmax(g))
            rows.append(f"| {d} | ±{100 * s:g} % | {float(b.sel(band=pp_band)):+.3g} | {1e3 * float(b['band'][ifast]):g} | "
                        f"{float(b.values[ifast]):+.3g} | {1e3 * lam[iline]:.1f} | {g[iline]:+.3g} |")
    head = (f"# Traffic study: growth-rate spectrum under the fleet\n\n"
            f"Mean speed {ds.attrs['mean_speed_m_per_s']:g} m/s; pinned-pinned frequency {ds.attrs['pinned_pinned_frequency_Hz']:.0f} Hz, "
            f"wavelength {1e3 * ds.attrs['pinned_pinned_wavelength_m']:.1f} mm at the mean speed, in the one-third-octave band of "
            f"nominal centre {1e3 * pp_band:g} mm. Rates in dB per 100,000 axle passages of the traffic (a fleet passage is "
            f"{ds.attrs['axles_per_train']:g} axles); a band's rate is the mean of its lines' rates ({ds.attrs['lines']} lines of a "
            f"{ds.attrs['bays']}-bay period, {ds.attrs['grid_phases']} contact grids). Vehicles: {ds.attrs['fleet_vehicles']}.\n\n"
            "| drive | speed spread | pinned-pinned band | fastest band (mm) | its rate | fastest line (mm) | its rate |\n"
            "|---|---|---|---|---|---|---|\n")
    return head + "\n".join(rows) + "\n"
