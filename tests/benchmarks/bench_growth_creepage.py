"""Benchmark (not a test): the growth loop with the dynamic creepage u_bar against the loop without it (issue 54:
at most 1.3 times), and the error of its lagged coupling per wear harmonic.

100,000 passages of one wheel at 40 m/s on the default track, 61 contact nodes, with the trailer wheelset and
the rail's flexibility (the case dyn_rail_trailer of config/studies/rail_flexibility.yaml at the default
contact grid), from the smooth rail. Each loop is timed as the best of three runs (CPU time, one core); the
marches (rail.contact.solve_tangential) of each are counted. Three loops with u_bar:

- lagged: the growth loop as it runs (rail.wear.bay_wear's creepage_lag = rail.wear.LAGGED_STEP: one march per
  update from the last update's state, extrapolated);
- Newton: every update's Newton steps to the tolerance 1e-5 (creepage_lag None; the loop before issue 54);
- reference: Newton steps to 1e-8 (run once, for the errors).

The errors are judged per harmonic against that harmonic: for each harmonic j within 40 dB of the largest at
the end, abs(dZ_j / dZ_j,ref - 1) of the roughness's change over the run (it bounds the relative amplitude error
and the phase error in rad), and the level's difference in dB.
Run:  OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python tests/benchmarks/bench_growth_creepage.py [speed ...]
"""

import dataclasses
import functools
import io
import sys
import time

import numpy as np

from rail import chain, growth, wear
from rail.app import api


def _loop(scn, tab, runs=3):
    """(best CPU time [s], marches of one run, history)."""
    marches = [0]
    tangential = wear.solve_tangential

    def counted(*args, **kwargs):
        marches[0] += 1
        return tangential(*args, **kwargs)

    wear.solve_tangential = counted
    try:
        best, hist, count = float("inf"), None, 0
        for _ in range(runs):
            marches[0] = 0
            c = time.process_time()
            hist = chain.grow(scn, tab, progress=io.StringIO())
            best = min(best, time.process_time() - c)
            count = marches[0]
    finally:
        wear.solve_tangential = tangential
    return best, count, hist


def _patched(runs, **bay_kwargs):
    """A _loop with rail.wear.bay_wear (and its march) called with other settings."""
    bay, march = wear.bay_wear, wear.march_with_creepage
    tol = bay_kwargs.pop("tol", None)
    if tol is not None:
        wear.march_with_creepage = functools.partial(march, tol=tol, max_iter=60)
    wear.bay_wear = functools.partial(bay, **bay_kwargs)
    try:
        return _loop(*runs)
    finally:
        wear.bay_wear, wear.march_with_creepage = bay, march


def _errors(hist, ref):
    Z0 = ref.Z[0]
    K = (len(Z0) - 1) // 2
    L = growth.levels_dB(ref.Z[-1])
    top = L >= L.max() - 40
    dW = np.abs((hist.Z[-1] - Z0)[K + 1:] / (ref.Z[-1] - Z0)[K + 1:] - 1)
    dB = np.abs(growth.levels_dB(hist.Z[-1]) - L)
    j = int(np.argmax(np.where(top, dW, 0))) + 1
    return dW[top].max(), j, dB[top].max(), int(top.sum())


def main(speeds):
    scn = api.load("dyn_rail_trailer", changes={"numerics": {"contact": {"nodes": 61}}}).scenario
    bare = dataclasses.replace(scn, material=dataclasses.replace(scn.material, longitudinal=None, rail_flexibility=None))
    g = scn.growth
    print(f"passages {g.passages}, per update {g.passages_per_update}, contact nodes {scn.contact_numerics.nodes}, "
          f"lagged step {wear.LAGGED_STEP:g}")
    for V in speeds:
        tab = chain.receptance_table(scn, V)
        chain.grow(bare, tab, progress=io.StringIO())  # compile and warm up
        t0, m0, _ = _loop(bare, tab)
        tl, ml, hl = _loop(scn, tab)
        tn, mn, hn = _patched((scn, tab), creepage_lag=None)
        _, mr, hr = _patched((scn, tab, 1), creepage_lag=None, tol=1e-8)
        updates = len(hl.full_slip)
        print(f"{V:g} m/s, {updates} updates: without u_bar {t0:.2f} s CPU ({m0} marches); lagged {tl:.2f} s ({ml} marches, "
              f"ratio {tl / t0:.2f}, target <= 1.3); Newton to 1e-5 {tn:.2f} s ({mn} marches, ratio {tn / t0:.2f}); "
              f"reference, Newton to 1e-8: {mr} marches")
        for label, h in (("lagged", hl), ("Newton 1e-5", hn)):
            e, j, db, n = _errors(h, hr)
            print(f"  {label}: worst wear harmonic (of {n} within 40 dB) {100 * e:.2g} % at j = {j}, level {db:.3f} dB")


if __name__ == "__main__":
    main([float(v) for v in sys.argv[1:]] or [40.0])
