"""Benchmark (not a test): cost of a roughness period of N bays at 40 m/s, one wheel, default settings.

For N = 1, 4, 16: CPU time of the receptance tables (floor(N/2) + 1 of them) and of one growth update
(forces of the N classes, contact and wear over the N bays). Target (issue 19): the update cost
grows no faster than linearly in N, and 100,000 passages with N = 16 take under 3 minutes on one core.
Run:  OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python tests/benchmarks/bench_bloch.py [N ...]
"""

import dataclasses
import sys
import time
from pathlib import Path

from rail import chain
from rail.setup import build, config

ROOT = Path(__file__).resolve().parents[2]


def main(bays=(1, 4, 16)):
    base = build.scenario(config.load_yaml(ROOT / "config/config.yaml"))
    updates = base.growth.passages // base.growth.passages_per_update + 1  # the last one for the error estimate
    print(f"K = {base.harmonics}, contact nodes {base.contact_numerics.nodes}, {updates} wear evaluations per 100,000 passages")
    print("N   tables_cpu_s  update_cpu_s  update_per_bay_s  estimated_100k_passages_s")
    for N in bays:
        scn = dataclasses.replace(base, roughness=dataclasses.replace(base.roughness, kind="spectrum",
                                                                       file=str(ROOT / "config/roughness/example_spectrum.csv"), bays=N))
        c0 = time.process_time()
        tab = chain.receptance_table(scn, 40.0)
        c1 = time.process_time()
        Z = chain.initial_roughness(scn, 40.0).Z
        chain.train_wear(scn, tab, Z)
        c2 = time.process_time()
        up = c2 - c1
        print(f"{N:<3d} {c1 - c0:12.1f}  {up:12.2f}  {up / N:16.3f}  {c1 - c0 + updates * up:25.0f}")


if __name__ == "__main__":
    main(tuple(int(a) for a in sys.argv[1:]) or (1, 4, 16))
