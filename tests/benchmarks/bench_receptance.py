"""Benchmark (not a test): receptance tables for 20, 40, 60, 80 m/s with K = 64 on one core.

Target (track issue): under 2 s per speed. Prints CPU time, node count and peak memory per speed.
Run:  OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python tests/benchmarks/bench_receptance.py
"""

import resource
import sys
import time
import tracemalloc
from pathlib import Path

from rail import moving
from rail.setup import build, config

ROOT = Path(__file__).resolve().parents[2]


def main(K=64, speeds=(20.0, 40.0, 60.0, 80.0)):
    cfg = config.load_yaml(ROOT / "config/config.yaml")
    scn = build.scenario(cfg)
    track, rtol = scn.track, scn.track_numerics.rtol
    print(f"K = {K}, rtol = {rtol}, damping = {track.damping}")
    print("speed_m_per_s  cpu_s  wall_s  nodes  peak_traced_MB")
    for V in speeds:
        tracemalloc.start()
        t0, c0 = time.perf_counter(), time.process_time()
        tab = moving.receptance_table(track, V, K, rtol=rtol)
        c1, t1 = time.process_time(), time.perf_counter()
        peak = tracemalloc.get_traced_memory()[1] / 2**20
        tracemalloc.stop()
        print(f"{V:13.0f}  {c1 - c0:5.2f}  {t1 - t0:6.2f}  {tab.nodes:5d}  {peak:14.0f}")
    print(f"max RSS {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MB")


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:2]))
