"""The settled rail roughness under the wheels' roughness (issue 58, rail.studies.wheel_source): per speed,
the wheels' roughness, the level each band settles to, the ground rail it starts from and the limit, over
the one-third-octave wavelength bands; and each line's settled level over frequency."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

__all__ = ["settled_figure"]


def _finite(v):
    v = np.asarray(v, dtype=float)
    return np.where(np.isfinite(v), v, np.nan)


def settled_figure(ds: xr.Dataset):
    """The settled spectrum's figure: bands (left) and lines over frequency (right), a colour per speed; a fleet's
    (its classes at several speeds) once, its lines over wavelength.

    Parameters
    ----------
    ds : xr.Dataset
        A spectrum with the wheels' source (rail.studies.wheel_source.source_dataset or fleet_source_dataset).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 4.8))
    mm = 1e3 * ds.band.values
    fleet = "speed" not in ds.settled_band_level_dB.dims  # a fleet's source (one row, lines over wavelength)
    wheels = "the fleet's wheels (the axles' mean square)" if fleet else f"wheels: {ds.attrs['wheel_roughness'].split(' (')[0]}"
    ax.plot(mm, ds.wheel_band_level_dB.values, "k-", lw=2, label=wheels)
    if "limit_dB" in ds:
        ax.plot(mm, ds.limit_dB.values, "r--", lw=1.5, label="limit")
        ax.plot(mm, ds.start_band_level_dB.values, "0.5", ls=":", lw=1.5, label=f"ground rail: {ds.attrs['ground_rail'].split(' (')[0]}")
    rows = [("under the fleet", ds.settled_band_level_dB.values, ds.settled_band_wheels_dB.values, 1e3 * ds.wavelength.values,
             ds.settled_level_dB.values)] if fleet else [
        (f"{V:g} m/s", ds.settled_band_level_dB.values[i], ds.settled_band_wheels_dB.values[i], ds.frequency.values[i],
         ds.settled_level_dB.values[i]) for i, V in enumerate(ds.speed.values)]
    colours = plt.cm.viridis(np.linspace(0, 0.9, len(rows)))
    for i, (what, lev, wheels, x, lines) in enumerate(rows):
        grows = np.isinf(lev) & (lev > 0)
        ax.plot(mm, _finite(lev), "o-", color=colours[i], ms=4, label=f"settled, {what}")
        ax.plot(mm, _finite(wheels), "s--", color=colours[i], ms=3, lw=1, label=f"the wheels' part alone, {what}")
        if grows.any():
            top = np.nanmax(ds.wheel_band_level_dB.values) + 5
            ax.plot(mm[grows], np.full(grows.sum(), top), "^", color=colours[i], ms=7,
                    label=f"a line grows: no settled level ({what})")
        bx.plot(x, _finite(lines), "o-", color=colours[i], ms=3, label=what)
    ax.set_xscale("log")
    ax.invert_xaxis()
    ax.set_xlabel("wavelength band centre (mm)")
    ax.set_ylabel("level (dB re 1 µm rms)")
    ax.set_title("one-third-octave bands: the wheels' roughness and the rail's settled level", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=6, loc="best", framealpha=0.8)
    if "pinned_pinned_Hz" in ds.attrs and not fleet:
        bx.axvline(ds.attrs["pinned_pinned_Hz"], color="k", ls="--", lw=1, label="pinned-pinned")
    if fleet and "pinned_pinned_wavelength_m" in ds.attrs:
        bx.axvline(1e3 * ds.attrs["pinned_pinned_wavelength_m"], color="k", ls="--", lw=1, label="pinned-pinned at the mean speed")
    bx.set_xscale("log")
    if fleet:
        bx.invert_xaxis()
    bx.set_xlabel("wavelength (mm)" if fleet else "excitation frequency V / λ (Hz)")
    bx.set_ylabel("settled line level (dB re 1 µm rms)")
    bx.set_title("each line of the spectrum (growing lines have none)", fontsize=10)
    bx.grid(True, which="both", alpha=0.3)
    bx.legend(fontsize=7)
    fig.suptitle("Expected rail roughness under the fleet's wheels' roughness (each axle alone on the track)" if fleet else
                 f"Expected rail roughness under the wheels' roughness ({ds.attrs.get('wheel_source_transfer', '')})", fontsize=10)
    fig.tight_layout()
    return fig
