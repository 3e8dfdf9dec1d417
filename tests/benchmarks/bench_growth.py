"""Benchmark (not a test): 100,000 passages of one wheel at 40 m/s at the default settings.

Target (growth issue): under 30 s on one core. Prints the CPU time of the receptance table and of
the growth loop separately.
Run:  OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python tests/benchmarks/bench_growth.py
"""

import io
import time
from pathlib import Path

from rail import config, growth, interaction, moving, params

ROOT = Path(__file__).resolve().parents[2]


def main():
    cfg = config.load_yaml(ROOT / "config/config.yaml")
    track = params.track(cfg)
    K = params.harmonics(cfg)
    c0 = time.process_time()
    tab = moving.receptance_table(track, 40.0, K, rtol=float(cfg["numerics"]["track"]["rtol"]))
    c1 = time.process_time()
    settings = params.growth_settings(cfg)
    growth.run_growth(
        tab, params.wheels(cfg), params.contact_spring(cfg), params.contact_material(cfg),
        float(cfg["material"]["density"]), float(cfg["wear"]["coefficient"]),
        interaction.Roughness.smooth(K), track.beta0, track.L, settings, progress=io.StringIO(),
    )
    c2 = time.process_time()
    print(f"passages {settings.passages}, per update {settings.passages_per_update}, contact nodes {settings.nodes}")
    print(f"receptance table {c1 - c0:.1f} s CPU, growth loop {c2 - c1:.1f} s CPU, total {c2 - c0:.1f} s (target 30 s)")


if __name__ == "__main__":
    main()
