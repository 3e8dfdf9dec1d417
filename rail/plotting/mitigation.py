"""The mitigation study's figure (issue 55, rail.studies.mitigation): per nominal speed, the growth rate over
frequency near pinned-pinned of the default track, each mitigation, the speed spread and the driven shares."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

__all__ = ["mitigation_figure"]


def mitigation_figure(curves: dict, rows: list[dict]):
    """Growth rate near pinned-pinned per nominal speed, a curve per variant, and the peaks' changes.

    Parameters
    ----------
    curves : dict
        {nominal speed [m/s]: [(label, frequency [Hz], rate [dB per 100,000 axles])]}, frequencies at the nominal speed.
    rows : list of dict
        rail.studies.mitigation.mitigation_rows'.

    Returns
    -------
    matplotlib.figure.Figure
    """
    speeds = sorted(curves)
    fig, axes = plt.subplots(1, len(speeds) + 1, figsize=(5.2 * (len(speeds) + 1), 4.6))
    for ax, V in zip(axes, speeds):
        fpp = next(r["f_pp_Hz"] for r in rows if r["speed_m_s"] == V)
        for label, f, g in curves[V]:
            o = np.argsort(f)
            keep = (f[o] > 0.85 * fpp) & (f[o] < 1.35 * fpp)
            style = {"lw": 2.2, "color": "k"} if label.startswith("default") else {"lw": 1.2}
            if label.startswith("driven"):
                style.update(ls=":", lw=1.0)
            ax.plot(f[o][keep], g[o][keep], label=label, **style)
        ax.axhline(0, color="0.4", lw=0.8)
        ax.axvline(fpp, color="k", ls="--", lw=0.8)
        ax.text(fpp, ax.get_ylim()[1], " f_pp", va="top", fontsize=7)
        ax.set_xlabel("excitation frequency V / λ at the nominal speed (Hz)")
        ax.set_ylabel("growth rate (dB per 100,000 axles)")
        ax.set_title(f"{V:g} m/s", fontsize=10)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=6, loc="best")
    bx = axes[-1]
    labels = [r["case"] for r in rows if r["speed_m_s"] == speeds[0] and r["verdict"] != "reference"]
    y = np.arange(len(labels))
    for k, V in enumerate(speeds):
        ch = [next(r["change_dB_per_1e5_axles"] for r in rows if r["speed_m_s"] == V and r["case"] == lab) for lab in labels]
        bx.barh(y + (k - 0.5) * 0.38, ch, height=0.36, label=f"{V:g} m/s")
    bx.set_yticks(y, labels, fontsize=7)
    bx.axvline(0, color="k", lw=0.8)
    bx.set_xlabel("change of the band's peak growth (dB per 100,000 axles)")
    bx.set_title("against the default track (< 0: reduces)", fontsize=10)
    bx.grid(True, axis="x", alpha=0.3)
    bx.legend(fontsize=7)
    fig.suptitle("Which mitigation reduces the band near pinned-pinned (the rail's flexibility, the motored wheelset, "
                 "non-Hertzian contact on the patch's path)", fontsize=10)
    fig.tight_layout()
    return fig
