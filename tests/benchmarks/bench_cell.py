"""Benchmark (not a test): an irregular track periodic over 8 bays at 40 m/s (issue 34).

The receptance table over the cell and 100,000 passages of one wheel from the smooth rail, for the
stiff-pad case (irregular_stiff_pad of config/studies/irregular_track.yaml, K = 36 per bay, non-Hertzian contact) and
a random track of the ensemble, with their CPU time and peak resident memory; and, for scale, the
uniform track's table at the same K and the uniform cell of 8 bays.
Run:  OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python tests/benchmarks/bench_cell.py
"""

import copy
import io
import resource
import time
from pathlib import Path

from rail import chain, moving
from rail.cell import TrackCell
from rail.setup import build, config
from rail.setup.study_files import study_cases

ROOT = Path(__file__).resolve().parents[2]


def _peak_mb():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def _scenario(name, **extra):
    cfg = config.load_yaml(ROOT / "config/config.yaml")
    schema = config.load_yaml(ROOT / "config/schema/config.schema.yaml")
    scen = copy.deepcopy(study_cases(ROOT)[name][1])  # a case of config/studies/irregular_track.yaml
    scen.pop("sweep", None)
    scen = config.deep_merge(scen, extra)
    return build.scenario(config.resolve(cfg, schema, scen, name), name)


def main():
    for name in ("irregular_stiff_pad", "irregular_random"):
        scn = _scenario(name)
        c0 = time.process_time()
        tab = chain.receptance_table(scn, 40.0)
        c1 = time.process_time()
        chain.grow(scn, tab, progress=io.StringIO())
        c2 = time.process_time()
        print(f"{name}: cell of {scn.cell.bays} bays, K = {scn.harmonics} per bay ({tab.A.shape[-1]} harmonics of the cell, "
              f"{tab.nodes} nodes): table {c1 - c0:.1f} s CPU, {scn.growth.passages} passages {c2 - c1:.1f} s CPU; "
              f"peak {_peak_mb():.0f} MB so far")
    scn = _scenario("irregular_stiff_pad")
    c0 = time.process_time()
    moving.receptance_table(scn.track, 40.0, scn.harmonics, (0.0,), scn.track_numerics.rtol)
    c1 = time.process_time()
    moving.cell_receptance_table(TrackCell.uniform(scn.track, 8), 40.0, scn.harmonics, (0.0,), scn.track_numerics.rtol)
    c2 = time.process_time()
    print(f"for scale: the uniform track's table {c1 - c0:.1f} s CPU; the uniform cell of 8 bays {c2 - c1:.1f} s CPU")


if __name__ == "__main__":
    main()
