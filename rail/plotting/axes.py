"""Axes shared by the study figures (issue 45, item 4): one wavelength axis, the frequency and per-MGT
axes of a quantity that has them, the supports along the rail, and notes kept off the curves.

Conventions
-----------
- **Wavelength decreases to the right** (long wavelengths on the left), as EN 15610 / ISO 3095
  roughness spectra are drawn and as the report's wavenumber and frequency axes run: every study
  figure against wavelength agrees, so a frequency axis f = V / lambda on top increases to the right.
- A secondary frequency axis is f = V / lambda at the figure's speed (Hz); a secondary per-MGT axis is
  a rate per 100,000 axle passages times 1e6 / axle load [t] / 1e5 (rail.traffic.Traffic.per_mgt).
- Supports along the rail: every sleeper a dotted grey line (gid ``"support"``); a support that differs
  from the nominal one (a voided sleeper, a soft pad) a red dashed line (gid ``"support-differs"``),
  described in the axis label.
- Notes (no default run, where a result leaves the model) sit in one framed box below the axes
  (a figure legend placed outside them, gid ``"notes"``), so that constrained layout keeps them off
  the curves and off every label.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.patches  # noqa: E402
import matplotlib.ticker  # noqa: E402
import numpy as np  # noqa: E402

__all__ = ["wavelength_axis", "frequency_axis", "per_mgt_axis", "mark_supports", "footer", "AXLES_PER_RATE"]

AXLES_PER_RATE = 100000  # rates are per this many axle passages (rail.traffic.AXLES_PER_RATE; plotting imports no physics)
_TICKS_MM = (1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000, 5000, 10000)


def wavelength_axis(ax, lam_mm, pad: float = 1.05, ticks=_TICKS_MM) -> None:
    """A log wavelength axis in mm over the wavelengths (or cell edges) ``lam_mm``, decreasing to the
    right, ticked at round values written plainly (20, 50, 100, not 2×10¹).

    Parameters
    ----------
    ax : matplotlib Axes
    lam_mm : array-like
        Wavelengths [mm] the axis spans (> 0).
    pad : float
        Factor of room beyond the extreme wavelengths [-] (1: none, for cell edges).
    ticks : sequence of float
        Candidate ticks [mm]; those inside the span are used.

    Returns
    -------
    None
    """
    lo, hi = float(np.min(lam_mm)) / pad, float(np.max(lam_mm)) * pad
    ax.set_xscale("log")
    ax.set_xlim(hi, lo)
    ax.set_xticks(_ticks_within(lo, hi, ticks))
    ax.xaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
    ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())


def _ticks_within(lo: float, hi: float, ticks) -> list:
    """At least two round ticks in [lo, hi] (mm): the candidates ``ticks`` inside it; where fewer than two
    are (a few lines near pinned-pinned span 33-38 mm, between the round 30 and 50: issue 57, item 8), the
    values 1, 1.2, 1.5, ..., 8 of every decade inside it, thinned to at most six; where still fewer, the
    span's ends to two significant figures."""
    inside = [t for t in ticks if lo <= t <= hi]
    if len(inside) >= 2:
        return inside
    decades = range(int(np.floor(np.log10(lo))), int(np.ceil(np.log10(hi))) + 1)
    for mantissas in ((1, 1.2, 1.5, 2, 2.5, 3, 3.5, 4, 4.5, 5, 6, 7, 8, 9), np.arange(10, 100) / 10, np.arange(100, 1000) / 100):
        inside = [float(f"{m * 10.0 ** e:.12g}") for e in decades for m in mantissas if lo <= m * 10.0 ** e <= hi]
        if len(inside) >= 2:
            return inside[:: int(np.ceil(len(inside) / 6))]
    return [lo, hi]


def frequency_axis(ax, speed: float, what: str = "V"):
    """A secondary axis on top of a wavelength axis in mm: the frequency f = V / lambda [Hz] at the
    speed ``speed`` [m/s]; ``what`` names the speed in the label ("V", "mean V"). Returns the axis.

    Parameters
    ----------
    ax : matplotlib Axes
        With a wavelength axis in mm (wavelength_axis).
    speed : float
        Train speed V [m/s].
    what : str
        How the label names the speed.

    Returns
    -------
    matplotlib axis
        The secondary axis [Hz].
    """
    V = float(speed)

    def f_of_lam(lam_mm):
        with np.errstate(divide="ignore", invalid="ignore"):
            return 1e3 * V / np.asarray(lam_mm, dtype=float)

    sec = ax.secondary_xaxis("top", functions=(f_of_lam, f_of_lam))  # the map is its own inverse
    sec.set_xlabel(f"frequency at {what} = {V:g} m/s (Hz)", fontsize=8)
    f_lo, f_hi = sorted(float(f_of_lam(x)) for x in ax.get_xlim())
    decades = [10.0 ** e for e in range(-3, 8) if f_lo <= 10.0 ** e <= f_hi]
    if len(decades) < 2 and f_lo > 0 and np.isfinite(f_hi):  # a narrow span: round ticks inside it (issue 57, item 8)
        sec.set_xticks(_ticks_within(f_lo, f_hi, [m * 10.0 ** e for e in range(0, 6) for m in (1, 2, 5)]))
    sec.xaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
    sec.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    sec.tick_params(labelsize=7)
    return sec


def per_mgt_axis(ax, axle_load_t: float):
    """A secondary axis on the right of a rate axis in dB per 100,000 axle passages: the same rate in
    dB per million gross tonnes, rate x 1e6 / axle load / 1e5, at the axle load ``axle_load_t`` [t].
    Returns the axis.

    Parameters
    ----------
    ax : matplotlib Axes
        With a rate axis in dB per 100,000 axle passages.
    axle_load_t : float
        Axle load [t].

    Returns
    -------
    matplotlib axis
        The secondary axis [dB per MGT].
    """
    per = 1e6 / float(axle_load_t) / AXLES_PER_RATE
    sec = ax.secondary_yaxis("right", functions=(lambda r: np.asarray(r) * per, lambda m: np.asarray(m) / per))
    sec.set_ylabel(f"dB per MGT (axle load {float(axle_load_t):.3g} t)", fontsize=8)
    sec.tick_params(labelsize=7)
    return sec


def mark_supports(ax, supports) -> str:
    """Every support along the rail on an axis of position [m]: a dotted grey line per sleeper, a red
    dashed line per support that differs from the nominal one. Returns the key for the axis label
    ("dotted: sleepers; red dashed: ballast ×0.001 at 0.6 m"), which the caller writes under the axis
    (a label, not a note on the axes, so that it covers no curve and no title).

    Parameters
    ----------
    ax : matplotlib Axes
    supports : sequence of (float, str)
        (position [m], description) per support over the plotted length, the period's end included;
        an empty description for a nominal support ("ballast ×0.001" for a voided sleeper, say).

    Returns
    -------
    str
        The key for the axis label ("" without supports).
    """
    differs = {}
    for x, label in supports:
        if label:
            ax.axvline(x, color="firebrick", ls="--", lw=1.0, zorder=0, gid="support-differs")
            differs.setdefault(label, []).append(x)
        else:
            ax.axvline(x, color="0.55", ls=":", lw=0.8, zorder=0, gid="support")
    key = "dotted: sleepers"
    for label, xs in differs.items():
        key += f"; red dashed: {label} at {', '.join(f'{x:g}' for x in xs)} m"
    return key


def footer(fig, notes) -> None:
    """Notes in one framed box below every axes (a figure legend outside them, gid "notes"), one line
    each in its colour; nothing when ``notes`` is empty.

    Parameters
    ----------
    fig : matplotlib Figure (constrained layout)
    notes : sequence of (str, colour)

    Returns
    -------
    None
    """
    notes = [(t, c) for t, c in notes if t]
    if not notes:
        return
    blank = [matplotlib.patches.Rectangle((0, 0), 0, 0, visible=False) for _ in notes]
    leg = fig.legend(blank, [t for t, _ in notes], loc="outside lower center", fontsize=7, handlelength=0, handletextpad=0,
                     labelcolor=[c for _, c in notes], edgecolor="0.6", borderaxespad=0.2)
    leg.set_gid("notes")
