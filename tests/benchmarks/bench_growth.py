"""Benchmark (not a test): 100,000 passages of one wheel at 40 m/s at the default settings.

Target (growth issue): under 30 s on one core. Prints the CPU time of the receptance table and of
the growth loop separately.
Run:  OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python tests/benchmarks/bench_growth.py
"""

import io
import time
from pathlib import Path

from rail import chain
from rail.setup import build, config

ROOT = Path(__file__).resolve().parents[2]


def main():
    scn = build.scenario(config.load_yaml(ROOT / "config/config.yaml"))
    c0 = time.process_time()
    tab = chain.receptance_table(scn, 40.0)
    c1 = time.process_time()
    chain.grow(scn, tab, progress=io.StringIO())
    c2 = time.process_time()
    g = scn.growth
    print(f"passages {g.passages}, per update {g.passages_per_update}, contact nodes {scn.contact_numerics.nodes}")
    print(f"receptance table {c1 - c0:.1f} s CPU, growth loop {c2 - c1:.1f} s CPU, total {c2 - c0:.1f} s (target 30 s)")


if __name__ == "__main__":
    main()
