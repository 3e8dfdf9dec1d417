"""Track characterisation figures: point receptance, moving-load receptance, decay rate.

Each function takes the dataset built by ``rail.studies.characterisation`` (or read back from its netCDF
file) and returns a matplotlib Figure.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402
from matplotlib.ticker import FixedFormatter, FixedLocator, NullFormatter, NullLocator  # noqa: E402

__all__ = ["track_receptance", "moving_receptance", "track_decay_rate"]

_MARKS = (
    ("track_on_ballast_Hz", "track on ballast"),
    ("out_of_phase_Hz", "rail/sleeper out of phase"),
    ("pinned_pinned_Hz", "pinned-pinned"),
)


def _title(ds, what):
    return f"{what}, track '{ds.attrs.get('track_name', 'default')}' (L = {ds.attrs.get('sleeper_spacing_m', float('nan')):g} m)"


def _mark(ax, f, label, y=0.03):
    ax.axvline(f, color="0.5", lw=0.8, ls=":")
    ax.annotate(f"{label}\n{f:.0f} Hz", (f, y), xycoords=("data", "axes fraction"),
                ha="right", va="bottom" if y < 0.5 else "top", fontsize=7, rotation=90)


def track_receptance(ds: xr.Dataset):
    """Magnitude and phase of the vertical point receptance above a sleeper (solid) and at
    mid-span (dashed), with the characteristic frequencies marked (dotted).

    Parameters
    ----------
    ds : xr.Dataset
        rail.studies.characterisation.track_receptance's: receptance [m/N] over frequency [Hz].

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, (ax_m, ax_p) = plt.subplots(2, 1, figsize=(6.5, 6.0), sharex=True, layout="constrained", height_ratios=(2, 1))
    f = ds["frequency"]
    for key, style, label in (("sleeper", "-", "above a sleeper, x = 0"), ("midspan", "--", "mid-span, x = L/2")):
        a = ds[f"receptance_{key}_real"].values + 1j * ds[f"receptance_{key}_imag"].values
        color = "k" if key == "sleeper" else "tab:red"
        ax_m.loglog(f, np.abs(a), style, color=color, label=label)
        ax_p.semilogx(f, np.degrees(np.angle(a)), style, color=color)
    for key, label in _MARKS:
        if key in ds.attrs and np.isfinite(ds.attrs[key]):
            _mark(ax_m, ds.attrs[key], label)
            ax_p.axvline(ds.attrs[key], color="0.5", lw=0.8, ls=":")
    for ax in (ax_m, ax_p):
        ax.grid(True, which="both", alpha=0.3)
    ax_m.set_ylabel("receptance magnitude (m/N)")
    ax_p.set_ylabel("phase (degrees)")
    ax_p.set_yticks([-180, -90, 0])
    ax_p.set_ylim(-185, 5)
    ax_p.set_xlabel("frequency (Hz)")
    ax_p.set_xlim(float(f.min()), float(f.max()))
    ax_m.legend(loc="upper right", fontsize=8)
    ax_m.set_title(_title(ds, "Vertical point receptance"), fontsize=9)
    return fig


def moving_receptance(ds: xr.Dataset):
    """abs(a_0) of a moving harmonic load at the contact point for each speed (coloured) and the
    stationary point receptance averaged over the bay (black dashed).

    Parameters
    ----------
    ds : xr.Dataset
        rail.studies.characterisation.moving_receptance's: a_0 [m/N] over speed [m/s] and frequency [Hz].

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = plt.subplots(figsize=(6.5, 4.5), layout="constrained")
    f = ds["frequency"]
    speeds = ds["speed"].values
    colors = plt.get_cmap("viridis")(np.linspace(0.0, 0.85, len(speeds)))
    for i, (V, c) in enumerate(zip(speeds, colors)):
        a = ds["moving_receptance_real"][i] + 1j * ds["moving_receptance_imag"][i]
        ax.loglog(f, np.abs(a), "-", color=c, lw=1.2, label=f"V = {V:g} m/s")
    bay = ds["stationary_receptance_real"] + 1j * ds["stationary_receptance_imag"]
    ax.loglog(f, np.abs(bay), "--", color="k", lw=1.2, label="stationary, averaged over the bay")
    if "pinned_pinned_closed_form_Hz" in ds.attrs:
        _mark(ax, ds.attrs["pinned_pinned_closed_form_Hz"], "pinned-pinned", y=0.97)
    ax.grid(True, which="both", alpha=0.3)
    ax.set_xlim(float(f.min()), float(f.max()))
    ax.set_xlabel(r"excitation frequency $\Omega / 2\pi$ (Hz)")
    ax.set_ylabel(r"receptance at the contact point $|a_0|$ (m/N)")
    ax.legend(loc="lower left", fontsize=8)
    ax.set_title(_title(ds, "Moving-load receptance"), fontsize=9)
    return fig


def track_decay_rate(ds: xr.Dataset, measured: xr.Dataset | None = None):
    """Vertical track decay rate in one-third-octave bands, excited above a sleeper (circles) and
    at mid-span (squares) with EN 15461-like positions, dotted with far positions sampling the
    whole bay; a measured decay rate (``measured_decay_rate`` over ``measured_band_centre``), if
    given, on the same axes.

    Parameters
    ----------
    ds : xr.Dataset
        rail.studies.characterisation.track_decay_rate's: decay rate [dB/m] per band centre [Hz].
    measured : xr.Dataset, optional
        A measured decay rate (rail.studies.characterisation.measured_decay_rate).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = plt.subplots(figsize=(6.5, 4.5), layout="constrained")
    fc = ds["band_centre"].values
    L = ds.attrs.get("sleeper_spacing_m", np.nan)
    for i, x0 in enumerate(ds["excitation_position"].values):
        where = "above a sleeper" if np.isclose(x0, 0.0) else ("at mid-span" if np.isclose(x0, L / 2) else f"x0 = {x0:g} m")
        style = ("o-", "k") if i == 0 else ("s--", "tab:red")
        ax.plot(fc, ds["decay_rate"][i], style[0], color=style[1], ms=4, mfc="none", label=f"model, excited {where}")
        if "decay_rate_bay_sampled" in ds:
            ax.plot(fc, ds["decay_rate_bay_sampled"][i], ":", color=style[1], lw=1.0, label=f"model, excited {where}, far positions across the bay")
    if measured is not None:
        ax.plot(measured["measured_band_centre"], measured["measured_decay_rate"], "x", color="tab:blue", ms=7, mew=1.5, label="measured")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ticks = [f for f in (100, 125, 160, 200, 250, 315, 400, 500, 630, 800, 1000,
                         1250, 1600, 2000, 2500, 3150, 4000, 5000) if fc.min() <= f <= fc.max()]
    ax.xaxis.set_major_locator(FixedLocator(ticks))
    ax.xaxis.set_major_formatter(FixedFormatter([f"{t:g}" for t in ticks]))
    ax.xaxis.set_minor_locator(NullLocator())
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.tick_params(axis="x", labelrotation=90, labelsize=8)
    ax.grid(True, which="both", alpha=0.3)
    ax.set_xlabel("one-third-octave band centre frequency (Hz)")
    ax.set_ylabel("vertical track decay rate (dB/m)")
    lo, hi = ax.get_ylim()
    ax.set_ylim(lo, hi * 4)  # room for the legend above the curves
    ax.legend(loc="upper right", fontsize=7)
    ax.set_title(_title(ds, f"Track decay rate, EN 15461, {ds.attrs.get('frequencies_per_band', '?')} frequencies per band"), fontsize=9)
    return fig
