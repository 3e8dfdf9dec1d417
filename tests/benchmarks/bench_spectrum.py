"""Benchmark (not a test): the growth-rate spectrum of the default scenario at one speed.

Target (issue 33): at 40 m/s at the default resolution (config.yaml: 48 bays, 20 mm to 0.6 m, 30
lines per octave, two contact grids, the report's normal contact) at most 60 s CPU, within 1 % of
the previous result at every line where |rate| exceeds a hundredth of the largest. The
non-Hertzian contact of the scenario files (lines down to L / K) is measured too (--normal).

The inputs are those of the workflow's rule rate_spectrum_speed at the default configuration
(rail.setup.build.spectrum_scenario, the tables of the scenario's own wheel offsets, the lines and
settings of rail.studies.rate_spectrum.spectrum_with_settings). The
receptance tables (about 40 s) are computed once and kept in --tables-dir, so that only the
spectrum is timed. numba is warmed up first on a small case (its compilation is reported
separately). CPU time is time.process_time of this process.

Run:  OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python tests/benchmarks/bench_spectrum.py [--speed 40]
      [--normal report|nonhertzian] [--method linear|probe] [--save-reference r.npz] [--compare r.npz]
"""

import argparse
import dataclasses
import pickle
import time
from pathlib import Path

import numpy as np

from rail import chain, growth_spectrum
from rail.setup import build, config
from rail.setup.config import SCENARIO_FILE_DEFAULTS

ROOT = Path(__file__).resolve().parents[2]


def settings(normal: str):
    """The configuration and figures.rate_spectrum settings: config.yaml for 'report' (the
    report's figures), config.yaml with the scenario-file defaults for 'nonhertzian'."""
    cfg = config.load_yaml(ROOT / "config/config.yaml")
    if normal == "nonhertzian":
        cfg = config.deep_merge(cfg, SCENARIO_FILE_DEFAULTS)
    cfg = config.deep_merge(cfg, {"contact": {"normal": normal}})
    return cfg, dict(cfg["figures"]["rate_spectrum"])


def tables(scn, speed: float, cache_dir: Path):
    """The spectrum's Bloch tables at the speed, computed once and kept (pickled) in cache_dir."""
    path = cache_dir / f"tables_V{speed:g}_N{scn.roughness.bays}_K{scn.harmonics}.pkl"
    if path.exists():
        with open(path, "rb") as f:
            return pickle.load(f)
    c = time.process_time()
    tabs = chain.receptance_table(scn, speed)
    print(f"receptance tables: {time.process_time() - c:.1f} s CPU (kept in {path})", flush=True)
    cache_dir.mkdir(parents=True, exist_ok=True)
    with open(path, "wb") as f:
        pickle.dump(tabs, f)
    return tabs


def warm_up(scn, tabs, method):
    """Compile (or load from numba's cache) the contact march on a few lines."""
    c = time.process_time()
    growth_spectrum.rate_spectrum(scn, tabs, [5], grid_phases=1, check_lines=1, method=method)
    return time.process_time() - c


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--speed", type=float, default=40.0)
    ap.add_argument("--normal", choices=("report", "nonhertzian"), default="report")
    ap.add_argument("--method", choices=("linear", "probe"), default="linear",
                    help="rail.growth_spectrum.rate_spectrum's method ('probe': the previous, independent path)")
    ap.add_argument("--tables-dir", type=Path, default=ROOT / ".bench_cache")
    ap.add_argument("--save-reference", type=Path)
    ap.add_argument("--compare", type=Path)
    ap.add_argument("--profile", type=Path, help="write a cProfile of the spectrum here")
    a = ap.parse_args()
    cfg, s = settings(a.normal)
    scn = build.spectrum_scenario(cfg)
    tabs = tables(scn, a.speed, a.tables_dir)
    print(f"warm-up (numba compilation or cache load): {warm_up(scn, tabs, a.method):.1f} s CPU", flush=True)
    prof = None
    if a.profile:
        import cProfile
        prof = cProfile.Profile()
        prof.enable()
    c0, t0 = time.process_time(), time.perf_counter()
    lines = growth_spectrum.spectrum_lines(scn.L, scn.roughness.bays, scn.harmonics, float(s["shortest"]), float(s["longest"]),
                                           int(s["per_octave"]))
    sp = growth_spectrum.rate_spectrum(scn, tabs, lines, eps=float(s["eps"]), grid_phases=int(s["grid_phases"]), method=a.method)
    cpu, wall = time.process_time() - c0, time.perf_counter() - t0
    if prof:
        prof.disable()
        prof.dump_stats(a.profile)
    print(f"V = {a.speed:g} m/s, normal contact {a.normal}, method {a.method}: {len(sp.line)} lines of "
          f"{scn.roughness.bays} bays, {sp.wavelength.min() * 1e3:.3g}-{sp.wavelength.max() * 1e3:.3g} mm, "
          f"{s['grid_phases']} grids: {cpu:.1f} s CPU ({wall:.1f} s wall); target 60 s CPU", flush=True)
    print(f"linearity {sp.linearity:.2e}, grid spread at most {(sp.grid_spread / np.abs(sp.growth_rate).max()).max():.2e} "
          "of the largest rate")
    arrays = {f.name: getattr(sp, f.name) for f in dataclasses.fields(sp)}
    if a.save_reference:
        np.savez(a.save_reference, cpu=cpu, speed=a.speed, normal=a.normal, **arrays)
        print(f"saved {a.save_reference}")
    if a.compare:
        ref = np.load(a.compare)
        if not np.array_equal(ref["line"], sp.line):
            raise SystemExit("the reference holds other lines")
        compare(ref, sp, float(ref["cpu"]), cpu)


def compare(ref, sp, cpu_ref, cpu):
    """The error table: at every line with |rate| > max |rate| / 100, the relative error of the rate
    (complex), of its real part (growth) and imaginary part (drift), and of the phase."""
    R0, R = ref["rate"], sp.rate
    big = np.abs(R0) > np.abs(R0).max() / 100
    rel = np.abs(R - R0) / np.abs(R0)
    re = np.abs(R.real - R0.real) / np.abs(R0)
    im = np.abs(R.imag - R0.imag) / np.abs(R0)
    ph = np.abs(np.angle(R / R0))
    print(f"CPU {cpu_ref:.1f} s (reference) -> {cpu:.1f} s")
    print(f"lines with |rate| > max/100: {big.sum()} of {big.size}")
    print(f"worst |R - R0| / |R0|      {rel[big].max():.2e} at {ref['wavelength'][big][np.argmax(rel[big])] * 1e3:.4g} mm")
    print(f"worst |Re(R - R0)| / |R0|  {re[big].max():.2e}")
    print(f"worst |Im(R - R0)| / |R0|  {im[big].max():.2e}")
    print(f"worst |phase(R / R0)|      {ph[big].max():.2e} rad")
    g0 = -R0.real
    gbig = np.abs(g0) > np.abs(g0).max() / 100
    print(f"worst growth rate error |dg| / |g0| where |g0| > max/100: {(np.abs(R.real - R0.real) / np.abs(g0))[gbig].max():.2e}")
    o0, o = ref["rate_other"], sp.rate_other
    print(f"worst |other - other0| / |R0| {(np.abs(o - o0) / np.abs(R0))[big].max():.2e}")
    for name in ("source", "sideband", "grid_spread"):
        print(f"{name}: largest difference {np.abs(sp.__getattribute__(name) - ref[name]).max():.3e} "
              f"(largest value {np.abs(ref[name]).max():.3e})")
    print(f"linearity {float(ref['linearity']):.2e} -> {sp.linearity:.2e}")
    print(" wavelength_mm  locked  |R0|/max   rel_err   re_err    im_err   phase_rad")
    for i in np.flatnonzero(big):
        print(f"{ref['wavelength'][i] * 1e3:14.4g}  {int(ref['locked'][i]):6d}  {abs(R0[i]) / abs(R0).max():8.3f}  "
              f"{rel[i]:8.1e}  {re[i]:8.1e}  {im[i]:8.1e}  {ph[i]:9.1e}")
    ok = rel[big].max() <= 0.01
    print("WITHIN 1 %" if ok else "NOT WITHIN 1 %")


if __name__ == "__main__":
    main()
