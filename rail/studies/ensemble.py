"""Datasets of the uncertainty ensemble (rail.uncertainty, config/uncertainty.yaml): the growth-rate
spectrum of every member, its one-third-octave band means, and their median and stated interval."""

from __future__ import annotations

import numpy as np
import xarray as xr

from ..uncertainty import band_statistics
from .bands import third_octave_bands
from .datasets import _var

__all__ = ["ensemble_dataset"]


def ensemble_dataset(members, values: dict, interval=(0.1, 0.9)) -> xr.Dataset:
    """The ensemble's spectra (member, wavelength), band means (member, band) and, per band, the median
    and the interval between the stated quantiles over the members.

    Parameters
    ----------
    members : sequence of xr.Dataset
        rate_spectrum_dataset of each member at one speed, on the same lines.
    values : dict
        {dotted key: (members,) drawn values} (rail.uncertainty.sample).
    interval : (float, float)
        Quantiles [-].

    Returns
    -------
    xr.Dataset
        growth_dB (member, wavelength), band_growth_dB (member, band), band_median, band_lower,
        band_upper (band) [dB per 100,000 train passages]; each parameter's draws as a coordinate.
    """
    lam = members[0]["wavelength"].values
    for m in members:
        if not np.array_equal(m["wavelength"].values, lam):
            raise ValueError("the ensemble's spectra must share their lines (one figures.rate_spectrum for every member).")
    g = np.array([m["growth_dB"].values.reshape(-1, lam.size)[0] for m in members])
    bands = third_octave_bands(float(lam.max()), float(lam.min()))
    keep = (bands.upper > lam.min()) & (bands.lower < lam.max())
    centre, nominal, lower, upper = (x[keep] for x in (bands.centre, bands.nominal, bands.lower, bands.upper))
    gb = np.full((len(members), centre.size), np.nan)
    for b in range(centre.size):
        sel = (lam >= lower[b]) & (lam < upper[b])
        if sel.any():
            gb[:, b] = g[:, sel].mean(axis=1)
    med, lo, hi = band_statistics(gb, interval)
    unit = "dB"
    coords = {
        "member": _var("member", np.arange(len(members)), "1", "ensemble member"),
        "wavelength": _var("wavelength", lam, "m", "roughness wavelength"),
        "band": _var("band", nominal, "m", "nominal centre wavelength of the one-third-octave band (EN 15610)"),
    }
    for key, v in values.items():
        coords[f"draw_{key}"] = _var("member", np.asarray(v, dtype=float), "", f"drawn value of {key} (its unit in the configuration)")
    q = f"{100 * interval[0]:g}-{100 * interval[1]:g} % quantiles"
    return xr.Dataset(
        {
            "growth_dB": _var(("member", "wavelength"), g, unit, "level change per 100,000 train passages of a small roughness"),
            "band_growth_dB": _var(("member", "band"), gb, unit, "mean over the band's lines of growth_dB (NaN: no line in the band)"),
            "band_median": _var("band", med, unit, "median of band_growth_dB over the members"),
            "band_lower": _var("band", lo, unit, f"lower end of the interval ({q}) of band_growth_dB over the members"),
            "band_upper": _var("band", hi, unit, f"upper end of the interval ({q}) of band_growth_dB over the members"),
        },
        coords=coords,
        attrs={"interval_quantiles": list(interval), "members": len(members)},
    )
