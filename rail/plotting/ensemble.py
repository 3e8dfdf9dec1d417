"""Figure of the uncertainty ensemble (rail.studies.ensemble)."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import xarray as xr  # noqa: E402

from .axes import wavelength_axis  # noqa: E402

__all__ = ["band_interval_figure"]


def band_interval_figure(ds: xr.Dataset):
    """Band spectrum of the growth rate: median over the members and its stated interval (shaded), each
    member's band values as dots; dB per 100,000 axle passages over band centre wavelength (mm).

    Parameters
    ----------
    ds : xr.Dataset
        The ensemble's band dataset (rail.studies.ensemble): rates [dB per 100000 axle passages] per member and band centre [m].

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = plt.subplots(figsize=(7.5, 4.5), layout="constrained")
    x = ds["band"].values * 1e3
    q = ds.attrs["interval_quantiles"]
    ax.fill_between(x, ds["band_lower_dB_per_1e5_axles"].values, ds["band_upper_dB_per_1e5_axles"].values, color="C0", alpha=0.3,
                    label=f"{100 * q[0]:g}-{100 * q[1]:g} % interval over {int(ds.attrs['members'])} members")
    ax.plot(x, ds["band_median_dB_per_1e5_axles"].values, "o-", color="C0", label="median")
    for m in ds["member"].values:
        ax.plot(x, ds["band_growth_dB_per_1e5_axles"].sel(member=m).values, ".", color="0.6", ms=2)
    ax.axhline(0, color="0.3", lw=0.7)
    wavelength_axis(ax, x, ticks=(20, 31.5, 50, 80, 125, 200, 315))  # decreasing to the right, as every study figure
    ax.set_xlabel("one-third-octave band centre wavelength (mm)")
    ax.set_ylabel("growth (dB per 100,000 axle passages)")
    ax.set_title("growth-rate band spectrum with the uncertainty of the inputs", fontsize=9)
    ax.legend(fontsize=7)
    return fig


