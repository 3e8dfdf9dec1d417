"""Map of the growth-rate spectrum over excitation frequency and speed (issue 54): does a growing band
keep its frequency (a vertical stripe: a frequency-fixing mechanism such as the pinned-pinned
resonance) or its wavelength (a stripe along a ray f = V / lambda through the origin)?

Each speed is a row of cells, one per line of the spectrum, from the midpoints between neighbouring
lines in frequency (f = V / lambda of the line); red grows, blue decays, on a scale symmetric about
zero growth. The pinned-pinned frequency is a vertical dashed line; the sleeper-passing harmonics
f = n V / L are rays from the origin (dotted), labelled with n; a line of constant wavelength lambda
would be the ray f = V / lambda.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.colors  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

__all__ = ["frequency_speed_cells", "rate_map_figure", "placeholder_figure"]


def frequency_speed_cells(frequency, speed):
    """Cell edges of a map over (frequency, speed) from the lines' frequencies at each speed.

    Parameters
    ----------
    frequency : ndarray, shape (n_speed, n_line)
        The lines' excitation frequencies V / lambda at each speed [Hz], each row monotonic.
    speed : ndarray, shape (n_speed,)
        The speeds [m/s], increasing.

    Returns
    -------
    f_edges : ndarray, shape (n_speed, n_line + 1)
        Each row's cell edges in frequency, at the midpoints between neighbouring lines and half a
        spacing beyond the end lines [Hz].
    v_edges : ndarray, shape (n_speed + 1,)
        The rows' edges in speed, at the midpoints between neighbouring speeds (one speed: +-5 %) [m/s].
    """
    f = np.atleast_2d(np.asarray(frequency, dtype=float))
    V = np.atleast_1d(np.asarray(speed, dtype=float))
    if f.shape[0] != V.size:
        raise ValueError(f"frequency has {f.shape[0]} rows but there are {V.size} speeds.")
    if f.shape[1] < 2:
        raise ValueError("a map needs at least two lines per speed.")
    order = np.argsort(f, axis=1)
    fs = np.take_along_axis(f, order, axis=1)
    mid = 0.5 * (fs[:, 1:] + fs[:, :-1])
    edges = np.concatenate([fs[:, :1] - (mid[:, :1] - fs[:, :1]), mid, fs[:, -1:] + (fs[:, -1:] - mid[:, -1:])], axis=1)
    if V.size == 1:
        v_edges = np.array([0.95 * V[0], 1.05 * V[0]])
    else:
        vm = 0.5 * (V[1:] + V[:-1])
        v_edges = np.r_[V[0] - (vm[0] - V[0]), vm, V[-1] + (V[-1] - vm[-1])]
    return edges, v_edges


def rate_map_figure(ds: xr.Dataset, pinned_pinned_Hz: float | None = None, harmonics: int = 40,
                    f_range: tuple[float, float] | None = None, title: str = ""):
    """Growth rate (dB per 100,000 axle passages) over excitation frequency and speed (module docstring).

    Parameters
    ----------
    ds : xarray.Dataset
        A growth-rate spectrum over speeds (rail.studies.rate_spectrum.rate_spectrum_dataset):
        growth_dB_per_1e5_axles and the coordinate frequency over (speed, wavelength); its attribute
        sleeper_spacing_m gives the sleeper-passing harmonics.
    pinned_pinned_Hz : float, optional
        The pinned-pinned frequency [Hz] (default: the attribute pinned_pinned_Hz, if any).
    harmonics : int
        The highest sleeper-passing harmonic n drawn [-].
    f_range : (float, float), optional
        The frequency axis [Hz] (default: the lines' range).
    title : str
        Added to the figure's title (for example the scenario and its model choices).

    Returns
    -------
    matplotlib.figure.Figure
    """
    g = np.asarray(ds["growth_dB_per_1e5_axles"].values, dtype=float)
    f = np.asarray(ds["frequency"].values, dtype=float)
    V = np.asarray(ds["speed"].values, dtype=float)
    f_edges, v_edges = frequency_speed_cells(f, V)
    order = np.argsort(f, axis=1)
    gs = np.take_along_axis(g, order, axis=1)
    finite = gs[np.isfinite(gs)]
    top = float(np.max(np.abs(finite))) if finite.size else 1.0
    norm = matplotlib.colors.TwoSlopeNorm(vmin=-max(top, 1e-6), vcenter=0.0, vmax=max(top, 1e-6))
    fig, ax = plt.subplots(figsize=(7.5, 4.2), layout="constrained")
    for k in range(V.size):
        xx = np.vstack([f_edges[k], f_edges[k]])
        yy = np.array([[v_edges[k]] * f_edges.shape[1], [v_edges[k + 1]] * f_edges.shape[1]])
        m = ax.pcolormesh(xx, yy, gs[k][None, :], cmap="RdBu_r", norm=norm, shading="flat")
    lo, hi = f_range if f_range is not None else (float(np.nanmin(f_edges)), float(np.nanmax(f_edges)))
    ax.set_xlim(lo, hi)
    ax.set_ylim(v_edges[0], v_edges[-1])
    L = ds.attrs.get("sleeper_spacing_m")
    if L:
        vv = np.array([v_edges[0], v_edges[-1]])
        last = np.inf  # the speed of the last label on the right edge: labels at least 1/30 of the axis apart
        for n in range(1, int(harmonics) + 1):
            fx = n * vv / float(L)
            if fx[1] < lo or fx[0] > hi:
                continue
            ax.plot(fx, vv, ":", color="0.35", lw=0.7)
            # label where the ray leaves the axes (top edge or the right edge)
            if fx[1] <= hi:
                ax.text(fx[1], vv[1], f"{n}", fontsize=6, color="0.3", ha="center", va="bottom")
            elif last - hi * float(L) / n > (vv[1] - vv[0]) / 30:
                last = hi * float(L) / n
                ax.text(hi, last, f"{n}", fontsize=6, color="0.3", ha="left", va="center")
    fpp = pinned_pinned_Hz if pinned_pinned_Hz is not None else ds.attrs.get("pinned_pinned_Hz")
    if fpp is not None and np.isfinite(float(fpp)):
        ax.axvline(float(fpp), color="k", ls="--", lw=1.0)
        ax.text(float(fpp), v_edges[-1], f" f_pp {float(fpp):.0f} Hz", fontsize=7, va="top", ha="left")
    ax.set_xlabel("excitation frequency V / λ (Hz)")
    ax.set_ylabel("train speed V (m/s)")
    cb = fig.colorbar(m, ax=ax)
    cb.set_label("growth (dB per 100,000 axles)")
    head = "Growth rate over frequency and speed (dotted: sleeper-passing harmonics n V / L)"
    ax.set_title(head + (f"\n{title}" if title else ""), fontsize=9)
    return fig


def placeholder_figure(text: str):
    """A figure that says in words why there is no map (for example a spectrum of one line).

    Parameters
    ----------
    text : str
        What to say.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = plt.subplots(figsize=(5.0, 1.6), layout="constrained")
    ax.axis("off")
    ax.text(0.5, 0.5, text, ha="center", va="center", fontsize=10)
    return fig
