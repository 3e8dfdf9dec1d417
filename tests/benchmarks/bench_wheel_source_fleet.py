"""Benchmark (not a test): the cost of a fleet's wheels' source (issue 58 for fleets, rail.studies.wheel_source.
class_source_arrays and fleet_source_dataset) against the fleet's growth-rate spectrum it is added to.

The fleet: a four-axle locomotive (Class 87 positions, every axle driven at -0.001: one axle group) with disc-braked
wheels and a four-axle coach (two trailing axles, two braked at +0.0008: two axle groups) with cast-iron block-braked
wheels, each at 36 and 44 m/s (four classes), on the default track. It is a scenario file (the scenario files'
contact) with the report's rail and fixed creepage, as config/studies/wheel_source.yaml's ws_cast_iron; one grid, 41
nodes; the fleet's spectrum lines (fleet.spectrum: bays, shortest, longest, per_octave; smaller here by the options).
Timed: the classes' spectra (as rule fleet_class_spectrum computes them), then the source: each class's axle groups
alone on the track (one spectrum of one wheel per group) and the fleet's arithmetic.
The tables (rail.chain.fleet_tables) are shared and timed apart.

Target (issue 58): the source at most the cost of the spectrum itself. CPU time is time.process_time.

Run:  OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python tests/benchmarks/bench_wheel_source_fleet.py [--per-octave 2]
"""

import argparse
import tempfile
import time
from pathlib import Path

import yaml

from rail import chain
from rail.app import api
from rail.growth_spectrum import fleet_spectrum_of, settings_lines
from rail.setup import build, inputs
from rail.studies import fleet as fleet_study
from rail.studies import rate_spectrum
from rail.studies import wheel_source

CLASS87 = [0.0, 3.3, 10.0, 13.3]  # m
COACH = [0.0, 2.6, 16.0, 18.6]  # m


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bays", type=int, default=5)
    ap.add_argument("--shortest", type=float, default=0.02)
    ap.add_argument("--longest", type=float, default=0.3)
    ap.add_argument("--per-octave", type=int, default=6)
    a = ap.parse_args()
    vehicles = [{"name": "class87", "positions": CLASS87, "static_load": 1.0e5, "unsprung_mass": 1350.0, "creepage": [-0.001] * 4,
                 "share": 0.5, "wheel_source": {"roughness": "disc"}},
                {"name": "coach", "positions": COACH, "static_load": 6.0e4, "unsprung_mass": 900.0,
                 "creepage": [0.0, 0.0, 0.0008, 0.0008], "share": 0.5}]  # the coach: the top-level roughness (cast iron)
    changes = {"fleet": {"vehicles": vehicles, "speeds": {"values": [36.0, 44.0], "weights": [0.5, 0.5]},
                         "spectrum": {"bays": a.bays, "shortest": a.shortest, "longest": a.longest, "per_octave": a.per_octave,
                                      "grid_phases": 1}},
               "wheel_source": {"roughness": "cast_iron"}, "numerics": {"contact": {"nodes": 41}},
               # the report's rail and fixed creepage, as ws_cast_iron of bench_wheel_source.py (with the rail's flexibility
               # the locomotive's class at 36 m/s stops: its dynamic creepage does not settle in the probes' march)
               "rail_flexibility": {"model": "none"}}
    with tempfile.TemporaryDirectory() as d:  # a scenario file: the scenario files' start (docs/wheel-source.md)
        path = Path(d) / "fleet_source.yaml"
        path.write_text(yaml.safe_dump(changes))
        study = api.load(path)
    cfg = study.config
    s = cfg["figures"]["rate_spectrum"]
    scn = build.spectrum_scenario(cfg, study.name)
    lines = settings_lines(scn.L, scn.roughness.bays, scn.harmonics, s)
    fl = build.fleet(cfg)
    classes = build.fleet_classes(cfg, scn)
    spectra = inputs.wheel_source_spectra(cfg)
    print(f"{len(lines)} lines, settings {s}", flush=True)
    c = time.process_time()
    tables = chain.fleet_tables(classes)
    t_tables = time.process_time() - c
    c = time.process_time()
    # each class as rule fleet_class_spectrum computes it (its method and checks from the settings), then combined
    fs = fleet_spectrum_of(classes, [rate_spectrum.spectrum_with_settings(cl.scenario, tables[cl.speed], s) for cl in classes])
    ds = fleet_study.fleet_spectrum_dataset(fs, fl, classes)
    t_spectrum = time.process_time() - c
    c = time.process_time()
    out = wheel_source.with_fleet_source(ds, fs, fl, classes, tables, s, spectra, scn.roughness.bays * scn.L)
    t_source = time.process_time() - c
    groups = {cl.vehicle: len(wheel_source.axle_groups(cl.scenario)) for cl in classes}
    what = ", ".join(f"{v}: 4 axles, {g} group(s)" for v, g in groups.items())
    print(f"{len(lines)} lines of {scn.roughness.bays} bays, {len(classes)} classes ({what}): "
          f"tables {t_tables:.1f} s, spectrum {t_spectrum:.1f} s CPU, source {t_source:.1f} s CPU, ratio {t_source / t_spectrum:.2f} "
          "(target at most 1)")
    print(wheel_source.settled_summary_markdown(out))


if __name__ == "__main__":
    main()
