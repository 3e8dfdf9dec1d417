"""Benchmark (not a test): the growth loop with the dynamic creepage u_bar against the loop without it (issue 54:
at most 1.3 times), and the error of its lagged coupling per wear harmonic.

100,000 passages of one wheel at 40 m/s on the default track, 61 contact nodes, with the trailer wheelset and
the rail's flexibility (the case dyn_rail_trailer of config/studies/rail_flexibility.yaml at the default
contact grid), from the smooth rail. The loops are run in turn, three rounds (CPU time, one core; a machine
loaded by other jobs moves the time of a run by 10-30 %, so the ratios are given as the median of the rounds' own
ratios, and the best times); the marches (rail.contact.solve_tangential) of each are counted, the measure that
does not depend on the load. Loops with u_bar:

- lagged: the growth loop as it runs (rail.wear.bay_wear's creepage_lag = rail.creepage.coupling.LAGGED_STEP: one march per
  update from the last update's state, extrapolated; the first update from rest, rail.creepage.coupling.REST_STATE, stops at
  the lagged threshold too, 3 marches);
- lagged, first update to a step below 1e-4: the same with the first update's lag 1e-4 (4 marches);
- lagged, first update to 1e-5: the same with the first update's Newton steps to the tolerance 1e-5 (5 marches;
  the loop of issue 54 before its first update took the lag);
- Newton: every update's Newton steps to the tolerance 1e-5 (creepage_lag None; the loop before issue 54);
- reference: Newton steps to 1e-8 (run once, for the errors).

Every loop with u_bar has the modes' periodic response (rail.creepage.modes.periodic_response) compiled since issue 54's
first update lagged; in Python it took about 10 % of the loop without u_bar.

The errors are judged per harmonic against that harmonic: for each harmonic j within 40 dB of the largest at
the end, abs(dZ_j / dZ_j,ref - 1) of the roughness's change over the run (it bounds the relative amplitude error
and the phase error in rad), and the level's difference in dB. The loop without u_bar is judged the same way: the
size of what the coupling changes, which a wrong coupling's error would be of the order of.
Run:  OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python tests/benchmarks/bench_growth_creepage.py [speed ...]
"""

import contextlib
import dataclasses
import functools
import io
import sys
import time

import numpy as np

from rail.creepage import coupling
from rail import chain, growth, wear
from rail.app import api


@contextlib.contextmanager
def _settings(bay_kwargs=None, tol=None, first_lag=False):
    """rail.wear.bay_wear (and its march) called with other settings while in the block: bay_kwargs, the march's
    tol, or the first update's (its start rail.creepage.coupling.REST_STATE) creepage_lag first_lag (None: Newton steps to the
    tolerance)."""
    bay, march = wear.bay_wear, coupling.march_with_creepage

    def first(*args, creepage_start=None, creepage_lag=coupling.LAGGED_STEP, **kwargs):
        return bay(*args, creepage_start=creepage_start, creepage_lag=first_lag if creepage_start is coupling.REST_STATE else creepage_lag,
                   **kwargs)

    if tol is not None:
        coupling.march_with_creepage = functools.partial(march, tol=tol, max_iter=60)
    if bay_kwargs:
        wear.bay_wear = functools.partial(bay, **bay_kwargs)
    if first_lag is not False:
        wear.bay_wear = first
    try:
        yield
    finally:
        wear.bay_wear, coupling.march_with_creepage = bay, march


def _run(scn, tab, **settings):
    """(CPU time [s], marches, history) of one growth run."""
    marches = [0]
    tangential = wear.solve_tangential

    def counted(*args, **kwargs):
        marches[0] += 1
        return tangential(*args, **kwargs)

    wear.solve_tangential = counted
    try:
        with _settings(**settings):
            c = time.process_time()
            hist = chain.grow(scn, tab, progress=io.StringIO())
            return time.process_time() - c, marches[0], hist
    finally:
        wear.solve_tangential = tangential


def _errors(hist, ref):
    """Per harmonic within 40 dB of the largest at the end: (harmonics j, abs(dZ_j / dZ_j,ref - 1), level difference [dB])."""
    Z0 = ref.Z[0]
    K = (len(Z0) - 1) // 2
    L = growth.levels_dB(ref.Z[-1])
    top = L >= L.max() - 40
    dW = np.abs((hist.Z[-1] - Z0)[K + 1:] / (ref.Z[-1] - Z0)[K + 1:] - 1)
    dB = np.abs(growth.levels_dB(hist.Z[-1]) - L)
    return np.flatnonzero(top) + 1, dW[top], dB[top]


LOOPS = {  # label: (u_bar, settings)
    "without u_bar": (False, {}),
    "lagged, first update lagged too (the loop as it runs)": (True, {}),
    "lagged, first update to a step below 1e-4": (True, dict(first_lag=1e-4)),
    "lagged, first update to 1e-5": (True, dict(first_lag=None)),
    "Newton to 1e-5": (True, dict(bay_kwargs=dict(creepage_lag=None))),
}


def main(speeds, rounds=3):
    scn = api.load("dyn_rail_trailer", changes={"numerics": {"contact": {"nodes": 61}}}).scenario
    bare = dataclasses.replace(scn, material=dataclasses.replace(scn.material, longitudinal=None, rail_flexibility=None))
    g = scn.growth
    print(f"passages {g.passages}, per update {g.passages_per_update}, contact nodes {scn.contact_numerics.nodes}, "
          f"lagged step {coupling.LAGGED_STEP:g}, {rounds} rounds")
    for V in speeds:
        tab = chain.receptance_table(scn, V)
        for s in (bare, scn):  # compile (or load numba's cache) and warm up: the first run with u_bar took 4-5 times the next
            chain.grow(s, tab, progress=io.StringIO())
        times = {k: [] for k in LOOPS}
        marches, hists = {}, {}
        for _ in range(rounds):
            for label, (dyn, settings) in LOOPS.items():
                t, marches[label], hists[label] = _run(scn if dyn else bare, tab, **settings)
                times[label].append(t)
        _, mr, ref = _run(scn, tab, bay_kwargs=dict(creepage_lag=None), tol=1e-8)
        t0 = np.array(times["without u_bar"])
        print(f"{V:g} m/s, {len(ref.full_slip)} updates; reference, Newton to 1e-8 at every update: {mr} marches")
        for label in LOOPS:
            t = np.array(times[label])
            ratio = "" if label == "without u_bar" else (f", ratio {np.median(t / t0):.2f} (rounds {', '.join(f'{r:.2f}' for r in t / t0)}; "
                                                          f"marches {marches[label] / marches['without u_bar']:.2f})")
            j, e, db = _errors(hists[label], ref)
            worst = int(np.argmax(e))
            print(f"  {label}: best {t.min():.2f} s CPU, {marches[label]} marches{ratio}")
            print(f"    worst wear harmonic (of {len(j)} within 40 dB) {100 * e[worst]:.2g} % at j = {j[worst]}, level {db.max():.3f} dB; "
                  f"per harmonic [%]: {', '.join(f'{jj}: {100 * ee:.2g}' for jj, ee in zip(j, e))}")
        print("  target: lagged at most 1.3 times without u_bar")


if __name__ == "__main__":
    main([float(v) for v in sys.argv[1:]] or [40.0])
