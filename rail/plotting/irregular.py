"""Figures of the irregular-track study (rail.studies.irregular, named target irregular_track)."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

from . import text  # noqa: E402
from .axes import mark_supports, wavelength_axis  # noqa: E402

__all__ = ["case_figure", "summary_figure"]


def case_figure(ds: xr.Dataset, title: str):
    """Four panels, each beside the uniform track: receptance above each support, force along the cell,
    roughness after the run, growth-rate spectrum (pinned-pinned wavelength marked).

    Parameters
    ----------
    ds : xr.Dataset
        One irregular case beside the uniform track (workflow/scripts/irregular_case.py): receptance [m/N],
        force [N], roughness [m] and growth rates [dB per 100000 axle passages].
    title : str
        The figure's title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, axs = plt.subplots(2, 2, figsize=(11, 8), layout="constrained")
    a, b, c, d = axs.ravel()
    f = ds["frequency"].values
    for j, lab in enumerate(ds["support_label"].values):
        a.plot(f, ds["receptance_above_support_dB"].values[:, j], lw=1.1, label=str(lab))
    a.plot(f, ds["uniform_receptance_above_support_dB"].values, "k--", lw=1.2, label="uniform track, above a support")
    a.plot(f, ds["uniform_receptance_mid_bay_dB"].values, "k:", lw=1.2, label="uniform track, mid-span")
    a.set_xscale("log")
    a.set_xlabel("frequency (Hz)")
    a.set_ylabel("point receptance (dB re 1 m/N)")
    a.set_title("receptance above each support", fontsize=9)
    a.legend(fontsize=6.5, loc="lower left")
    x = ds["position"].values
    b.plot(x, ds["force"].values / 1e3, lw=1.2, label="this track")
    xu = ds["position_uniform"].values
    L = float(xu[-1] - xu[0]) if xu.size > 1 else 0.6
    reps = int(np.ceil((x[-1] - x[0]) / L)) if L > 0 else 1
    b.plot(np.concatenate([xu + k * L for k in range(reps)]), np.tile(ds["uniform_force"].values, reps) / 1e3, "k--", lw=1.0,
           label="uniform track")
    b.set_xlim(x[0], x[-1])
    xlabel = "wheel position along the cell (m)"
    if "support_position" in ds.coords:  # the supports, a differing one (a voided sleeper) in red
        marks = [(float(p), str(d)) for p, d in zip(ds["support_position"].values, ds["support_difference"].values)]
        xlabel += "\n" + mark_supports(b, marks + [(float(ds.attrs["cell_period_m"]), marks[0][1])])
    b.set_xlabel(xlabel)
    b.set_ylabel("contact force (kN)")
    b.set_title(f"one wheel over the smooth rail at {ds.attrs['speed_m_per_s']:g} m/s", fontsize=9)
    b.legend(fontsize=8)
    lam = ds["wavelength"].values * 1e3
    c.plot(lam, ds["level"].values, "o", ms=2.5, label="this track (lines of the cell)")
    c.plot(ds["wavelength_uniform"].values * 1e3, ds["uniform_level"].values, "k^", ms=4, mfc="none", label="uniform track (comb L/k)")
    top = np.nanmax(np.concatenate([ds["level"].values, ds["uniform_level"].values]))
    c.set_ylim(top - 100, top + 5)  # lines 100 dB below the loudest are round-off (e.g. the odd lines of a cell of identical bays)
    c.set_xscale("log")
    c.set_xlabel("wavelength (mm)")
    c.set_ylabel("roughness level (dB re 1 µm)")
    c.set_title(ds["level"].attrs["long_name"], fontsize=9)
    c.legend(fontsize=8)
    d.plot(ds["spectrum_wavelength"].values * 1e3, ds["growth_dB_per_1e5_axles"].values, "-", lw=1.2, label="this track")
    d.plot(ds["spectrum_wavelength_uniform"].values * 1e3, ds["uniform_growth_dB_per_1e5_axles"].values, "k--", lw=1.0, label="uniform track")
    d.axhline(0, color="0.4", lw=0.7)
    d.set_xscale("log")
    d.set_xlabel("wavelength (mm)")
    d.set_ylabel("growth (dB per 100,000 axle passages)")
    d.set_title("linearised growth-rate spectrum from the smooth rail", fontsize=9)
    d.legend(fontsize=8)
    for ax in (c, d):  # plain millimetre ticks, wavelength decreasing to the right as every study figure
        lo, hi = ax.get_xlim()
        wavelength_axis(ax, (lo, hi), pad=1.0, ticks=(20, 30, 50, 100, 200, 300, 500, 1000, 2000))
    lpp = 1e3 * float(ds.attrs["pinned_pinned_wavelength_m"])
    for ax in (c, d):
        ax.axvline(lpp, color="tab:red", lw=0.8, ls=":")
        ax.text(lpp, ax.get_ylim()[1], " pinned-pinned", color="tab:red", fontsize=7, va="top")
    fig.suptitle(title, fontsize=10)
    return fig


def summary_figure(table: xr.Dataset):
    """The pinned-pinned band's level after the run against the irregularity: the uniform track, the
    named cases, and the random tracks (median and range over seeds per spread).

    Parameters
    ----------
    table : xr.Dataset
        The study's summary (workflow/scripts/irregular_summary.py): pp_level_dB [dB re 1 µm] per case, its kind
        and spacing spread [-].

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = plt.subplots(figsize=(7.5, 4.5), layout="constrained")
    kind = table["kind"].values
    lvl = table["pp_level_dB"].values
    spread = table["spacing_spread"].values
    uni = lvl[kind == "uniform"]
    if uni.size:
        ax.axhline(float(uni[0]), color="k", ls="--", lw=1.0, label="uniform track")
    rnd = kind == "random"
    for s in sorted(set(spread[rnd].tolist())):
        sel = rnd & (spread == s)
        v = lvl[sel]
        ax.errorbar([100 * s], [np.median(v)], yerr=[[np.median(v) - v.min()], [v.max() - np.median(v)]], fmt="o", capsize=4,
                    color="tab:blue", label="random track: median and range over seeds" if s == min(spread[rnd]) else None)
        ax.plot(np.full(v.size, 100 * s) + 0.15, v, ".", color="tab:blue", alpha=0.5)
    named = (kind != "uniform") & ~rnd
    for k, (name, v) in enumerate(zip(table["case"].values[named], lvl[named])):
        ax.plot([-2 - k], [v], "s", ms=6, label=str(name))
    ax.set_xlabel("spread of the sleeper spacing in the random tracks (± %; named cases at the left)")
    band = float(table.attrs.get("pp_band_m", np.nan)) * 1e3
    ax.set_ylabel(f"level of the {band:g} mm band (dB re 1 µm)")
    ax.set_title(f"pinned-pinned band {text.after(int(table.attrs.get('passages', 0)))} at {table.attrs.get('speed_m_per_s', 0):g} m/s",
                 fontsize=9)
    ax.legend(fontsize=7, loc="best")
    return fig
