"""Benchmark (not a test): the growth-rate spectrum of an irregular track (a cell of bays whose
supports differ) at one speed, method 'linear' against the nonlinear probes (method 'probe').

Target (issue 44): irregular_voided at 40 m/s at most 60 s CPU per speed, within 1 % of the
nonlinear cell spectrum at every line above a hundredth of the largest rate.

The inputs are the workflow's: the scenario file resolved as the workflow resolves it
(rail.setup.config.resolve_scenario_file), rail.setup.build.spectrum_scenario, the lines and
settings of its figures.rate_spectrum. The cell's receptance table is computed once and kept in
--tables-dir, so that only the spectrum is timed. numba is warmed up first on one line (its
compilation is reported separately). CPU time is time.process_time of this process.

Run:  OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python tests/benchmarks/bench_cell_spectrum.py
      [--scenario irregular_voided] [--speed 40] [--method linear|probe] [--save-reference r.npz] [--compare r.npz]
"""

import argparse
import dataclasses
import time
from pathlib import Path

import numpy as np
from bench_spectrum import tables

from rail import growth_spectrum
from rail.setup import build, config

ROOT = Path(__file__).resolve().parents[2]


def scenario(name: str):
    """The spectrum's Scenario and figures.rate_spectrum settings of a scenario file or a study file's case, as the
    workflow resolves it."""
    from rail.setup.study_files import study_cases

    cfg = config.load_yaml(ROOT / "config/config.yaml")
    schema = config.load_yaml(ROOT / "config/schema/config.schema.yaml")
    path = ROOT / f"config/scenarios/{name}.yaml"
    scen = config.load_yaml(path) if path.exists() else dict(study_cases(ROOT)[name][1])
    scen.pop("sweep", None)
    res = config.resolve_scenario_file(cfg, schema, scen, name)
    return build.spectrum_scenario(res, name), dict(res["figures"]["rate_spectrum"])


def compare(ref, sp):
    """Per line above a hundredth of the largest |rate|: the relative error of the growth rate (its
    real part, against itself), of the complex rate and of the other eigenvalue."""
    R0, R = ref["rate"], sp.rate
    g0, g = -R0.real, sp.growth_rate
    big = np.abs(g0) > np.abs(g0).max() / 100
    eg = np.abs(g - g0) / np.abs(g0)
    er = np.abs(R - R0) / np.abs(R0)
    eo = np.abs(sp.rate_other - ref["rate_other"]) / np.abs(ref["rate_other"])
    print(f"lines with |growth rate| > max/100: {big.sum()} of {big.size}")
    print(f"worst |g - g0| / |g0| there: {eg[big].max():.2e} at {ref['wavelength'][big][np.argmax(eg[big])] * 1e3:.4g} mm")
    print(f"worst |R - R0| / |R0| (every line): {er.max():.2e}; other eigenvalue {eo.max():.2e}")
    print(f"source: largest relative difference {np.max(np.abs(sp.source - ref['source']) / np.abs(ref['source'])):.2e}")
    print(" wavelength_mm  g0/max|g0|   rel_err_g   rel_err_R")
    for i in range(big.size):
        print(f"{ref['wavelength'][i] * 1e3:14.4g}  {g0[i] / np.abs(g0).max():10.3f}  {eg[i]:10.1e}  {er[i]:10.1e}")
    print("WITHIN 1 %" if eg[big].max() <= 0.01 else "NOT WITHIN 1 %")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenario", default="irregular_voided")
    ap.add_argument("--speed", type=float, default=40.0)
    ap.add_argument("--method", choices=("linear", "probe"), default="linear")
    ap.add_argument("--tables-dir", type=Path, default=ROOT / ".bench_cache")
    ap.add_argument("--save-reference", type=Path)
    ap.add_argument("--compare", type=Path)
    ap.add_argument("--profile", type=Path, help="write a cProfile of the spectrum here")
    a = ap.parse_args()
    scn, s = scenario(a.scenario)
    tab = tables(scn, a.speed, a.tables_dir)
    lines = growth_spectrum.spectrum_lines(scn.L, scn.roughness.bays, scn.harmonics, float(s["shortest"]), float(s["longest"]),
                                           int(s["per_octave"]))
    c = time.process_time()
    growth_spectrum.rate_spectrum(scn, tab, lines[:1], grid_phases=1, method=a.method)
    print(f"warm-up (numba compilation or cache load, one line): {time.process_time() - c:.1f} s CPU", flush=True)
    prof = None
    if a.profile:
        import cProfile
        prof = cProfile.Profile()
        prof.enable()
    c0, t0 = time.process_time(), time.perf_counter()
    sp = growth_spectrum.rate_spectrum(scn, tab, lines, eps=float(s["eps"]), grid_phases=int(s["grid_phases"]), method=a.method)
    cpu, wall = time.process_time() - c0, time.perf_counter() - t0
    if prof:
        prof.disable()
        prof.dump_stats(a.profile)
    print(f"{a.scenario}, V = {a.speed:g} m/s, method {a.method}: {len(sp.line)} lines of a cell of {scn.roughness.bays} bays, "
          f"{sp.wavelength.min() * 1e3:.3g}-{sp.wavelength.max() * 1e3:.3g} mm, {s['grid_phases']} grids: {cpu:.1f} s CPU "
          f"({wall:.1f} s wall); target 60 s CPU", flush=True)
    print(f"method: {sp.method}; linearity {sp.linearity:.2e}; grid spread at most "
          f"{(sp.grid_spread / np.abs(sp.growth_rate).max()).max():.2e} of the largest growth rate")
    arrays = {f.name: getattr(sp, f.name) for f in dataclasses.fields(sp)}
    if a.save_reference:
        np.savez(a.save_reference, cpu=cpu, **arrays)
        print(f"saved {a.save_reference}")
    if a.compare:
        ref = np.load(a.compare)
        if not np.array_equal(ref["line"], sp.line):
            raise SystemExit("the reference holds other lines")
        print(f"CPU {float(ref['cpu']):.1f} s (reference) -> {cpu:.1f} s")
        compare(ref, sp)


if __name__ == "__main__":
    main()
