"""Benchmark (not a test): 100,000 passages of one wheel at 40 m/s at the default settings.

Target (growth issue): under 30 s on one core. Prints the CPU time of the receptance table and of
the growth loop separately, the loop for each normal-contact model (issue 31: the non-Hertzian
contact at most 1.5 times the report's) and for the wear on the patch's true path (issue 42: at most
1.2 times the wear under the wheel centre) and with the wheelset's dynamic creepage (issue 43: at most
1.3 times without), each the best of three runs. The smooth rail's growth is
what the default runs, and a 1 um roughness at 12 mm exercises the pressure's shape factor.
Run:  OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python tests/benchmarks/bench_growth.py
"""

import dataclasses
import io
import time
from pathlib import Path

from rail import interaction
from rail import chain
from rail.setup import build, config
from rail.creepage.wheelset import Wheelset, wheelset_modes

ROOT = Path(__file__).resolve().parents[2]


def _loop(scn, tab, rough):
    best = float("inf")
    for _ in range(3):
        c = time.process_time()
        chain.grow(scn, tab, rough, progress=io.StringIO())
        best = min(best, time.process_time() - c)
    return best


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
    K = scn.harmonics
    for label, rough in (("smooth rail", interaction.Roughness.smooth(K)),
                         ("1 um at 12 mm", interaction.Roughness.harmonic(1e-6, 0.012, scn.L, K))):
        t = {}
        for model in ("report", "nonhertzian"):
            s = dataclasses.replace(scn, contact_numerics=dataclasses.replace(scn.contact_numerics, normal=model))
            t[model] = _loop(s, tab, rough)
        print(f"growth loop, {label}: report {t['report']:.2f} s, nonhertzian {t['nonhertzian']:.2f} s CPU per "
              f"{g.passages} passages (ratio {t['nonhertzian'] / t['report']:.2f}, target <= 1.5)")
        s = dataclasses.replace(scn, contact_numerics=dataclasses.replace(scn.contact_numerics, normal="nonhertzian", path="patch"))
        tp = _loop(s, tab, rough)
        print(f"growth loop, {label}: nonhertzian on the patch's true path {tp:.2f} s CPU (ratio to the wheel's path "
              f"{tp / t['nonhertzian']:.2f}, target <= 1.2)")
        for name, ws in (("trailer", Wheelset("torsional", scn.material.wheel_radius, wheel_inertia=45.0, centre_inertia=14.0,
                                              axle_stiffness=5.5e6, damping=0.01)),
                         ("motored", Wheelset("torsional", scn.material.wheel_radius, wheel_inertia=50.0, centre_inertia=20.0,
                                              axle_stiffness=5.5e6, motor_inertia=288.0, coupling_stiffness=3.6e6, damping=0.02))):
            sd = dataclasses.replace(s, material=dataclasses.replace(s.material, longitudinal=wheelset_modes(ws)))
            td = _loop(sd, tab, rough)
            print(f"growth loop, {label}: with the {name} wheelset's dynamic creepage {td:.2f} s CPU (ratio to without "
                  f"{td / tp:.2f}, target <= 1.3; issue 43)")


if __name__ == "__main__":
    main()
