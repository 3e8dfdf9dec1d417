"""The noise over traffic of a growth run (rail.studies.noise): a dataset in, a Figure out."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import textwrap  # noqa: E402

from . import text  # noqa: E402

__all__ = ["noise_over_traffic"]

_MAX_SPECTRA = 8  # saves drawn in the spectrum panel, evenly chosen


def noise_over_traffic(ds, name: str = ""):
    """(left) The A-weighted sound power per metre of line L'_W,A at every save against the axle
    passages (years of traffic on top when the traffic is known), its cycle average from the start,
    the start + rise_dB line and the average target, a mark where each criterion trips inside the
    axes; (right) the line sound power per one-third-octave band at the saves (up to _MAX_SPECTRA,
    evenly chosen), with the A-weighted spectrum of the last save dashed. The criteria in words below.

    Parameters
    ----------
    ds : xarray.Dataset
        From rail.studies.noise.noise_outputs (or rail.app.api.noise).
    name : str
        The scenario, for the title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(12.5, 4.8), layout="constrained")
    n = ds["passage"].values
    L = ds["line_sound_power_A"].values
    a1.plot(n, L, "o-", color="k", ms=4, label="L'_W,A at the saves")
    a1.plot(n, ds["line_sound_power_A_cycle_average"].values, "s--", color="tab:blue", ms=3,
            label="cycle average from the start")
    a = ds.attrs
    rise = a.get("grinding_noise_rise_threshold")
    if rise is not None and np.isfinite(rise):
        a1.axhline(L[0] + rise, color="tab:red", lw=0.9, ls=":", label=f"start + {rise:g} dB (criterion a)")
    target = a.get("grinding_noise_average_threshold")
    if target is not None and np.isfinite(target):
        a1.axhline(target, color="tab:blue", lw=0.9, ls=":", label=f"target {target:g} dB(A) (criterion b)")
    for c, colour in (("rise", "tab:red"), ("average", "tab:blue"), ("band_rms", "tab:green")):
        p = a.get(f"grinding_noise_{c}_passages")
        if p is not None and np.isfinite(p) and p <= n[-1]:
            a1.axvline(p, color=colour, lw=1.2, alpha=0.6, label=f"{c.replace('_', ' ')} trips ({text.count(float(p))})")
    a1.set_xlabel("axle passages")
    a1.set_ylabel("A-weighted line sound power\nL'_W,A (dB(A) re 1 pW/m)")
    a1.set_title(f"overall level against traffic; change {L[-1] - L[0]:+.2f} dB over the run", fontsize=9)
    years = ds["years"].values
    if np.all(np.isfinite(years)) and years[-1] > 0:
        per = years[-1] / n[-1]
        top = a1.secondary_xaxis("top", functions=(lambda x: x * per, lambda y: y / per))
        top.set_xlabel("years of traffic")
    a1.legend(fontsize=7, loc="best")
    f = ds["frequency"].values
    shown = np.unique(np.linspace(0, len(n) - 1, min(len(n), _MAX_SPECTRA)).round().astype(int))
    colours = [plt.cm.viridis(i / max(len(shown) - 1, 1)) for i in range(len(shown))]
    for c, i in zip(colours, shown):
        a2.semilogx(f, ds["line_sound_power"].values[i], "o-", color=c, ms=3, lw=0.9, label=f"{text.count(float(n[i]))}")
    a2.semilogx(f, ds["line_sound_power"].values[-1] + ds["a_weighting"].values, "--", color="0.4", lw=1.0,
                label="last save, A-weighted")
    a2.set_xlabel("one-third-octave band centre frequency (Hz)")
    a2.set_ylabel("line sound power L'_W,eq,line\n(dB re 1 pW/m)")
    a2.set_title("spectrum at the saves (axle passages)", fontsize=9)
    a2.legend(fontsize=7, title="axle passages", title_fontsize=7, loc="best")
    speed = (f"a fleet of {ds.sizes['traffic_class']} classes, mean speed {a['speed_m_per_s']:g} m/s" if "fleet_speeds" in a
             else f"{a['speed_m_per_s']:g} m/s")
    fig.suptitle(f"Rolling noise by CNOSSOS-EU{', scenario ' + name if name else ''}: {speed}, "
                 f"{a['vehicles_per_hour']:.4g} vehicles/h, {a['sleeper']} sleepers, pad {a['pad_class']}, wheel {a['brake']}",
                 fontsize=9)
    notes = "\n".join(textwrap.fill(str(a[f"grinding_noise_{c}_text"]).replace(" um", " µm"), 170)
                      for c in ("rise", "average", "band_rms") if f"grinding_noise_{c}_text" in a)
    if "fleet_speeds" in a:  # each class's A-weighted line sound power, start -> last save
        L = ds["line_sound_power_A_class"].values
        notes += "\n" + textwrap.fill("per class, L'_W,A at the start -> the last save, dB(A) re 1 pW/m: " + "; ".join(
            f"{n} {L[0, k]:.1f} -> {L[-1, k]:.1f} ({L[-1, k] - L[0, k]:+.1f} dB)" for k, n in enumerate(ds["class_name"].values)), 170)
    fig.text(0.01, -0.01, notes, fontsize=6.5, va="top", ha="left")
    return fig
