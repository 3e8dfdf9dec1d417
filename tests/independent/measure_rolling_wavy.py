"""Issue 42's measurement with the brute-force rolling simulation (tests/independent/rolling_wavy.py).

For each lambda / 2a: the work harmonic at beta per unit roughness amplitude, normalised by the issue's
yardstick W-bar R_w beta^2 (W-bar the mean work per unit area, proportional to the mean wear depth), from
the exact rolling ('exact': the patch where the gap puts it), the same simulator with the patch held under
the wheel ('centred': the production model's assumption), and optionally the production model itself
(rail.normal.patch_contact + rail.contact.solve_tangential). Writes one JSON line per case.

    python tests/independent/measure_rolling_wavy.py --per-a 100 --out tests/independent/rolling_wavy_results/a100.jsonl

Sign: the harmonic is that of the wear DEPTH (material removed), W = W-bar + Re(H Delta e^{i beta x}) with the
rail r = Delta cos(beta x); the closed form of docs/contact.md, "-w-bar dc/dx", is +J0(beta a) in these units
(more wear on crests while J0 > 0: the rail height changes by -J0 w-bar R_w beta^2 Delta per passage).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from scipy.special import j0  # noqa: E402

from independent import rolling_wavy as rw  # noqa: E402
from rail.contact import ContactMaterial  # noqa: E402

# config/config.yaml: E, nu, half-width b, wheel radius 0.575 m (Class 87), mu_d, mu_s, creepage
MATERIAL = ContactMaterial(2.1e11, 0.3, 0.008, 0.575, 0.3, 0.3, -0.001)
LOAD = 1.0e5
LAMS = (0.7, 1.0, 1.5, 2.0, 3.0, 5.0, 10.0, 20.0)


def c2(z: complex) -> list[float]:
    return [round(z.real, 6), round(z.imag, 6)]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--per-a", type=float, default=100.0, help="lattice cells per smooth half-length a0")
    ap.add_argument("--rwkb2", type=float, default=1e-3, help="R_w Delta beta^2 (roughness amplitude)")
    ap.add_argument("--closure", default="zone", choices=("zone", "moment", "fixed"))
    ap.add_argument("--lams", default=",".join(str(x) for x in LAMS), help="comma-separated lambda / 2a0")
    ap.add_argument("--period", type=int, default=None, help="dither period K + 1 (default: rw.lattice)")
    ap.add_argument("--warmup", type=float, default=8.0, help="warm-up transits 2 a0")
    ap.add_argument("--production", type=int, default=0, help="also the production model at this many nodes (0: no)")
    ap.add_argument("--offsets", type=int, default=1,
                    help="average over this many interleaved wheel offsets phi = j / (offsets K) "
                         "(finer grid-phase average)")
    ap.add_argument("--creepage-modulation", action="store_true",
                    help="also the centred patch with the moving patch's effective creepage gamma / (1 + dc/dx)")
    ap.add_argument("--out", type=Path, default=None, help="append JSON lines here")
    args = ap.parse_args(argv)
    lams = [float(x) for x in args.lams.split(",")]
    for lo in lams:
        row = dict(lam_over_2a=lo, per_a=args.per_a, rwkb2=args.rwkb2, closure=args.closure, warmup=args.warmup,
                   offsets=args.offsets)
        modes = ["exact", "centred"] + (["centred_creep"] if args.creepage_modulation else [])
        for mode in modes:
            rs = []
            for j in range(args.offsets):
                a0 = rw.hertz_a(MATERIAL, LOAD)
                K = rw.lattice(lo * 2 * a0, a0, args.per_a, args.period)[2]
                rs.append(rw.measure(MATERIAL, LOAD, lo, per_a=args.per_a, rwkb2=args.rwkb2, mode=mode.split("_")[0],
                                     closure=args.closure, period=args.period, warmup_transits=args.warmup,
                                     phi=j / (args.offsets * K), creepage_modulation=mode == "centred_creep"))
            r = rs[0]
            mean = lambda name: sum(getattr(x, name) for x in rs) / len(rs)  # noqa: E731
            row[mode] = dict(H=c2(mean("H")), centre=c2(mean("centre")), half_length=c2(mean("half_length")),
                             force=c2(mean("force")), mean_work=mean("mean_work"),
                             seconds=round(sum(x.seconds for x in rs), 2), steps=r.steps,
                             H_each=[c2(x.H) for x in rs])
            row.update(a_over_h=round(r.a0 / r.h, 3), dither=r.dither, beta_a0=r.beta * r.a0,
                       J0=float(j0(r.beta * r.a0)), amplitude=r.amplitude)
        if args.production:
            t = time.process_time()
            H, W, _ = rw.production_centred(MATERIAL, LOAD, lo, nodes=args.production, rwkb2=args.rwkb2)
            row["production"] = dict(H=c2(H), mean_work=W, nodes=args.production,
                                     seconds=round(time.process_time() - t, 2))
        He = complex(*row["exact"]["H"])
        Hc = complex(*row["centred"]["H"])
        d = He - Hc
        print(f"lambda/2a {lo:5.2f}  a/h {row['a_over_h']:6.1f}  exact {He.real:+.4f}{He.imag:+.4f}i  centred "
              f"{Hc.real:+.4f}{Hc.imag:+.4f}i  difference {d.real:+.4f}{d.imag:+.4f}i  J0 {row['J0']:+.4f}"
              + (f"  centred+creepage minus centred {complex(*row['centred_creep']['H']) - Hc:+.4f}"
                 if args.creepage_modulation else "")
              + (f"  production {complex(*row['production']['H']):+.4f}" if args.production else "")
              + f"  ({row['exact']['seconds'] + row['centred']['seconds']:.0f} s)", flush=True)
        if args.out:
            args.out.parent.mkdir(parents=True, exist_ok=True)
            with open(args.out, "a") as f:
                f.write(json.dumps(row) + "\n")


if __name__ == "__main__":
    main()
