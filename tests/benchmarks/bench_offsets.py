"""Benchmark (not a test): the receptance table with the four-wheel vehicle's nine offsets
(0, +-3.3, +-6.7, +-10, +-13.3 m) against the table of offset 0 alone, at one speed, K = 64.

Issue 33's targets: the nine-offset table at most 3 times the CPU of the offset-0 table and at
most 500 MB peak (resident set of a process that computes only that table). Each case runs in its
own process, so its peak resident memory is its own. With --save PATH the nine-offset table is
saved; with --reference PATH a table saved earlier (e.g. by the previous method) is compared entry
by entry with the new table's stated error.

Run:  OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python tests/benchmarks/bench_offsets.py [--speed 40]
"""

import argparse
import json
import subprocess
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
NINE = [0.0, 3.3, -3.3, 6.7, -6.7, 10.0, -10.0, 13.3, -13.3]

CHILD = """
import json, resource, sys, time
import numpy as np
from pathlib import Path
from rail import moving
from rail.setup import build, config
speed, offsets, save = float(sys.argv[1]), json.loads(sys.argv[2]), sys.argv[3]
scn = build.scenario(config.load_yaml(Path(sys.argv[4]) / "config/config.yaml"))
moving.receptance_table(scn.track, speed, 2, [0.0])  # imports and first calls outside the timing
c0, t0 = time.process_time(), time.perf_counter()
tab = moving.receptance_table(scn.track, speed, scn.track_numerics.harmonics, offsets, scn.track_numerics.rtol)
cpu, wall = time.process_time() - c0, time.perf_counter() - t0
if save:
    np.savez(save, A=tab.A, error=tab.error, offsets=tab.offsets)
print(json.dumps(dict(cpu=cpu, wall=wall, nodes=tab.nodes, rss_mb=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)))
"""


def run(speed, offsets, save=""):
    out = subprocess.run([sys.executable, "-c", CHILD, str(speed), json.dumps(offsets), save, str(ROOT)],
                         capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--speed", type=float, default=40.0)
    ap.add_argument("--save", default="")
    ap.add_argument("--reference", default="")
    args = ap.parse_args()
    save = args.save or ("/tmp/bench_offsets_table.npz" if args.reference else "")
    one = run(args.speed, [0.0])
    nine = run(args.speed, NINE, save)
    print(f"V = {args.speed:g} m/s, K = 64         cpu_s  wall_s  nodes  peak_rss_MB")
    for name, r in (("offset 0", one), ("nine offsets", nine)):
        print(f"{name:24s} {r['cpu']:6.2f}  {r['wall']:6.2f}  {r['nodes']:5d}  {r['rss_mb']:11.0f}")
    print(f"CPU ratio nine / one: {nine['cpu'] / one['cpu']:.2f} (target <= 3); peak {nine['rss_mb']:.0f} MB (target <= 500)")
    if args.reference:
        new, ref = np.load(save), np.load(args.reference)
        for i, d in enumerate(new["offsets"]):
            j = int(np.argmin(np.abs(ref["offsets"] - d)))
            diff = np.abs(new["A"][i] - ref["A"][j])
            print(f"d = {d:6.2f} m: max |new - reference| / new stated error = {np.max(diff / new['error'][i]):.3f}")


if __name__ == "__main__":
    main()
