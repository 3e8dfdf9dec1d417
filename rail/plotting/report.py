"""One function per report figure: take the figure's dataset, return a matplotlib Figure.

Nothing here computes physics, saves or shows; the Agg backend is used so that figures are
made the same way on a laptop, in CI and on a cluster node.  Line styles follow the report's
captions.
"""

from __future__ import annotations

import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.colors  # noqa: E402
import matplotlib.ticker  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

from . import text  # noqa: E402
from .axes import frequency_axis, mark_supports, per_mgt_axis, wavelength_axis  # noqa: E402

__all__ = ["fig02", "fig03", "fig04", "fig05", "fig06", "fig08", "fig09",
           "fig10", "fig11", "fig_wear", "fig_wear_spectrum", "fig22", "growth_profiles", "growth_spectra",
           "growth_final_profiles", "growth_3d", "sweep_map"]

_SIZE = (6.0, 4.0)


def _new():
    fig, ax = plt.subplots(figsize=_SIZE, layout="constrained")
    ax.grid(True, alpha=0.3)
    return fig, ax


def fig02(ds: xr.Dataset):
    """Fig. 2: real (solid) and imaginary (dashed) parts of the folded integrand of eq (14).

    Parameters
    ----------
    ds : xr.Dataset
        rail.studies.datasets.fig02's: the integrand over beta / beta_R [-].

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = _new()
    beta = ds["wavenumber"]
    ax.plot(beta, ds["integrand_real"], "-", color="k", label="real part")
    ax.plot(beta, ds["integrand_imag"], "--", color="tab:red", label="imaginary part")
    for key, name in (("beta_P_rad_per_m", r"$\beta_1$"), ("beta_S_rad_per_m", r"$\beta_2$")):
        ax.axvline(ds.attrs[key], color="0.5", lw=0.8, ls=":")
        ax.annotate(name, (ds.attrs[key], 0.97), xycoords=("data", "axes fraction"), ha="right", va="top")
    ax.set_xlabel(r"wavenumber $\beta$ (rad/m)")
    ax.set_ylabel(r"integrand of eq (14) (m$^2$/N)")
    ax.set_title(f"f = {ds.attrs['frequency_Hz']:g} Hz, r = {1e3 * ds.attrs['radius_m']:g} mm", fontsize=9)
    ax.legend(loc="lower right")
    return fig


def fig03(ds: xr.Dataset):
    """Fig. 3: beta G against wavenumber for beta >= 2 beta_R, with the limit of eq (15).

    Parameters
    ----------
    ds : xr.Dataset
        rail.studies.datasets.fig03's: beta G over beta / beta_R [-].

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = _new()
    ax.plot(ds["wavenumber"], ds["beta_G"], "-", color="k", label=r"$\beta G(\beta,\omega)$")
    ax.plot(ds["wavenumber"], ds["static_limit"], "--", color="tab:blue", label=r"$2(1-\nu^2)/E$, eq (15)")
    ax.set_xlabel(r"wavenumber $\beta$ (rad/m)")
    ax.set_ylabel(r"$\beta G$ (m$^2$/N)")
    ax.set_title(f"f = {ds.attrs['frequency_Hz']:g} Hz", fontsize=9)
    ax.legend()
    return fig


def fig04(ds: xr.Dataset):
    """Fig. 4: real part of eq (16) (solid) against Boussinesq's eq (17) (dashed).

    Parameters
    ----------
    ds : xr.Dataset
        rail.studies.datasets.fig04's: displacement [m] per unit load over radius [m].

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = _new()
    r_mm = 1e3 * ds["radius"]
    ax.plot(r_mm, ds["displacement_real"], "-", color="k", label="real part, eq (16)")
    ax.plot(r_mm, ds["displacement_boussinesq"], "--", color="tab:red", label="eq (17), Boussinesq")
    ax.set_yscale("log")
    ax.set_xlabel("distance from the loading point r (mm)")
    ax.set_ylabel("vertical displacement amplitude (m)")
    ax.set_title(f"unit load, f = {ds.attrs['frequency_Hz']:g} Hz", fontsize=9)
    ax.legend()
    return fig


def fig05(ds: xr.Dataset):
    """Fig. 5: power radiated into the half-space by a unit harmonic load.

    Parameters
    ----------
    ds : xr.Dataset
        rail.studies.datasets.fig05's: radiated power [W] over frequency [Hz].

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = _new()
    ax.plot(ds["frequency"], ds["radiated_power"], "-", color="k")
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("radiated power (W)")
    ax.set_title(f"vertical point load of amplitude {ds.attrs['load_N']:g} N", fontsize=9)
    return fig


def fig06(ds: xr.Dataset):
    """Fig. 6: loss factor of the contact spring against frequency.

    Parameters
    ----------
    ds : xr.Dataset
        rail.studies.datasets.fig06's: loss factor [-] over frequency [Hz].

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = _new()
    ax.plot(ds["frequency"], ds["loss_factor"], "-", color="k")
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel(r"contact-spring loss factor $\eta_H$ (-)")
    ax.set_title(f"$k_H$ = {ds.attrs['hertz_stiffness_N_per_m']:.3g} N/m", fontsize=9)
    return fig


def fig08(ds: xr.Dataset):
    """Fig. 8: position-history of the normal dynamic contact force (solid), roughness (dotted, not to scale).

    Parameters
    ----------
    ds : xr.Dataset
        rail.studies.datasets.fig08's: force [N] and roughness [m] over position [m].

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = _new()
    x = ds["position"]
    ax.plot(x, ds["dynamic_force"] / 1e3, "-", color="k", label="dynamic contact force")
    ax.set_xlabel("wheel position in the sleeper bay (m)")
    ax.set_ylabel("normal dynamic contact force (kN)")
    ax2 = ax.twinx()
    ax2.plot(x, ds["roughness"] * 1e6, ":", color="tab:blue", label="roughness")
    ax2.set_ylabel("roughness (µm)")
    lines = ax.get_lines() + ax2.get_lines()
    ax.legend(lines, [ln.get_label() for ln in lines], loc="upper right", fontsize=8)
    ax.set_title(
        f"V = {ds.attrs['speed_m_per_s']:g} m/s, {1e6 * ds.attrs['roughness_amplitude_m']:g} µm at "
        f"{ds.attrs['roughness_frequency_Hz']:g} Hz",
        fontsize=9,
    )
    return fig


def fig22(ds: xr.Dataset):
    """Fig. 22: normal contact force over a smooth rail at each speed (solid, dashed, ...).

    Parameters
    ----------
    ds : xr.Dataset
        rail.studies.datasets.fig22's: force [N] per speed over position [m].

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = _new()
    styles = ["-", "--", "-.", ":"]
    for i, name in enumerate(v for v in ds.data_vars if v.startswith("force_V")):
        V = name.removeprefix("force_V")
        ax.plot(ds["position"], ds[name] / 1e3, styles[i % 4], color="k", label=f"{V} m/s")
    ax.set_xlabel("wheel position in the sleeper bay (m)")
    ax.set_ylabel("normal contact force (kN)")
    ax.set_title("smooth rail", fontsize=9)
    ax.legend()
    return fig


def _case_title(ds):
    return f"V = {ds.attrs['speed_m_per_s']:g} m/s, {1e6 * ds.attrs['roughness_amplitude_m']:g} µm at {ds.attrs['roughness_frequency_Hz']:.0f} Hz"


def fig09(ds: xr.Dataset):
    """Fig. 9: position-history of the tangential contact force.

    Parameters
    ----------
    ds : xr.Dataset
        rail.studies.datasets.fig09's: tangential force [N] over position [m].

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = _new()
    ax.plot(ds["position"], ds["tangential_force"] / 1e3, "-", color="k")
    ax.set_xlabel("wheel position in the sleeper bay (m)")
    ax.set_ylabel("tangential contact force (kN)")
    ax.set_title(_case_title(ds), fontsize=9)
    return fig


_INSTANT_STYLES = ["-", "--", "-.", ":", (0, (5, 1, 1, 1, 1, 1))]


def _instants(ds, scale, ylabel):
    fig, ax = _new()
    for style, name in zip(_INSTANT_STYLES, ds.data_vars):
        label = ds[name].attrs["long_name"].split(" at ")[-1]
        ax.plot(1e3 * ds["patch"], ds[name] * scale, linestyle=style, color="k", label=label)
    ax.set_xlabel("position in the contact patch (mm, leading edge positive)")
    ax.set_ylabel(ylabel)
    ax.set_title(_case_title(ds), fontsize=9)
    ax.legend(fontsize=8)
    return fig


def fig10(ds: xr.Dataset):
    """Fig. 10: tangential contact stress at five instants of one excitation period.

    Parameters
    ----------
    ds : xr.Dataset
        rail.studies.datasets.fig10_11's traction [Pa] across the patch [m] at each instant [s].

    Returns
    -------
    matplotlib.figure.Figure
    """
    return _instants(ds, 1e-6, "tangential contact stress (MPa)")


def fig11(ds: xr.Dataset):
    """Fig. 11: slip velocity at five instants (meaningless outside the patch, plotted as 0).

    Parameters
    ----------
    ds : xr.Dataset
        rail.studies.datasets.fig10_11's slip velocity [m/s] across the patch [m] at each instant [s].

    Returns
    -------
    matplotlib.figure.Figure
    """
    return _instants(ds, 1.0, "slip velocity (m/s)")


def fig_wear(ds: xr.Dataset):
    """Figs 12, 14, 16, 18: wear (solid), initial roughness (dotted) and dynamic force (dashed), the
    last two scaled to the wear's range (not to scale, as in the report).

    Parameters
    ----------
    ds : xr.Dataset
        rail.studies.datasets.fig_wear's: wear depth [m], roughness [m] and dynamic force [N] over position [m].

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = _new()
    x = ds["position"]
    wear = ds["wear_depth"] * 1e9
    ax.plot(x, wear, "-", color="k", label="wear after one passage")
    span = float(wear.max() - wear.min()) / 2
    mid = float(wear.mean())
    for name, style, label in (("roughness", ":", "initial roughness (not to scale)"),
                               ("dynamic_normal_force", "--", "dynamic normal force (not to scale)")):
        v = ds[name]
        ax.plot(x, mid + span * v / float(np.abs(v).max()), style, color="0.4", label=label)
    ax.set_xlabel("position in the sleeper bay (m)")
    ax.set_ylabel("wear depth after one passage (nm)")
    ax.set_title(_case_title(ds), fontsize=9)
    ax.legend(fontsize=8, loc="lower right")
    return fig


def fig_wear_spectrum(ds: xr.Dataset):
    """Figs 13, 15, 17, 19: amplitude spectrum of the wear after one passage.

    Parameters
    ----------
    ds : xr.Dataset
        rail.studies.datasets.fig_wear_spectrum's: wear amplitude [m] over wavenumber [rad/m].

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = _new()
    ax.plot(ds["wavenumber"], ds["wear_spectrum"] * 1e12, "-o", color="k", ms=2.5)
    ax.set_xlabel("wavenumber (rad/m)")
    ax.set_ylabel("wear amplitude after one passage (pm)")
    ax.set_title(_case_title(ds), fontsize=9)
    return fig


_STYLES = ["-", "--", "-.", ":"]
_MARKERS = ["o", "s", "^", "v", "D", "P", "X", "*", "<", ">", "h", "p"]


def _speed_name(ds) -> str:
    """How a run's speed is named on an axis: "mean V" under a fleet, else "V"."""
    return "mean V" if "fleet_speeds" in ds.attrs else "V"


def _speed_text(ds) -> str:
    """The run's speed for a title: "V = 40 m/s" or "fleet at mean V = 40 m/s"."""
    return f"{'fleet at ' if 'fleet_speeds' in ds.attrs else ''}{_speed_name(ds)} = {ds.attrs['speed_m_per_s']:g} m/s"


def uniform_supports(ds):
    """The sleepers over a growth dataset's period, every L = period / N from 0 (0 above a sleeper) to the
    period's end, as (position [m], "") pairs for rail.plotting.axes.mark_supports.

    Parameters
    ----------
    ds : xr.Dataset
        A growth dataset (its period and bays).

    Returns
    -------
    list of tuple of (float, str)
        (position [m], "") per sleeper, the period's end included.
    """
    N = int(ds.attrs.get("bays", 1))
    x = ds["position"].values
    return [(float(x[0] + j * (x[-1] - x[0]) / N), "") for j in range(N + 1)]


def growth_profiles(ds: xr.Dataset):
    """Figs 20, 21: roughness profiles every saved passage count (10,000 apart), offset for clarity.

    Parameters
    ----------
    ds : xr.Dataset
        A growth dataset (rail.studies.datasets.growth): levels [dB re 1 µm], profiles [m] over position [m].

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = _new()
    names = list(ds.data_vars)
    vals = [ds[n].values * 1e6 for n in names]
    step = max(float(np.ptp(vals[-1])), 1e-12)
    for i, (n, v) in enumerate(zip(names, vals)):
        ax.plot(ds["position"], v + i * step * 0.6, "-", color="k", lw=0.8)
        ax.annotate(n.split("_")[1], (ds["position"].values[-1], v[-1] + i * step * 0.6), fontsize=6, ha="left", va="center")
    ax.set_xlabel("position in the sleeper bay (m)")
    ax.set_ylabel("roughness, profiles offset (µm)")
    ax.set_title(f"from a smooth rail, V = {ds.attrs.get('speed_m_per_s', 0):g} m/s; labels: passages", fontsize=9)
    return fig


def growth_spectra(ds: xr.Dataset):
    """Figs 23, 25, 26, 27: roughness level spectra of several runs (solid, dashed, dash-dot, dotted).

    Parameters
    ----------
    ds : xr.Dataset
        rail.studies.datasets.growth_figure's spectra: levels [dB re 1 µm] per run over wavenumber [rad/m].

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = _new()
    for style, name in zip(_STYLES, ds.data_vars):
        ax.plot(ds["wavenumber"], ds[name], linestyle=style, color="k", label=ds[name].attrs.get("label", name))
    ax.set_xlabel("wavenumber (rad/m)")
    ax.set_ylabel("roughness level (dB re 1 µm)")
    ax.legend(fontsize=8)
    return fig


def growth_final_profiles(ds: xr.Dataset):
    """Fig. 24: final roughness profiles of two runs (solid, dashed).

    Parameters
    ----------
    ds : xr.Dataset
        rail.studies.datasets.growth_figure's final profiles [m] per run over position [m].

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = _new()
    for style, name in zip(_STYLES, ds.data_vars):
        ax.plot(ds["position"], ds[name] * 1e6, linestyle=style, color="k", label=ds[name].attrs.get("label", name))
    ax.set_xlabel("position in the sleeper bay (m)")
    ax.set_ylabel("roughness (µm)")
    ax.legend(fontsize=8)
    return fig


def growth_3d(ds: xr.Dataset, axis: str = "wavenumber", name: str = ""):
    """The three-dimensional plot of section 5: level over wavenumber (or wavelength) and passages.

    Parameters
    ----------
    ds : xarray.Dataset
        A growth dataset (rail.studies.datasets.growth).
    axis : str
        "wavenumber" (rad/m, linear; the level as the report describes the plot, used for the default
        scenario's section-5 plot) or "wavelength" (mm, log scale, decreasing to the right as every
        study figure; a scenario's plot). Against wavelength the height is the change in level of each
        line since the initial state (level_change: since the first state with a level when the rail
        starts smooth), for the lines within 80 dB of the highest, so that the growth, not the
        spectrum's shape (a jump of tens of dB between neighbouring lines of an N-bay period), sets the
        scale; the slope along the passage axis is the growth rate either way.
    name : str
        The scenario, named in the title when given.

    Returns
    -------
    matplotlib.figure.Figure
    """
    if axis not in ("wavenumber", "wavelength"):
        raise ValueError(f"growth_3d: axis = {axis!r} is not allowed: it must be 'wavenumber' or 'wavelength'")
    fig = plt.figure(figsize=(7.0, 5.0), layout="constrained")
    ax = fig.add_subplot(projection="3d")
    level = ds["level"].values
    keep = np.any(np.isfinite(level), axis=1)  # a smooth rail (no level) is left out, not drawn at a floor
    k = ds["wavenumber"].values
    if axis == "wavenumber":
        xx, nn = np.meshgrid(k, ds["passage"].values[keep])
        ax.plot_surface(xx, nn / 1e3, level[keep], cmap="viridis", linewidth=0)
        ax.set_xlabel("wavenumber (rad/m)")
        ax.set_zlabel("level (dB re 1 µm)")
    else:
        change, ref = level_change(ds)
        top = float(np.nanmax(level)) if keep.any() else 0.0
        lines = np.isfinite(level[-1]) & (level[-1] >= top - 80)
        lam = 2 * np.pi / k[lines] * 1e3
        order = np.argsort(lam)[::-1]  # long wavelengths first: decreasing to the right
        x = np.log10(lam[order])  # mplot3d has no log axis: log10 of mm, ticks in mm
        rows = np.arange(len(level)) >= (ref if ref is not None else len(level))
        z = change[rows][:, lines][:, order]
        xx, nn = np.meshgrid(x, ds["passage"].values[rows])
        lim = max(float(np.nanmax(np.abs(z))) if np.isfinite(z).any() else 1.0, 1e-6)
        ax.plot_surface(xx, nn / 1e3, z, cmap="RdBu_r", vmin=-lim, vmax=lim, linewidth=0)
        ticks = [t for t in (1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000, 5000) if x.min() - 1e-9 <= np.log10(t) <= x.max() + 1e-9]
        ax.set_xticks(np.log10(ticks), [f"{t:g}" for t in ticks])
        ax.set_xlim(x.max(), x.min())
        ax.set_xlabel("wavelength (mm, log scale)")
        since = "initially" if ref in (0, None) else text.passages(ds["passage"].values[ref])
        ax.set_zlabel(f"change in level since {since} (dB)" if ref in (0, None) else f"change since {since} (dB)")
        ax.set_box_aspect(None, zoom=0.85)  # room for the tick labels in mm below the axis
    ax.set_ylabel("passages (thousands)")
    ax.set_title(f"roughness growth{f' of {name}' if name else ''}, V = {ds.attrs['speed_m_per_s']:g} m/s", fontsize=9)
    return fig


def growth_narrowband(ds: xr.Dataset, supports=None):
    """Growth over a roughness period of N bays: (left) the narrow-band level spectrum against
    wavelength (frequency at the run's speed on top) at the first, middle and last saved passage
    counts, with the lines of the one-bay comb L / k (every N-th wavenumber) marked; (right) the
    profiles over the N bays with the supports marked (``supports``: (position [m], description)
    pairs as rail.plotting.axes.mark_supports takes them; default every sleeper of uniform track).

    Parameters
    ----------
    ds : xr.Dataset
        A growth dataset (rail.studies.datasets.growth): levels [dB re 1 µm], profiles [m] over position [m].
    supports : sequence of (float, str), optional
        (position [m], description) per support (uniform_supports by default).

    Returns
    -------
    matplotlib.figure.Figure
    """
    N = int(ds.attrs.get("bays", 1))
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11.0, 4.2), layout="constrained")
    lam = 2 * np.pi / ds["wavenumber"].values * 1e3
    n = ds["passage"].values
    picks = sorted({0, len(n) // 2, len(n) - 1})
    comb = (ds["harmonic"].values % N) == 0
    colours = dict(zip(picks, _passage_colours(picks)))  # line style and colour both tell the saves apart
    for style, i in zip(_STYLES, picks):
        lev = ds["level"].values[i]
        a1.semilogx(lam, lev, linestyle=style, color=colours[i], lw=0.8, label=text.passages(n[i]))
        a1.plot(lam[comb], lev[comb], "o", mfc="none", color=colours[i], ms=3)
    a1.set_xlabel("wavelength (mm)")
    a1.set_ylabel("roughness level (dB re 1 µm)")
    a1.set_ylim(bottom=max(a1.get_ylim()[0], float(np.nanmax(ds["level"].values)) - 80))
    wavelength_axis(a1, lam)
    frequency_axis(a1, ds.attrs["speed_m_per_s"], _speed_name(ds))
    a1.set_title(f"narrow band over {N} bays (circles: the one-bay comb L/k)", fontsize=9)
    a1.legend(fontsize=8)
    for style, i in zip(_STYLES, picks):
        a2.plot(ds["position"], ds["profile"].values[i] * 1e6, linestyle=style, color=colours[i], lw=0.7, label=text.passages(n[i]))
    key = mark_supports(a2, supports if supports is not None else uniform_supports(ds))
    a2.set_xlabel(f"position over the {N}-bay period (m)\n{key}")
    a2.set_ylabel("roughness (µm)")
    a2.legend(fontsize=8)
    fig.suptitle(f"{_speed_text(ds)}, roughness period {N} bays", fontsize=9)
    text.validity_note(fig, ds.attrs)
    return fig


def band_spectra(ds: xr.Dataset):
    """One-third-octave bands of a growth run: (left) band levels at every saved passage count with a
    level (one colour and marker per save, up to _MAX_LEGEND saves evenly chosen) against the limit;
    (middle) the level growth rate per band in dB per 100,000 axle passages at the last save with its
    error, as in the band export, and in dB per MGT on the right when the traffic's axle load is known
    (the law the data prefer marked: o linear, ^ exponential); (right) the amplitude growth rate in µm
    per 100,000 axle passages, which ranks the bands where growth is linear (from a smooth rail every
    such band's dB rate is the same, about 8.7 dB at 100,000 passages). Wavelength decreases to the
    right with the band's frequency at the run's speed on top; one key beside the panels.

    Parameters
    ----------
    ds : xr.Dataset
        A band dataset (rail.studies.bands): band levels [dB re 1 µm], growth rates [dB per 100000 axle passages]
        and [µm per 100000 axle passages] per band centre [m].

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, (a1, a2, a3) = plt.subplots(1, 3, figsize=(15.0, 4.6), layout="constrained")
    lam = ds["nominal_wavelength"].values * 1e3
    n = ds["passage"].values
    res = ds["resolved"].values.astype(bool)
    has = np.nonzero(np.isfinite(ds["level"].values[:, res]).any(axis=1))[0] if res.any() else np.arange(len(n))
    has = has if has.size else np.arange(len(n))  # the saves with a level (not the smooth rail at the start)
    shown = has if has.size <= _MAX_LEGEND else has[np.unique(np.linspace(0, has.size - 1, _MAX_LEGEND).round().astype(int))]
    colours = _passage_colours(shown)
    for j, i in enumerate(shown):
        days = ds["days"].values[i]
        label = f"{text.count(n[i])}" + (f" ({text.count(days)} day{'' if days == 1 else 's'})" if np.isfinite(days) else "")
        a1.plot(lam[res], ds["level"].values[i][res], color=colours[j], marker=_MARKERS[j % len(_MARKERS)], ms=3.5, lw=0.9,
                label=label)
    if np.isfinite(ds["limit"].values).any():
        a1.plot(lam, ds["limit"].values, color="0.5", lw=2.5, label="limit")
    if "rate_floor_dB_re_1um" in ds.attrs:  # below it a band's rate is not ranked (rail.studies.bands)
        a1.axhline(float(ds.attrs["rate_floor_dB_re_1um"]), color="0.5", lw=0.8, ls=":", label="floor: rates below not ranked")
    wavelength_axis(a1, lam)
    a1.set_xlabel("band centre wavelength (mm)")
    a1.set_ylabel("roughness level (dB re 1 µm)")
    a1.set_title("band levels", fontsize=9)
    nb = int(ds.attrs['bays'])
    title = f"{_speed_text(ds)}, roughness period {nb} bay{'s' if nb > 1 else ''}"
    if ds.attrs.get("grinding_interval_text"):  # with how far it is extrapolated (rail.studies.bands.extrapolation_text)
        title += "\n" + "\n".join(textwrap.wrap(ds.attrs["grinding_interval_text"], 120))
    fig.suptitle(title, fontsize=9)
    law = ds["growth_law"].values
    # the rates of the ranked bands only: a band below the floor grows from nothing (rail.studies.bands)
    rank = res & (ds["ranked"].values.astype(bool) if "ranked" in ds else True)
    floor = ds.attrs.get("rate_floor_dB_re_1um")
    below = ([(f"{int((res & ~rank).sum())} bands below {floor:g} dB re 1 µm at the last save, or grown from below it, have no dB rate "
               "drawn (growth from nothing, not a feedback rate: not ranked)", "0.2")]
             if floor is not None and (res & ~rank).any() else [])
    if ds.attrs.get("grinding_interval_extrapolated"):  # the interval carries the fitted law far beyond the run (rail.studies.bands)
        below.append((f"grinding interval extrapolated x{text.count(float(ds.attrs['grinding_interval_extrapolation_factor']), 2)} "
                      f"beyond the computed {text.count(float(ds.attrs['computed_passages']))} axle passages", "firebrick"))
    _band_rate_panel(a2, lam, ds["growth_dB_per_1e5_axles"].values, ds["growth_dB_per_1e5_axles_error"].values, rank, law,
                     "level growth\n(dB per 100,000 axle passages)", "level growth rate at the last save")
    load = ds.attrs.get("axle_load_t", ds.attrs.get("mean_axle_load_t"))  # a fleet states its traffic-weighted mean
    if load is not None:
        per_mgt_axis(a2, float(load))
    # a band grown from nothing has no dB rate that means something, but its amplitude rate does (rail.studies.bands)
    grown = np.char.startswith(ds["rate_note"].values.astype(str), "grown from nothing") if "rate_note" in ds else False
    _band_rate_panel(a3, lam, ds["amplitude_growth_um_per_1e5_axles"].values, ds["amplitude_growth_um_per_1e5_axles_error"].values,
                     res & (rank | grown), law, "amplitude growth\n(µm rms per 100,000 axle passages)", "amplitude growth rate (ranks linear growth)")
    for a in (a1, a2, a3):
        frequency_axis(a, ds.attrs["speed_m_per_s"], _speed_name(ds))
    handles, labels = a1.get_legend_handles_labels()
    h2, l2 = a2.get_legend_handles_labels()
    fig.legend(handles + h2, labels + l2, title="axle passages", loc="outside right upper", fontsize=7, title_fontsize=8)
    text.validity_note(fig, ds.attrs, below)
    return fig


def _band_rate_panel(ax, lam, value, err, resolved, law, ylabel, title):
    """One rate panel of band_spectra: the resolved bands' rates with their errors, marked by the
    growth law that fits better, against the band's centre wavelength (mm, the levels' axis)."""
    ok = resolved & np.isfinite(value)
    ax.errorbar(lam[ok], value[ok], yerr=err[ok], fmt="none", ecolor="k", lw=0.6)
    for mark, name in (("o", "linear"), ("^", "exponential")):
        sel = ok & (law == name)
        ax.plot(lam[sel], value[sel], mark, color="k", mfc="none", label=f"{name} growth fits better")
    ax.axhline(0.0, color="0.6", lw=0.6)
    wavelength_axis(ax, lam)  # the same bands under each other
    ax.set_xlabel("band centre wavelength (mm)")
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=9)


def sweep_panels(ds: xr.Dataset, name: str, across: str, extra_width: float = 0.0):
    """The layout of a map over a sweep: ``across`` along x, the first swept key up, one panel per
    value of a second swept key (the first value of any further key). Returns (z, keys, second,
    panels, fig, axes): the variable with the further keys fixed, the swept keys, the second key (or
    None), the panel indices and the figure with its row of axes.

    Parameters
    ----------
    ds : xr.Dataset
        A dataset over a sweep's grid.
    name : str
        The variable mapped.
    across : str
        Its dimension along x.
    extra_width : float
        Room added to the figure's width [in].

    Returns
    -------
    tuple
        (z, keys, second, panels, fig, axes).
    """
    keys = [d for d in ds[name].dims if d != across]
    z = ds[name]
    for k in keys[2:]:
        z = z.isel({k: 0})
    second = keys[1] if len(keys) > 1 else None
    panels = list(range(ds.sizes[second])) if second else [None]
    fig, axes = plt.subplots(1, len(panels), figsize=(5.5 * len(panels) + extra_width, 4.2), layout="constrained", squeeze=False)
    return z, keys, second, panels, fig, axes


def sweep_band_map(ds: xr.Dataset):
    """Level growth rate per one-third-octave band over a sweep (dB per 100,000 axle passages, as the
    band export): band wavelength across, the first swept key up; one panel per value of a second
    swept key (the first value of any further key).

    Parameters
    ----------
    ds : xr.Dataset
        A sweep's band dataset: growth_dB_per_1e5_axles [dB per 100000 axle passages] per band over the grid.

    Returns
    -------
    matplotlib.figure.Figure
    """
    z, keys, second, panels, fig, axes = sweep_panels(ds, "growth_dB_per_1e5_axles", "band")
    lam = ds["nominal_wavelength"].values * 1e3
    lim = float(np.nanmax(np.abs(z.values))) if np.isfinite(z.values).any() else 1.0
    y = ds[keys[0]].values
    for ax, p in zip(axes[0], panels):
        zz = (z.isel({second: p}) if second else z).transpose(keys[0], "band").values
        m = ax.pcolormesh(np.arange(len(lam) + 1), np.arange(len(y) + 1), zz, cmap="RdBu_r", vmin=-lim, vmax=lim)
        ax.set_xticks(np.arange(len(lam))[::3] + 0.5, [f"{v:g}" for v in lam[::3]], fontsize=7)
        ax.set_yticks(np.arange(len(y)) + 0.5, [text.number(v) for v in y], fontsize=7)
        ax.set_xlabel("one-third-octave band, centre wavelength (mm)")
        ax.set_ylabel(f"{keys[0]} ({ds[keys[0]].attrs.get('units', '')})")
        if second:
            ax.set_title(f"{second} = {text.number(ds[second].values[p])} {ds[second].attrs.get('units', '')}", fontsize=9)
    fig.colorbar(m, ax=axes[0].tolist(), label="level growth at the last save (dB per 100,000 axle passages)")
    return fig


def sweep_map(ds: xr.Dataset):
    """Growth rate of the fastest-growing wavelength over a sweep's grid (map for two swept keys,
    lines for one or more than two).

    Parameters
    ----------
    ds : xr.Dataset
        rail.studies.datasets.sweep's: the fastest growth [µm per 100000 axle passages] on the grid.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = _new()
    dims = [d for d in ds["max_amplitude_growth_um_per_1e5_axles"].dims]
    z = ds["max_amplitude_growth_um_per_1e5_axles"]
    if len(dims) == 2:
        m = ax.pcolormesh(ds[dims[1]], ds[dims[0]], z.values, shading="nearest", cmap="viridis")
        fig.colorbar(m, ax=ax, label="fastest growth (µm rms per 100,000 axle passages)")
        for i, y in enumerate(ds[dims[0]].values):
            for j, x in enumerate(ds[dims[1]].values):
                ax.annotate(f"{1e3 * float(ds['fastest_wavelength'].values[i, j]):.0f} mm", (x, y), ha="center", va="center", fontsize=7, color="w")
        ax.set_xlabel(f"{dims[1]} ({ds[dims[1]].attrs['units']})")
        ax.set_ylabel(f"{dims[0]} ({ds[dims[0]].attrs['units']})")
    else:
        x = dims[0]
        other = z.stack(points=dims[1:]) if len(dims) > 1 else z.expand_dims(points=[0])
        for i in range(other.sizes["points"]):
            ax.plot(ds[x], other.isel(points=i), "-o", color="k", ms=3)
        ax.set_xlabel(f"{x} ({ds[x].attrs['units']})")
        ax.set_ylabel("fastest growth (µm rms per 100,000 axle passages)")
    ax.set_title("labels: fastest-growing wavelength", fontsize=9)
    return fig



_MAX_LEGEND = 16  # more saved passage counts than this get a colour bar of passages instead of a legend


def _passage_colours(n):
    """One viridis colour per saved passage count (dark: first, yellow: last)."""
    return [plt.cm.viridis(i / max(len(n) - 1, 1)) for i in range(len(n))]


def _passage_key(fig, n, colours, drawn):
    """Every saved passage count on the figure: a legend (up to _MAX_LEGEND counts; a count whose
    state has no level, a smooth rail, says so) or a discrete colour bar of passages."""
    if len(n) <= _MAX_LEGEND:
        handles = [plt.Line2D([], [], color=c, lw=1.5) for c in colours]
        labels = [text.count(p) + ("" if ok else " (smooth: no level)") for p, ok in zip(n, drawn)]
        fig.legend(handles, labels, title="passages", loc="outside right upper", fontsize=7, title_fontsize=8)
        return
    cmap = matplotlib.colors.ListedColormap(colours)
    norm = matplotlib.colors.BoundaryNorm(np.arange(len(n) + 1) - 0.5, len(n))
    bar = fig.colorbar(matplotlib.cm.ScalarMappable(norm=norm, cmap=cmap), ax=fig.axes, label="passages", location="right")
    ticks = np.unique(np.linspace(0, len(n) - 1, _MAX_LEGEND // 2).round().astype(int))
    bar.set_ticks(ticks, labels=[text.count(n[i]) for i in ticks])


def level_change(ds: xr.Dataset):
    """Change in level of every line since a reference state [dB]: the initial state where it has a
    level, else (a smooth rail) the first saved state with a level. Returns (change, ref): change of
    shape (passage, harmonic), NaN where a line has no level at the reference or at that state; ref
    the index of the reference state (None when no state has a level).

    Parameters
    ----------
    ds : xr.Dataset
        A growth dataset (levels [dB re 1 µm] per passage and harmonic).

    Returns
    -------
    tuple of (ndarray, int or None)
        (change [dB], ref).
    """
    level = ds["level"].values
    has = np.isfinite(level).any(axis=1)
    if not has.any():
        return np.full_like(level, np.nan), None
    ref = int(np.argmax(has))
    return level - level[ref], ref


def scenario_overview(ds: xr.Dataset, default: xr.Dataset | None = None, name: str = "", default_note: str = "", supports=None):
    """A growth run of any scenario on one page, every saved passage count in one colour per count
    (legend, or a colour bar beyond 16 counts):
    (a) the narrow-band level against wavelength, with the default scenario's final spectrum at the
    same speed (grey) or, when there is none, a note saying so (``default_note``, or a generic one) in
    the box of notes below the panels;
    (b) the change in level of every line since the initial state (since the first state with a level
    when the rail starts smooth; then linear amplitude growth gives 20 log10(n / n_ref) dB at every
    line, drawn as dotted lines), for the lines within 80 dB of the highest;
    (c) the profiles over the period; (d) the contact force of the first wheel at the start and the end;
    on (c) and (d) the supports (``supports``: (position [m], description) pairs as
    rail.plotting.axes.mark_supports takes them; default every sleeper of uniform track).
    Wavelength decreases to the right, with the frequency at the run's speed on top.

    Parameters
    ----------
    ds : xr.Dataset
        A growth dataset (rail.studies.datasets.growth): levels [dB re 1 µm], profiles [m] over position [m].
    default : xr.Dataset, optional
        The default scenario's run at the same speed [m/s].
    name : str
        The scenario, in the title.
    default_note : str
        Why there is no default run to compare with.
    supports : sequence of (float, str), optional
        (position [m], description) per support (uniform_supports by default).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, axes = plt.subplots(2, 2, figsize=(13.0, 8.5), layout="constrained")
    (a1, a4), (a2, a3) = axes
    N = int(ds.attrs.get("bays", 1))
    lam = 2 * np.pi / ds["wavenumber"].values * 1e3
    n = ds["passage"].values
    colours = _passage_colours(n)
    level = ds["level"].values
    drawn = np.isfinite(level).any(axis=1)
    notes = []
    for i in range(len(n)):
        if drawn[i]:
            a1.plot(lam, level[i], color=colours[i], lw=0.8)
    if default is not None:
        dl = 2 * np.pi / default["wavenumber"].values * 1e3
        a1.plot(dl, default["level"].values[-1], color="0.6", lw=1.6, zorder=0,
                label=f"default scenario, {text.passages(default['passage'].values[-1])}")
        a1.legend(fontsize=7, loc="lower right")
    elif name != "default":
        notes.append((default_note or "no default run to compare with", "firebrick"))
    a1.set_xlabel("wavelength (mm)")
    a1.set_ylabel("roughness level (dB re 1 µm)")
    wavelength_axis(a1, lam)
    top = float(np.nanmax(level)) if drawn.any() else 0.0
    a1.set_ylim(top - 80, top + 5)
    a1.set_title("(a) roughness level of each line", fontsize=9)

    change, ref = level_change(ds)
    shown = np.isfinite(level[-1]) & (level[-1] >= top - 80)
    if ref is not None:
        for i in range(ref + 1, len(n)):
            a4.plot(lam[shown], change[i][shown], color=colours[i], lw=0.8)
            if ref > 0:  # from a smooth rail: the change of a line growing linearly in amplitude
                a4.axhline(20 * np.log10(n[i] / n[ref]), color=colours[i], lw=0.8, ls=":")
        since = "the start" if ref == 0 else text.passages(n[ref])
        if ref > 0:
            notes.append((f"(b) the rail starts smooth, so the change is since {text.passages(n[ref])}; dotted: linear growth in "
                          f"amplitude, 20 log10(n / {text.count(n[ref])}) dB", "0.2"))
    else:
        since = "the start (no state has a level)"
    a4.axhline(0.0, color="0.3", lw=0.6)
    a4.set_xlabel("wavelength (mm)")
    wavelength_axis(a4, lam)
    a4.set_ylabel("change in level (dB)")
    a4.set_title(f"(b) change in level since {since}", fontsize=9)
    for a in (a1, a4):
        frequency_axis(a, ds.attrs["speed_m_per_s"], _speed_name(ds))

    marks = supports if supports is not None else uniform_supports(ds)
    for i in range(len(n)):
        a2.plot(ds["position"], ds["profile"].values[i] * 1e6, color=colours[i], lw=0.7)
    a2.set_ylabel("roughness (µm)")
    a2.set_title("(c) roughness profile", fontsize=9)
    if "force" in ds:
        for style, i in zip(_STYLES, sorted({0, len(n) - 1})):
            a3.plot(ds["position"], ds["force"].values[i, 0] / 1e3, linestyle=style, color=colours[i], lw=0.9,
                    label=text.after(n[i]).capitalize())
        a3.set_ylabel("contact force, first wheel (kN)")
        a3.legend(fontsize=7)
    a3.set_title("(d) contact force at the start and the end", fontsize=9)
    for a in (a2, a3):
        a.set_xlabel(f"position over the {N}-bay period (m)\n{mark_supports(a, marks)}")
    _passage_key(fig, n, colours, drawn)
    contact = ds.attrs.get("normal_contact")
    title = (f"{name + ': ' if name else ''}{_speed_text(ds)}, roughness period {N} bay{'s' if N > 1 else ''}"
             + (f", normal contact {contact}" if contact else ""))
    if ds.attrs.get("stopped"):  # the run left the model: say where, on the page
        reason = ds.attrs["stopped"].split(": ", 2)
        fig.suptitle(f"{title}\nSTOPPED {text.after(n[-1])} ({reason[1] if len(reason) > 1 else 'see the file'}); "
                     "the states up to there are shown", fontsize=10, color="firebrick")
    else:
        fig.suptitle(title, fontsize=10)
    text.validity_note(fig, ds.attrs, notes)
    return fig
