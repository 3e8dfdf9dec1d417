"""Datasets of the uncertainty ensemble (rail.uncertainty, config/uncertainty.yaml): the growth-rate
spectrum of every member, its one-third-octave band means, and their median and stated interval."""

from __future__ import annotations

import numpy as np
import xarray as xr

from ..uncertainty import band_statistics
from ..bands import in_band, wavelength_bands
from ..setup.io import data_var

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
        growth_dB_per_1e5_axles (member, wavelength), band_growth_dB_per_1e5_axles (member, band),
        band_median_dB_per_1e5_axles, band_lower_dB_per_1e5_axles, band_upper_dB_per_1e5_axles (band)
        [dB per 100,000 axle (wheel) passages: each member's train is one wheel, so per axle and per
        train passage are the same numbers]; each parameter's draws as a coordinate.
    """
    lam = members[0]["wavelength"].values
    for m in members:
        if not np.array_equal(m["wavelength"].values, lam):
            raise ValueError("the ensemble's spectra must share their lines (one figures.rate_spectrum for every member).")
    g = np.array([m["growth_dB_per_1e5_axles"].values.reshape(-1, lam.size)[0] for m in members])
    bands = wavelength_bands(float(lam.max()), float(lam.min()))
    bands = bands.select((bands.upper > lam.min()) & (bands.lower < lam.max()))
    centre, nominal, lower, upper = bands.centre, bands.nominal, bands.lower, bands.upper
    gb = np.full((len(members), centre.size), np.nan)
    for b in range(centre.size):
        sel = in_band(lam, lower[b], upper[b])  # the one band rule (rail.bands)
        if sel.any():
            gb[:, b] = g[:, sel].mean(axis=1)
    med, lo, hi = band_statistics(gb, interval)
    unit = "dB per 100000 axle passages"
    coords = {
        "member": data_var("member", np.arange(len(members)), "1", "ensemble member"),
        "wavelength": data_var("wavelength", lam, "m", "roughness wavelength"),
        "band": data_var("band", nominal, "m", "nominal centre wavelength of the one-third-octave band (EN 15610)"),
    }
    for key, v in values.items():
        coords[f"draw_{key}"] = data_var("member", np.asarray(v, dtype=float), "", f"drawn value of {key} (its unit in the configuration)")
    q = f"{100 * interval[0]:g}-{100 * interval[1]:g} % quantiles"
    return xr.Dataset(
        {
            "growth_dB_per_1e5_axles": data_var(("member", "wavelength"), g, unit,
                                            "level change per 100,000 axle (wheel) passages of a small roughness"),
            "band_growth_dB_per_1e5_axles": data_var(("member", "band"), gb, unit, "mean over the band's lines of growth_dB_per_1e5_axles "
                                                 "(NaN: no line in the band)"),
            "band_median_dB_per_1e5_axles": data_var("band", med, unit, "median of band_growth_dB_per_1e5_axles over the members"),
            "band_lower_dB_per_1e5_axles": data_var("band", lo, unit,
                                                f"lower end of the interval ({q}) of band_growth_dB_per_1e5_axles over the members"),
            "band_upper_dB_per_1e5_axles": data_var("band", hi, unit,
                                                f"upper end of the interval ({q}) of band_growth_dB_per_1e5_axles over the members"),
        },
        coords=coords,
        attrs={"interval_quantiles": list(interval), "members": len(members)},
    )
