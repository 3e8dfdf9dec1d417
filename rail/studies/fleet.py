"""Datasets of growth under a fleet (rail.fleet, docs/traffic.md): the fleet's growth-rate spectrum with
each class's contribution, and a fleet growth run, both with the traffic in axles per day and million
gross tonnes per year and the rates per year as well as per passage."""

from __future__ import annotations

import numpy as np
import xarray as xr

from .. import chain, interaction
from ..fleet import Fleet
from ..growth_spectrum import FleetRateSpectrum
from . import datasets
from .datasets import _var
from .rate_spectrum import PASSAGES_PER_DB

__all__ = ["fleet_spectrum_dataset", "fleet_growth_dataset", "tables_by_speed", "DB_PER_NEPER"]

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


def fleet_spectrum_dataset(fs: FleetRateSpectrum, fleet: Fleet) -> xr.Dataset:
    """The growth-rate spectrum under a fleet, per fleet passage and per year, with each class kept.

    Parameters
    ----------
    fs : rail.growth_spectrum.FleetRateSpectrum
    fleet : rail.fleet.Fleet
        Its traffic (axles per day, axles per train) converts per-passage rates to per-year rates.

    Returns
    -------
    xr.Dataset
        growth_rate, drift, growth_dB, growth_dB_per_year over wavelength; class_growth_rate (per
        passage of the class's train) and class_contribution (w_c times it) over (class, wavelength).
    """
    t = fs.total
    g = -t.rate.real
    gc = np.array([-s.rate.real for s in fs.classes])
    trains_per_year = fleet.trains_per_day * 365
    return xr.Dataset(
        {
            "growth_rate": _var("wavelength", g, "1", "relative growth rate of the roughness amplitude per fleet passage, -Re R "
                                "(R = sum_c w_c R_c; > 0: grows)"),
            "growth_rate_other": _var("wavelength", -t.rate_other.real, "1", "growth rate of the other phase at a locked line"),
            "drift": _var("wavelength", -t.rate.imag, "rad", "phase drift of the roughness per fleet passage, -Im R"),
            "growth_dB": _var("wavelength", DB_PER_NEPER * g * PASSAGES_PER_DB, "dB",
                              f"level change per {PASSAGES_PER_DB} fleet passages of a small roughness at the wavelength"),
            "growth_dB_per_axle": _var("wavelength", DB_PER_NEPER * g * PASSAGES_PER_DB / fleet.axles_per_train, "dB",
                                       f"level change per {PASSAGES_PER_DB} axle passages of the traffic of a small roughness at "
                                       "the wavelength (growth_dB / axles_per_train)"),
            "growth_rate_per_year": _var("wavelength", g * trains_per_year, "1/year",
                                         "relative growth rate of the roughness amplitude per year of the traffic"),
            "growth_dB_per_year": _var("wavelength", DB_PER_NEPER * g * trains_per_year, "1/year",
                                       "level change per year of the traffic of a small roughness at the wavelength",
                                       level_unit="dB", units_text="dB/year"),
            "grid_spread": _var("wavelength", t.grid_spread, "1", "sum_c w_c of the classes' grid spreads (an upper bound)"),
            "class_growth_rate": _var(("class", "wavelength"), gc, "1",
                                      "growth rate of each class alone per passage of its train (-Re R_c)"),
            "class_drift": _var(("class", "wavelength"), np.array([-s.rate.imag for s in fs.classes]), "rad",
                                "phase drift of each class alone per passage of its train"),
            "class_contribution": _var(("class", "wavelength"), fs.weights[:, None] * gc, "1",
                                       "the class's share of the fleet's growth rate per fleet passage, w_c (-Re R_c); sums to "
                                       "growth_rate at a free line (at a locked line the fleet's rate is the eigenvalue of the "
                                       "weighted sum of the 2 x 2 operators)"),
        },
        coords={
            "wavelength": _var("wavelength", t.wavelength, "m", "roughness wavelength N L / j"),
            "line": _var("wavelength", t.line, "1", f"line j of the {t.bays}-bay period"),
            "locked": _var("wavelength", t.locked, "1", "0 free line; 1 on the one-bay comb; 2 on the half-comb"),
            "class": _var("class", np.arange(len(fs.classes)), "1", "(vehicle, speed) class"),
            "class_label": _var("class", np.array(fs.labels), "", "vehicle and speed of the class"),
            "class_speed": _var("class", fs.speeds, "m/s", "train speed of the class"),
            "class_weight": _var("class", fs.weights, "1", "w_c = share_v x weight_s, the class's share of the fleet passages"),
        },
        attrs={"eps_m": t.eps, "bays": t.bays, "grid_phases": t.grid_phases, "method": t.method,
               "passages": "per fleet passage: one train drawn from the traffic (docs/traffic.md)",
               "years": f"per year: x {trains_per_year:.6g} fleet passages a year (axles_per_day x 365 / axles_per_train)",
               **fleet.attributes()},
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
    ds = ds.assign_coords(years=_var("passage", years, "year", "years of the traffic (axle passages / axles_per_day / 365)"),
                          mgt=_var("passage", years * fleet.mgt_per_year, "Mt", "million gross tonnes of traffic"))
    ds["passage"].attrs["long_name"] = "axle passages of the traffic (wheel passages on one rail)"
    ds["exponential_rate"].attrs["long_name"] += " (per axle passage of the traffic)"
    ds["exponential_rate_per_year"] = ds["exponential_rate"] * fleet.axles_per_day * 365
    ds["exponential_rate_per_year"].attrs = {"units": "1/year", "long_name": "e-folding rate of the rms amplitude per year of traffic"}
    ds.attrs.update({**fleet.attributes(), "force_class": main.label, "speed_m_per_s": fleet.speeds.mean,
                     "wheels": chain.fleet_wheels(classes), "normal_contact": scn.contact_numerics.normal})
    if history.stopped:
        ds.attrs["stopped"] = history.stopped
    return ds
