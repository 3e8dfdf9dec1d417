"""Benchmark (not a test): CPU cost of one wheel passage's contact when the contact splits into several
zones (issue 31, rail.contact.normal.passage_contact / multizone_contact), against the same passage on a rail whose
contact stays one zone.

One passage of the growth loop is one rail.wear.bay_wear call: the normal contact at every step of the march
(single-zone Chebyshev solution; brute force with the centred hull at the steps where that fails), then the
tangential march. Printed: steps, multi-zone steps, CPU of the normal contact and of the march (one run each: the
multi-zone normal contact takes minutes). Default scenario, non-Hertzian contact, 40 m/s, harmonic roughness of 20 um at 10 mm (0.8 patch
lengths: the contact splits at most steps) and of 5 um at 10 mm (one zone throughout).
Run:  OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python tests/benchmarks/bench_multizone.py
(numpy's threads would count their spinning as CPU time)
"""

import dataclasses
import time
from pathlib import Path

import numpy as np

from rail import chain, interaction, wear
from rail.contact import normal
from rail.contact import solve_tangential
from rail.setup import build, config

ROOT = Path(__file__).resolve().parents[2]


def _best(f, n=1):
    best, out = float("inf"), None
    for _ in range(n):
        c = time.process_time()
        out = f()
        best = min(best, time.process_time() - c)
    return best, out


def main():
    scn = build.scenario(config.load_yaml(ROOT / "config/config.yaml"))
    scn = dataclasses.replace(scn, contact_numerics=dataclasses.replace(scn.contact_numerics, normal="nonhertzian"))
    tab = chain.receptance_table(scn, 40.0)
    K = scn.harmonics
    m, nums = scn.material, scn.contact_numerics
    print(f"contact nodes {nums.nodes}, brute-force elements per spacing {normal.MULTIZONE_REFINE}")
    for amp in (5e-6, 20e-6):
        rough = interaction.Roughness.harmonic(amp, 0.010, scn.L, K)
        forces = chain.solve_forces(scn, tab, rough)
        mi = wear.march_inputs(forces, 0, rough, m, nums)
        steps = mi.P.size
        xw = (np.arange(steps) - mi.spin) * mi.delta
        xi = (np.arange(2 * mi.M + 1) - mi.M) * mi.delta
        slope = wear.roughness_slope(rough, forces.period)
        t_norm, pc = _best(lambda: normal.passage_contact(mi.P, xw, slope, m, xi))
        multi = int(np.sum(pc.min_shape <= 0))
        t_sz, _ = _best(lambda: normal.patch_contact(mi.P, xw, slope, m, xi, strict=False))
        t_march, _ = _best(lambda: solve_tangential(mi.P, mi.a, m, 40.0, mi.delta, mi.M, closure=nums.closure,
                                                    closure_scale=nums.closure_scale, shape=mi.shape))
        zones = np.bincount(pc.zones)
        per_multi = (t_norm - t_sz) / multi * 1e3 if multi else float("nan")
        print(f"{amp * 1e6:.0f} um at 10 mm: {steps} steps, {multi} multi-zone (zones: {dict(enumerate(zones))}); normal contact "
              f"{t_norm:.2f} s CPU (single-zone part {t_sz:.2f} s, multi-zone {per_multi:.1f} ms per multi-zone step), "
              f"march {t_march:.2f} s CPU (one passage: the two together)")


if __name__ == "__main__":
    main()
