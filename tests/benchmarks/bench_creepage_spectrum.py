"""Benchmark (not a test): the linear growth-rate spectrum with every mechanism of dynamic creepage
(config/studies/dynamic_creepage_speeds.yaml, case dynspeed_together: the motored wheelset, the rail's longitudinal flexibility and
falling friction) against the fixed-creepage linear spectrum (dynspeed_fixed.yaml) on the same lines.

Target (issue 54): at most 1.5 times. Both on the scenarios' own settings (2 bays, 20-120 mm at five per
octave, one contact grid, 41 nodes, the non-Hertzian contact on the patch's true path) at one speed. The
receptance tables and the rail head's Bloch tables are computed first (kept in numba's and the
head tables' caches by a warm-up spectrum of one line at the same speed), so that only the spectrum is
timed. Printed: the CPU time of each spectrum, the ratio, and its parts: rail.growth_spectrum.linear_rates
(of which the smooth rail's u_bar_0, creepage_reference, and the tangent marches, work_tangent; the
comb's source is the smooth rail's wear of linear_rates' own march), and the linearity check's probes of
2 eps by the nonlinear march (with u_bar warm_train_wear, Newton steps from the linear prediction; without,
locked_matrix and probe_rates). The rest (rate_spectrum less those) is bookkeeping. With --probe the
probes' spectrum too (method 'probe', minutes) and the largest difference over the largest rate. CPU time
is time.process_time of this process.

Measured (2026-12-02, this machine, load 15-20, the code before and after run in turn): 8.8 at 40 m/s and 13.7
at 60 before the smooth rail's state was reused and the check's probes warm-started, 5.9 and 7.1 after
(docs/performance.md, "The linear spectrum with dynamic creepage").

Run:  OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python tests/benchmarks/bench_creepage_spectrum.py [--speed 40] [--probe]
"""

import argparse
import math
import os
import time
from pathlib import Path

import numpy as np

from rail import chain, growth_spectrum
from rail.growth_spectrum import creepage, linear
from rail.growth_spectrum.band import class_pair_spectrum
from rail.setup import build
from rail.setup.config import SCENARIO_FILE_DEFAULTS, deep_merge, load_yaml, validate_config
from rail.setup.plan import plan

ROOT = Path(__file__).resolve().parents[2]


def scenarios():
    """The resolved configurations of the dynspeed scenarios (rail.setup.plan, as the workflow reads them)."""
    here = Path.cwd()
    os.chdir(ROOT)
    try:
        schema = load_yaml("config/schema/config.schema.yaml")
        return plan(validate_config(load_yaml("config/config.yaml"), schema), schema).scenarios
    finally:
        os.chdir(here)


def timed(fn, *args, **kw):
    c = time.process_time()
    out = fn(*args, **kw)
    return out, time.process_time() - c


class Parts:
    """CPU time spent inside named functions (wrapped in their modules while a spectrum runs)."""

    def __init__(self, targets):
        self.targets, self.spent, self.saved = targets, {}, []

    def __enter__(self):
        for mod, name in self.targets:
            fn = getattr(mod, name)
            self.saved.append((mod, name, fn))

            def wrap(*a, _fn=fn, _key=name, **k):
                c = time.process_time()
                try:
                    return _fn(*a, **k)
                finally:
                    self.spent[_key] = self.spent.get(_key, 0.0) + time.process_time() - c
            setattr(mod, name, wrap)
        return self

    def __exit__(self, *exc):
        for mod, name, fn in self.saved:
            setattr(mod, name, fn)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--speed", type=float, default=40.0)
    ap.add_argument("--probe", action="store_true", help="also the probes' spectrum of dynspeed_together (minutes)")
    ap.add_argument("--band", action="store_true",
                    help="on the scenario files' default lines instead: the log-spaced lines and the band 900-1,400 Hz at most 15 Hz "
                         "apart (rail.setup.config.SCENARIO_FILE_DEFAULTS) on the shortest period that resolves it at the speed")
    a = ap.parse_args()
    cfgs = scenarios()
    out = {}
    for name in ("dynspeed_fixed", "dynspeed_together"):
        cfg = cfgs[name]
        if a.band:
            band = SCENARIO_FILE_DEFAULTS["figures"]["rate_spectrum"]["band"]
            N = max(2, math.ceil(a.speed / (band["spacing"] * build.spectrum_scenario(cfg, name).L)))
            cfg = deep_merge(cfg, {"figures": {"rate_spectrum": {"bays": N, "band": dict(band)}}, "roughness": {"bays": N}})
        scn = build.spectrum_scenario(cfg, name)
        s = cfg["figures"]["rate_spectrum"]
        lines = growth_spectrum.spectrum_lines(scn.L, scn.roughness.bays, scn.harmonics, float(s["shortest"]), float(s["longest"]),
                                               int(s["per_octave"]))
        if a.band:
            lines = growth_spectrum.settings_lines(scn.L, scn.roughness.bays, scn.harmonics, s, speeds=[a.speed])
        tabs, t_tab = timed(chain.receptance_table, scn, a.speed)
        _, t_warm = timed(growth_spectrum.rate_spectrum, scn, tabs, lines[:1], grid_phases=1, check_lines=1)
        print(f"{name}: tables {t_tab:.1f} s, warm-up {t_warm:.1f} s CPU", flush=True)
        with Parts([(growth_spectrum.spectrum, "linear_rates"), (linear, "creepage_reference"), (linear, "work_tangent"),
                    (growth_spectrum.spectrum, "warm_train_wear"), (growth_spectrum.spectrum, "locked_matrix"),
                    (growth_spectrum.spectrum, "probe_rates")]) as parts:
            # as a study's spectrum runs it (rail.studies.rate_spectrum.spectrum_with_settings): with dynamic creepage on
            # more than two bays one pair of Bloch classes at a time
            pairs = a.band and scn.roughness.bays > 2 and creepage.has_creepage(scn.material)
            sp, t = timed(class_pair_spectrum if pairs else growth_spectrum.rate_spectrum, scn, tabs, lines,
                          grid_phases=int(s["grid_phases"]), check_lines=4)
        out[name] = (scn, tabs, lines, sp, t)
        print(f"{name}: {len(lines)} lines of {scn.roughness.bays} bays at {a.speed:g} m/s, method {sp.method}: {t:.1f} s CPU; "
              + ", ".join(f"{k} {v:.1f} s" for k, v in parts.spent.items()), flush=True)
    t_fixed, t_all = out["dynspeed_fixed"][4], out["dynspeed_together"][4]
    print(f"ratio (every mechanism / fixed creepage): {t_all / t_fixed:.2f} (target 1.5)")
    if a.probe:
        scn, tabs, lines, sp, _ = out["dynspeed_together"]
        ref, t = timed(growth_spectrum.rate_spectrum, scn, tabs, lines, grid_phases=1, check_lines=1, method="probe")
        big = np.abs(ref.rate).max()
        print(f"probes: {t:.1f} s CPU; largest |linear - probe| / max |rate| = {np.abs(sp.rate - ref.rate).max() / big:.2e}")


if __name__ == "__main__":
    main()
