"""Benchmark (not a test): the cost of the wheels' source (issue 58, rail.studies.wheel_source.with_wheel_source)
against the growth-rate spectrum it is added to, on a train of four wheels (two bogies, 2.5 m wheelbase,
17.5 m apart) at one speed on the default track's lines (figures.rate_spectrum, the band's lines at most
15 Hz apart over 900-1,400 Hz, the non-Hertzian contact on the patch's true path: the scenario files' start).

Target (issue 58): the source at most the cost of the spectrum itself. For one wheel the source is free (its own
rate is the spectrum's); for a train it is one spectrum of one wheel on the same lines and tables (the wheel
alone on the track, rail.chain.single_wheel). Printed: the CPU time of the train's spectrum, of the source (the
single wheel's spectrum and the source's arithmetic) and their ratio. CPU time is time.process_time.

Run:  OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python tests/benchmarks/bench_wheel_source.py [--speed 39]
"""

import argparse
import time

from rail import chain
from rail.app import api
from rail.setup import build, inputs
from rail.studies import rate_spectrum, wheel_source

FOUR = [0.0, 2.5, 17.5, 20.0]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--speed", type=float, default=39.0)
    a = ap.parse_args()
    study = api.load("ws_cast_iron", changes={"wheels": {"positions": FOUR}, "figures": {"rate_spectrum": {"speeds": [a.speed]}}})
    scn = build.spectrum_scenario(study.config, study.name)
    s = study.config["figures"]["rate_spectrum"]
    tabs = chain.receptance_table(scn, a.speed)
    c = time.process_time()
    sp = rate_spectrum.spectrum_with_settings(scn, tabs, s)
    ds = rate_spectrum.spectrum_dataset_of({a.speed: sp}, scn)
    t_spectrum = time.process_time() - c
    c = time.process_time()
    out = wheel_source.with_wheel_source(ds, scn, tabs, s, inputs.wheel_source_spectra(study.config))
    t_source = time.process_time() - c
    print(f"{len(sp.line)} lines of {scn.roughness.bays} bays, {len(FOUR)} wheels at {a.speed:g} m/s: spectrum {t_spectrum:.1f} s CPU, "
          f"source {t_source:.1f} s CPU, ratio {t_source / t_spectrum:.2f} (target at most 1)")
    print(wheel_source.settled_summary_markdown(out))


if __name__ == "__main__":
    main()
