"""The band just above pinned-pinned with the rail's flexibility: its peak rate and frequency against
the parameters it rests on (issue 54, docs/dynamic-creepage.md, "What the band rests on").

Not a workflow rule (a study run by hand, about 1-2 min of CPU per spectrum): every variant is the case
``dyn_rail_pinned`` of config/studies/rail_flexibility.yaml (the default track with the rail's flexibility,
the rigid wheel at a fixed creepage, method 'linear') with one change, on the lines of ``--bays`` bays in
[``--low``, ``--high``] Hz at most ``--spacing`` Hz apart (rail.growth_spectrum.band_lines), one contact grid.
The peak is the largest rate on the lines, refined by a parabola through it and its two neighbours.

Run:  OMP_NUM_THREADS=1 python workflow/scripts/band_sensitivity.py --speed 60 --out results/band_sensitivity_60.csv
      [--variants base e-10 e+10 ...] [--bays 8] [--low 900] [--high 1400] [--spacing 15]
      python workflow/scripts/band_sensitivity.py --cross --speed 60 --out x.csv   (seconds: the moving load's cross
      receptance e psi/F at the load, a_0 of rail.creepage.rail_flexibility.moving_head_matrix, over the band for k_theta = 0, sourced,
      3 x sourced, on the default track)
"""

import argparse
import csv
import sys
import time
from pathlib import Path

import numpy as np

from rail.app import api

# The sourced rotational stiffness (schema, track.pad.rotational_stiffness): k_P l^2 / 12 for the default pad
# (3.5e8 N/m) over l = 0.18 m along the rail (docs/dynamic-creepage.md, "What the band rests on").
K_THETA = 3.5e8 * 0.18**2 / 12
E0 = 0.0911
KX0 = 1.0e7

VARIANTS = {
    "base": {},
    "e-10": {"track": {"rail": {"head_height": round(0.9 * E0, 6)}}},
    "e+10": {"track": {"rail": {"head_height": round(1.1 * E0, 6)}}},
    "ktheta": {"track": {"pad": {"rotational_stiffness": K_THETA}}},
    "ktheta3": {"track": {"pad": {"rotational_stiffness": 3 * K_THETA}}},
    "kx/3": {"track": {"pad": {"longitudinal_stiffness": KX0 / 3}}},
    "kx*3": {"track": {"pad": {"longitudinal_stiffness": KX0 * 3}}},
    "grid61": {"numerics": {"contact": {"nodes": 61}}},
    "grid41": {"numerics": {"contact": {"nodes": 41}}},
}


def peak(f, r):
    """Largest rate on the lines and its frequency, refined by a parabola through the three lines around it."""
    i = int(np.argmax(r))
    if 0 < i < len(r) - 1:
        y0, y1, y2 = r[i - 1 : i + 2]
        den = y0 - 2 * y1 + y2
        if den < 0 and abs(f[i + 1] - f[i] - (f[i] - f[i - 1])) < 1e-6 * f[i]:
            d = 0.5 * (y0 - y2) / den
            h = f[i + 1] - f[i]
            return float(y1 - 0.25 * (y0 - y2) * d), float(f[i] + d * h)
    return float(r[i]), float(f[i])


def cross(V, low, high, out):
    """The peak of the moving load's cross receptance e abs(psi/F) (a_0 at the load) over [low, high] Hz, 10 Hz apart
    (off the harmonics of V / L), for k_theta = 0, K_THETA and 3 K_THETA on the default track."""
    import dataclasses

    from rail.creepage import rail_flexibility as lg

    base = api.load("dyn_rail_pinned").scenario.track
    f = np.arange(low, high + 1.0, 10.0) + 0.37
    js = np.arange(-3, 4)
    with open(out, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["rotational_stiffness_N_m_per_rad", "frequency_Hz", "e_abs_psi_per_F_m_per_N"])
        for k in (0.0, K_THETA, 3 * K_THETA):
            h = lg.RailHead(dataclasses.replace(base, pad=dataclasses.replace(base.pad, rotational_stiffness=k)))
            e = np.array([h.head_height * abs(lg.moving_head_matrix(h, V, 2 * np.pi * fi, js, kinds=("psiF",))["psiF"][3, 3]) for fi in f])
            for fi, ei in zip(f, e):
                w.writerow([k, f"{fi:.2f}", f"{ei:.6e}"])
            i = int(np.argmax(e))
            y0, y1, y2 = np.log(e[i - 1 : i + 2])
            print(f"k_theta {k:.3g} N m/rad: e abs(psi/F) peaks at {f[i] + 5.0 * (y0 - y2) / (y0 - 2 * y1 + y2):.1f} Hz, "
                  f"{e[i]:.4g} m/N", flush=True)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--speed", type=float, default=60.0)
    p.add_argument("--variants", nargs="+", default=list(VARIANTS))
    p.add_argument("--bays", type=int, default=8)
    p.add_argument("--low", type=float, default=900.0)
    p.add_argument("--high", type=float, default=1400.0)
    p.add_argument("--spacing", type=float, default=15.0)
    p.add_argument("--nodes", type=int, default=41, help="contact grid of every variant but grid61/grid41")
    p.add_argument("--out", type=Path, required=True)
    p.add_argument("--cross", action="store_true", help="the cross receptance's peak only (seconds)")
    a = p.parse_args(argv)
    V = a.speed
    if a.cross:
        cross(V, a.low, a.high, a.out)
        return 0
    band = {"low": a.low, "high": a.high, "spacing": a.spacing}
    # the wavelength range: the band itself (the log-spaced lines then fall inside it too)
    rs = {"band": band, "shortest": V / a.high, "longest": V / a.low, "per_octave": 1, "grid_phases": 1,
          "speeds": [V], "bays": a.bays}
    a.out.parent.mkdir(parents=True, exist_ok=True)
    new = not a.out.exists()
    with open(a.out, "a", newline="") as fh:
        w = csv.writer(fh)
        if new:
            w.writerow(["variant", "speed_m_s", "frequency_Hz", "rate_dB_per_1e5_axles", "cpu_s"])
        for name in a.variants:
            ch = {"figures": {"rate_spectrum": rs}, "numerics": {"contact": {"nodes": a.nodes}}}
            for k1, v1 in VARIANTS[name].items():
                for k2, v2 in v1.items():
                    ch.setdefault(k1, {}).setdefault(k2, {}).update(v2)
            c = time.process_time()
            st = api.load("dyn_rail_pinned", changes=ch)
            ds = api.spectrum(st, speeds=[V], grid_phases=1)  # the period is figures.rate_spectrum.bays (a bays argument drops the band)
            cpu = time.process_time() - c
            db = ds["growth_dB_per_1e5_axles"].sel(speed=V).values if "growth_dB_per_1e5_axles" in ds else None
            lam = ds["wavelength"].values
            f = V / lam
            o = np.argsort(f)
            f, db = f[o], np.asarray(db)[o]
            for fi, ri in zip(f, db):
                w.writerow([name, V, f"{fi:.2f}", f"{ri:.4f}", f"{cpu:.1f}"])
            fh.flush()
            rp, fp = peak(f, db)
            print(f"{name:8s} V={V:g}: peak {rp:+.3f} dB/1e5 axles at {fp:.0f} Hz ({len(f)} lines, {cpu:.0f} s CPU)", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
