"""Figure of the dynamic-creepage study over speed (rail.studies.speed_study, named target
dynamic_creepage_speeds): growth rate against frequency, a panel per mechanism and track."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

__all__ = ["speed_study_figure"]

_TICKS_HZ = (50, 100, 200, 500, 1000, 2000, 5000)  # round frequencies, written plainly (200, not 2×10²)


def speed_study_figure(ds: xr.Dataset):
    """Growth rate (dB per 100,000 axles) against the passing frequency, one curve per speed, a panel per
    mechanism (columns) and track (rows); the pinned-pinned frequency and zero growth marked.

    Parameters
    ----------
    ds : xr.Dataset
        rail.studies.speed_study.study_dataset's: rates [dB per 100000 axle passages] per mechanism, track,
        speed [m/s] and frequency [Hz].

    Returns
    -------
    matplotlib.figure.Figure
    """
    mechs = list(dict.fromkeys(ds["mechanism"].values.tolist()))
    tracks = list(dict.fromkeys(ds["track"].values.tolist()))
    fig, axs = plt.subplots(len(tracks), len(mechs), figsize=(2.9 * len(mechs) + 1, 2.6 * len(tracks) + 0.8), sharex=True, sharey=True,
                            squeeze=False, layout="constrained")
    colours = plt.cm.viridis(np.linspace(0.0, 0.85, ds.sizes["speed"]))
    for i in range(ds.sizes["case"]):
        c = ds.isel(case=i)
        ax = axs[tracks.index(c["track"].item()), mechs.index(c["mechanism"].item())]
        for k, V in enumerate(c["speed"].values):
            r = c["growth_dB_per_1e5_axles"].values[k]
            if np.all(np.isnan(r)):
                continue
            f = c["frequency"].values[k]
            ax.plot(f, r, "o-", ms=2.5, lw=1.0, color=colours[k], label=f"{V:g} m/s")
        ax.axvline(float(c["pinned_pinned_Hz"]), color="0.4", ls="--", lw=0.9, label="pinned-pinned")
        ax.axhline(0.0, color="k", lw=0.6)
        ax.set_xscale("log")
        ax.xaxis.set_major_locator(matplotlib.ticker.FixedLocator(_TICKS_HZ))
        ax.xaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.set_title(f"{c['mechanism'].item()}\n{c['track'].item()}", fontsize=8)
    for ax in axs[-1]:
        ax.set_xlabel("frequency V / λ (Hz)")
    for ax in axs[:, 0]:
        ax.set_ylabel("growth (dB per 1e5 axles)")
    handles, labels = axs[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncol=len(labels), fontsize=8)
    fig.suptitle("Dynamic creepage over speed: growth rate of each line (20-120 mm)", fontsize=10)
    return fig
