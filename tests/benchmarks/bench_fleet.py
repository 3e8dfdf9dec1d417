"""Benchmark (not a test): cost of growth under a four-class fleet against four single-train runs.

The fleet: a four-wheel locomotive (Class 87 positions, driven) and a lighter two-bogie coach (trailing
and braked axles), each at 36 and 44 m/s, growth from the default configuration's smooth rail over
growth.passages (reduced here by --passages). Counted: the receptance tables computed (rail.chain.track_table
calls) and CPU time of (a) the fleet run (rail.chain.fleet_tables + grow_fleet) and (b) the four classes run one
by one as single trains (rail.chain.receptance_table + grow each, as a user without the fleet would).
Target (issue 35): (a) costs no more than (b), and the fleet computes one table per speed, not per class.
Run:  OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python tests/benchmarks/bench_fleet.py [--passages 20000]
"""

import argparse
import dataclasses
import io
import time
from pathlib import Path

from rail import chain
from rail import fleet as F
from rail.setup import build, config

ROOT = Path(__file__).resolve().parents[2]

CLASS87 = (0.0, 3.3, 10.0, 13.3)  # m
COACH = (0.0, 2.6, 16.0, 18.6)  # m


def count_tables():
    """Wrap rail.chain.track_table so that every table computed is counted; returns the list of speeds."""
    calls = []
    real = chain.track_table

    def counted(*args, **kwargs):
        calls.append(float(args[2]))
        return real(*args, **kwargs)

    chain.track_table = counted
    return calls


def main(passages: int):
    cfg = config.load_yaml(ROOT / "config/config.yaml")
    base = build.scenario(cfg)
    base = dataclasses.replace(base, growth=dataclasses.replace(base.growth, passages=passages, save_every=passages))
    fleet = F.Fleet((F.Vehicle("class87", CLASS87, 1e5, 1350.0, (-0.001,) * 4, 0.5),
                     F.Vehicle("coach", COACH, 6e4, 900.0, (0.0, 0.0, 0.0008, 0.0008), 0.5)),
                    F.SpeedClasses((36.0, 44.0), (0.5, 0.5)), 20000.0)
    classes = fleet.classes(base)
    print(f"K = {base.harmonics}, contact nodes {base.contact_numerics.nodes}, {passages} axle passages, "
          f"{base.growth.passages_per_update} per update; {len(classes)} classes")
    calls = count_tables()
    c0 = time.process_time()
    tables = chain.fleet_tables(classes)
    c1 = time.process_time()
    chain.grow_fleet(classes, tables, progress=io.StringIO())
    c2 = time.process_time()
    fleet_tables = len(calls)
    print(f"fleet:   {fleet_tables} tables computed (speeds {sorted(calls)}), tables {c1 - c0:.1f} s, growth {c2 - c1:.1f} s, "
          f"total {c2 - c0:.1f} s CPU")
    calls.clear()
    single_tab = single_grow = 0.0
    for c in classes:
        c3 = time.process_time()
        tab = chain.receptance_table(c.scenario, c.speed)
        c4 = time.process_time()
        chain.grow(c.scenario, tab, progress=io.StringIO())
        c5 = time.process_time()
        single_tab += c4 - c3
        single_grow += c5 - c4
    print(f"singles: {len(calls)} tables computed, tables {single_tab:.1f} s, growth {single_grow:.1f} s, "
          f"total {single_tab + single_grow:.1f} s CPU")
    print(f"fleet / four singles: {(c2 - c0) / (single_tab + single_grow):.2f} (target <= 1); tables per class "
          f"{fleet_tables / len(classes):.2f} (one per speed: {len({c.speed for c in classes}) / len(classes):.2f})")


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--passages", type=int, default=20000, help="axle passages of each run (a multiple of growth.passages_per_update)")
    main(p.parse_args().passages)
