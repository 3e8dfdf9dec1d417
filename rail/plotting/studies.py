"""Figures of the numerical studies: closure sensitivity and convergence (named targets, README).

One function per figure: it takes a dataset and returns a matplotlib Figure.
"""

from __future__ import annotations

import matplotlib
import matplotlib.colors
import matplotlib.ticker

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

from . import text  # noqa: E402
from .axes import frequency_axis, per_mgt_axis, wavelength_axis  # noqa: E402
from .report import sweep_panels  # noqa: E402

__all__ = ["closure_spectra", "closure_wear_spectra", "convergence_figure"]

GROWTH_LABEL = "growth (dB per 100,000 axle passages)"  # every growth-rate figure: the export convention (docs/exports.md)


def _closure_lines(ds):
    """Line style and grey level per closure value (dark: small s, light: large s); the default
    s = 1 is solid black."""
    S = ds["closure_scale"].values
    styles = ["--", "-.", ":", (0, (5, 1, 1, 1, 1, 1)), (0, (1, 3)), (0, (8, 2))]
    out = []
    for i, s in enumerate(S):
        if np.isclose(s, 1.0):
            out.append(("-", "k", 1.4))
        else:
            out.append((styles[i % len(styles)], plt.cm.viridis(i / max(len(S) - 1, 1)), 1.0))
    return out


def closure_spectra(ds: xr.Dataset):
    """Closure study: roughness level spectra after the last passage per closure value (as Fig. 23),
    one panel per speed. Closure values that are not well-posed are marked in the legend.

    Parameters
    ----------
    ds : xr.Dataset
        rail.studies.closure.closure_study's: levels [dB re 1 µm] per closure value, speed [m/s] and harmonic.

    Returns
    -------
    matplotlib.figure.Figure
    """
    V = ds["speed"].values
    fig, axes = plt.subplots(1, len(V), figsize=(6.0 * len(V), 4.2), layout="constrained", squeeze=False)
    sel = ds["wavenumber"].values <= ds.attrs["spectrum_max_wavenumber_rad_per_m"]
    for ax, v in zip(axes[0], V):
        for (style, color, lw), s, ok in zip(_closure_lines(ds), ds["closure_scale"].values, ds["well_posed"].values):
            y = ds["level"].sel(speed=v).sel(closure_scale=s).isel(passage=-1).values[sel]
            ax.plot(ds["wavenumber"].values[sel], y, linestyle=style, color=color, lw=lw, label=f"s = {s:g}" + ("" if ok else " (ill-posed)"))
        ax.set_xlabel("wavenumber (rad/m)")
        ax.set_ylabel("roughness level (dB re 1 µm)")
        ax.set_title(f"V = {v:g} m/s, {text.passages(ds['passage'].values[-1])}, single wheel", fontsize=9)
    axes[0][0].legend(fontsize=7, title="closure scale", title_fontsize=7)
    return fig


def closure_wear_spectra(ds: xr.Dataset):
    """Closure study: wear spectra of one passage over a harmonic roughness (Figs 13, 15, 17, 19)
    per closure value, one panel per excitation frequency.

    Parameters
    ----------
    ds : xr.Dataset
        rail.studies.closure.closure_study's: wear spectra [m] per closure value and frequency [Hz].

    Returns
    -------
    matplotlib.figure.Figure
    """
    F = ds["frequency"].values
    fig, axes = plt.subplots(2, (len(F) + 1) // 2, figsize=(11.0, 7.0), layout="constrained", squeeze=False)
    sel = ds["wavenumber"].values <= ds.attrs["spectrum_max_wavenumber_rad_per_m"]
    for ax, f in zip(axes.ravel(), F):
        for (style, color, lw), s in zip(_closure_lines(ds), ds["closure_scale"].values):
            y = ds["wear_spectrum"].sel(frequency=f, closure_scale=s).values[sel] * 1e12
            ax.plot(ds["wavenumber"].values[sel], y, linestyle=style, color=color, lw=lw, marker="o", ms=2, label=f"s = {s:g}")
        ax.set_xlabel("wavenumber (rad/m)")
        ax.set_ylabel("wear amplitude after one passage (pm)")
        ax.set_title(f"{f:.0f} Hz roughness, V = {ds.attrs['wear_speed_m_per_s']:g} m/s", fontsize=9)
    axes.ravel()[0].legend(fontsize=7, title="closure scale", title_fontsize=7)
    return fig


_QUANTITY_TEXT = {"force": "normal force along the bay (Fig. 22)", "wear": "wear spectrum of one passage (Figs 13, 19)",
                  "growth": "roughness after 100,000 passages (Fig. 23)"}


def convergence_figure(ds: xr.Dataset):
    """Error against CPU time, log-log, one panel per quantity and a line per setting; the default
    value is a filled marker, the others open; each point is labelled with its value.

    Parameters
    ----------
    ds : xr.Dataset
        rail.studies.convergence.convergence_dataset's: error [-] and CPU time [s] per point.

    Returns
    -------
    matplotlib.figure.Figure
    """
    quantities = list(dict.fromkeys(ds["quantity"].values))
    fig, axes = plt.subplots(1, len(quantities), figsize=(5.0 * len(quantities), 4.2), layout="constrained", squeeze=False)
    markers = ["o", "s", "^", "D", "v"]
    for ax, q in zip(axes[0], quantities):
        names = list(dict.fromkeys(ds["setting"].values[ds["quantity"].values == q]))
        for m, name in zip(markers, names):
            sel = ds["setting"].values == name
            t, e = ds["cpu_time"].values[sel], np.maximum(ds["error"].values[sel], 1e-12)
            order = np.argsort(t)
            ax.loglog(t[order], e[order], "-", color="k", lw=0.8, marker=m, mfc="none", label=name)
            d = ds["is_default"].values[sel].astype(bool)
            ax.loglog(t[d], e[d], m, color="k")
            for ti, ei, v in zip(t, e, ds["value"].values[sel]):
                ax.annotate(f"{v:g}", (ti, ei), fontsize=6, xytext=(3, 3), textcoords="offset points")
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.yaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.set_xlabel("CPU time (s, one core)")
        ax.set_ylabel("relative error")
        ax.set_title(_QUANTITY_TEXT.get(q, q), fontsize=9)
        ax.legend(fontsize=7, title="setting (filled: default)", title_fontsize=7)
    return fig


def _wavelength_edges(lam):
    """Cell edges of lines at the wavelengths lam (decreasing), at the geometric means."""
    return np.r_[lam[0] * np.sqrt(lam[0] / lam[1]), np.sqrt(lam[1:] * lam[:-1]), lam[-1] * np.sqrt(lam[-1] / lam[-2])]


def _wavelength_axis(ax, lam_edges):
    """A log wavelength axis (mm) spanning the lines' cells, decreasing to the right (rail.plotting.axes),
    with round ticks inside it only."""
    wavelength_axis(ax, lam_edges, pad=1.0, ticks=(5, 10, 20, 30, 50, 100, 200, 300, 600, 1000, 2000))


def _rate_axes(ax, ds, speed=None, what="V"):
    """The secondary axes of a growth-rate panel against wavelength: the frequency at ``speed`` on top
    (none when the panel holds several speeds) and dB per MGT on the right when the dataset states its
    axle load (attribute axle_load_t, or a fleet's mean_axle_load_t)."""
    if speed is not None:
        frequency_axis(ax, speed, what)
    load = ds.attrs.get("axle_load_t", ds.attrs.get("mean_axle_load_t"))  # a fleet states its traffic-weighted mean
    if load is not None:
        per_mgt_axis(ax, float(load))


def _growth_norm(values):
    """Diverging colour scale about 0 (red grows, blue decays) and its colour-bar ticks."""
    lo, hi = float(np.nanmin(values)), float(np.nanmax(values))
    norm = matplotlib.colors.TwoSlopeNorm(vmin=min(lo, -1e-6), vcenter=0.0, vmax=max(hi, 1e-6))
    return norm, np.r_[np.linspace(norm.vmin, 0, 4)[:-1], np.linspace(0, norm.vmax, 4)]


def rate_spectrum_figure(ds: xr.Dataset):
    """Growth-rate spectrum: the level change per 100,000 axle passages (growth_dB_per_1e5_axles, the
    export convention) over wavelength, one line
    per speed (top), and the speed x wavelength map (bottom); comb lines L/k marked. With one speed
    only the line (a map of one speed would smear it over an invented speed range).

    Parameters
    ----------
    ds : xr.Dataset
        A spectrum dataset over speed [m/s] and wavelength [m] (growth_dB_per_1e5_axles [dB per 100000 axle
        passages]).

    Returns
    -------
    matplotlib.figure.Figure
    """
    one = ds.sizes["speed"] == 1
    if one:
        fig, ax = plt.subplots(figsize=(7.5, 4.2), layout="constrained")
    else:
        fig, (ax, bx) = plt.subplots(2, 1, figsize=(7.5, 7.5), layout="constrained", sharex=True)
    lam = ds["wavelength"].values * 1e3
    g = ds["growth_dB_per_1e5_axles"]
    for v in ds["speed"].values:  # a marker on every line: a spectrum of a few lines is read at its points
        ax.plot(lam, g.sel(speed=v).values, lw=1.2, color="k" if one else None, marker="o", ms=3.5, label=f"{v:g} m/s")
    ax.axhline(0, color="0.3", lw=0.7)
    comb = ds["locked"].values == 1
    for x in lam[comb]:
        ax.axvline(x, color="0.85", lw=0.6, zorder=0)
    ax.set_xscale("log")
    ax.set_ylabel(GROWTH_LABEL)
    if not one:
        ax.legend(fontsize=8, ncol=2, loc="best", framealpha=0.9)
    wheels = int(ds.attrs['wheels'])
    ax.set_title(f"linearised growth-rate spectrum{f' at {float(ds.speed.values[0]):g} m/s' if one else ''}, "
                 f"{wheels} wheel{'' if wheels == 1 else 's'}\n{_track_text(ds.attrs)}", fontsize=9)
    method = [(f"probe amplitude {ds.attrs['eps_m'] * 1e9:g} nm; grey lines: the one-bay comb L/k", "0.2"), (_mechanisms_text(ds.attrs), "0.2")]
    lam_edges = _wavelength_edges(lam)
    if one:
        ax.set_xlabel("wavelength (mm)")
        _wavelength_axis(ax, lam_edges)
        _rate_axes(ax, ds, float(ds.speed.values[0]))
        method += _mark_contact(ds, (ax,), lam_edges)
        text.validity_note(fig, ds.attrs, method)
        return fig
    norm, ticks = _growth_norm(g.values)
    V = ds["speed"].values
    edges = np.r_[V[0] - 0.5 * (V[1] - V[0]), 0.5 * (V[1:] + V[:-1]), V[-1] + 0.5 * (V[-1] - V[-2])]
    m = bx.pcolormesh(lam_edges, edges, g.values, cmap="RdBu_r", norm=norm)
    fig.colorbar(m, ax=bx, ticks=ticks, format="%.2g", label=GROWTH_LABEL)
    bx.set_xlabel("wavelength (mm)")
    bx.set_ylabel("speed (m/s)")
    for a in (ax, bx):
        _wavelength_axis(a, lam_edges)
    _rate_axes(ax, ds)
    method += _mark_contact(ds, (ax, bx), lam_edges)
    text.validity_note(fig, ds.attrs, method)
    return fig


def _track_text(attrs) -> str:
    """The track of a spectrum for its title: "track: pad 3.5×10⁸ N/m, sleeper spacing 0.6 m"."""
    pad = attrs.get("pad_stiffness_N_per_m")
    parts = ([f"pad {text.number(float(pad))} N/m"] if pad is not None else []) + (
        [f"sleeper spacing {float(attrs['sleeper_spacing_m']):g} m"] if "sleeper_spacing_m" in attrs else [])
    return "track: " + (", ".join(parts) if parts else "not stated")


def _mechanisms_text(attrs) -> str:
    """The model's mechanisms as the result file states them, for a figure's note: normal contact, wear
    path, wheelset, rail flexibility, friction law ('not stated' where a file predates them)."""
    import textwrap

    def value(key):
        return str(attrs.get(key, "not stated"))

    line = (f"model: normal contact {value('normal_contact')}; wear path {value('wear_path')}; wheelset {value('wheelset_model')}; "
            f"rail flexibility {value('rail_flexibility')}; friction {value('friction_law')}")
    return "\n".join(textwrap.wrap(line, 110))


def _mark_contact(ds: xr.Dataset, axes, lam_edges):
    """The static contact length 2a (dashed) and, for the report's normal contact, the wavelengths
    below its range of validity (hatched), on spectrum panels with a wavelength axis in mm. Returns the
    notes for the figure's footer (the hatch explained where no label fits on the axes)."""
    notes = []
    if "contact_length_m" not in ds.attrs:
        return notes
    two_a = 1e3 * float(ds.attrs["contact_length_m"])
    lo, hi = float(lam_edges.min()), float(lam_edges.max())
    for i, a in enumerate(axes):
        if lo <= two_a <= hi:  # a label outside the axes would collapse the layout (a few lines far from 2a)
            a.axvline(two_a, color="k", ls="--", lw=0.9)
            if i == 0:
                a.text(two_a, 0.02, f" contact length 2a = {two_a:.1f} mm", transform=a.get_xaxis_transform(), fontsize=7,
                       rotation=90, va="bottom", ha="left")
        if "report_model_valid_above_m" in ds.attrs:
            limit = 1e3 * float(ds.attrs["report_model_valid_above_m"])
            if limit > lo:
                a.axvspan(lo, min(limit, hi), facecolor="none", edgecolor="0.6", hatch="//", lw=0, zorder=0)
                if i == 0 and limit <= hi:
                    a.text(limit, 0.98, "report's normal contact outside its validity (< 10 x 2a) ", transform=a.get_xaxis_transform(),
                           fontsize=7, ha="right", va="top", color="0.3")
                elif i == 0:  # every line lies below the limit: said in the notes (a label would cover a line)
                    notes.append((f"hatched: the report's normal contact outside its validity at every line (valid above 10 x 2a = "
                                  f"{limit:.0f} mm)", "0.3"))
    return notes


def rate_spectrum_sweep_figure(ds: xr.Dataset):
    """Growth-rate spectrum over a sweep (growth_dB_per_1e5_axles): wavelength across, the first swept
    key up, one panel per value of a second swept key (the first value of any further key).

    Parameters
    ----------
    ds : xr.Dataset
        The spectra of a sweep's points on its grid (growth_dB_per_1e5_axles [dB per 100000 axle passages] over
        wavelength [m]).

    Returns
    -------
    matplotlib.figure.Figure
    """
    z, keys, second, panels, fig, axes = sweep_panels(ds, "growth_dB_per_1e5_axles", "wavelength", extra_width=1.0)
    lam_edges = _wavelength_edges(ds["wavelength"].values * 1e3)
    norm, ticks = _growth_norm(z.values)
    y = ds[keys[0]].values
    for ax, p in zip(axes[0], panels):
        zz = (z.isel({second: p}) if second else z).transpose(keys[0], "wavelength").values
        m = ax.pcolormesh(lam_edges, np.arange(len(y) + 1), zz, cmap="RdBu_r", norm=norm)
        _wavelength_axis(ax, lam_edges)
        ax.set_yticks(np.arange(len(y)) + 0.5, [text.number(v) for v in y], fontsize=7)
        ax.set_xlabel("wavelength (mm)")
        ax.set_ylabel(f"{keys[0]} ({ds[keys[0]].attrs.get('units', '')})")
        if second:
            ax.set_title(f"{second} = {text.number(ds[second].values[p])} {ds[second].attrs.get('units', '')}", fontsize=9)
    fig.colorbar(m, ax=axes[0].tolist(), ticks=ticks, format="%.2g", label=GROWTH_LABEL)
    return fig


def fleet_spectrum_figure(ds: xr.Dataset, title: str = ""):
    """Growth-rate spectrum under a fleet (rail.studies.fleet.fleet_spectrum_dataset): the level change
    per 100,000 axle passages of the traffic over wavelength (thick), each class's contribution (thin;
    they sum to the total at a free line), the pinned-pinned wavelength at the mean speed (dotted) and
    the comb L/k (grey).

    Parameters
    ----------
    ds : xr.Dataset
        rail.studies.fleet.fleet_spectrum_dataset's: rates [dB per 100000 axle passages] over wavelength [m], total
        and per class.
    title : str
        The figure's title ("": the dataset's own).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = plt.subplots(figsize=(7.5, 4.5), layout="constrained")
    lam = ds["wavelength"].values * 1e3
    per_axle = 1.0 / float(ds.attrs["axles_per_train"])
    to_dB = float(ds["growth_dB_per_1e5_trains"].values[0] / ds["growth_rate"].values[0]) if ds["growth_rate"].values[0] else None
    for x in lam[ds["locked"].values == 1]:
        ax.axvline(x, color="0.88", lw=0.6, zorder=0)
    if to_dB is not None:
        for c in ds["class"].values:
            ax.plot(lam, ds["class_contribution"].sel({"class": c}).values * to_dB * per_axle, lw=0.7,
                    label=str(ds["class_label"].values[c]) + f" (w = {float(ds['class_weight'].values[c]):.3g})")
    ax.plot(lam, ds["growth_dB_per_1e5_axles"].values, color="k", lw=2, label="fleet")
    ax.axhline(0, color="0.3", lw=0.7)
    if "pinned_pinned_wavelength_m" in ds.attrs:
        x = 1e3 * float(ds.attrs["pinned_pinned_wavelength_m"])
        ax.axvline(x, color="k", ls=":", lw=1)
        ax.text(x, 0.98, f" pinned-pinned {x:.1f} mm", transform=ax.get_xaxis_transform(), fontsize=7, va="top")
    _wavelength_axis(ax, _wavelength_edges(lam))
    _rate_axes(ax, ds, ds.attrs.get("mean_speed_m_per_s"), "mean V")
    ax.set_xlabel("wavelength (mm)")
    ax.set_ylabel(GROWTH_LABEL)
    ax.set_title(title or f"growth-rate spectrum under the fleet ({ds.attrs.get('scenario', '')})", fontsize=9)
    if ds.sizes["class"] <= 12:
        ax.legend(fontsize=6, ncol=2, loc="best", framealpha=0.9)
    return fig


def traffic_study_figure(ds: xr.Dataset):
    """The traffic study: growth-rate spectrum per case (one line per speed spread, a panel per drive),
    dB per 100,000 axle passages over wavelength, the pinned-pinned wavelength marked.

    Parameters
    ----------
    ds : xr.Dataset
        The traffic study's dataset: rates [dB per 100000 axle passages] per drive, speed spread [-] and
        wavelength [m].

    Returns
    -------
    matplotlib.figure.Figure
    """
    drives = list(ds["drive"].values)
    fig, axes = plt.subplots(1, len(drives), figsize=(5.2 * len(drives), 4.5), layout="constrained", sharey=True, squeeze=False)
    lam = ds["wavelength"].values * 1e3
    pp = 1e3 * float(ds.attrs["pinned_pinned_wavelength_m"])
    for ax, d in zip(axes[0], drives):
        for s in ds["spread"].values:
            ax.plot(lam, ds["growth_dB_per_1e5_axles"].sel(drive=d, spread=s).values, lw=1.2, label=f"speed spread ±{100 * s:g} %")
        ax.axhline(0, color="0.3", lw=0.7)
        ax.axvline(pp, color="k", ls=":", lw=1)
        ax.text(pp, 0.98, f" pinned-pinned {pp:.1f} mm", transform=ax.get_xaxis_transform(), fontsize=7, va="top")
        _wavelength_axis(ax, _wavelength_edges(lam))
        frequency_axis(ax, float(ds.attrs["mean_speed_m_per_s"]), "mean V")
        ax.set_xlabel("wavelength (mm)")
        ax.set_title(f"locomotive {d}", fontsize=9)
    axes[0][0].set_ylabel(GROWTH_LABEL)
    axes[0][0].legend(fontsize=7, loc="best", framealpha=0.9)
    return fig
