#!/usr/bin/env bash
# Benchmark (not a test) of issue 55's cost target: a two-vehicle fleet at a speed spread of 3 classes, the full physics,
# spectrum and growth to a grinding interval, within 30 minutes on 2 cores and 8 GB at the fleet's default settings.
# What a user does: drop the fleet file (tests/benchmarks/fleet_full_physics.yaml) into config/scenarios/ of a clean
# clone and run `snakemake -j2 study_fleet_bench` (tables per speed, the 6 class spectra, the fleet's spectrum, its
# growth run over growth.passages, the band view with the grinding interval, the noise and the overview).
# Prints the wall time, the CPU time of all jobs and the largest job's max_rss (Snakemake's benchmark files).
#
# Run:  bash tests/benchmarks/bench_fleet_full_physics.sh   (from the project folder, its .venv active)
set -euo pipefail
here=$(pwd)
work=$(mktemp -d)
git clone -q "$here" "$work/clone"
cp tests/benchmarks/fleet_full_physics.yaml "$work/clone/config/scenarios/fleet_bench.yaml"
cd "$work/clone"
export PYTHONPATH=$PWD OMP_NUM_THREADS=1
start=$(date +%s)
snakemake -j2 study_fleet_bench > "$work/snakemake.log" 2>&1 || { tail -30 "$work/snakemake.log"; exit 1; }
wall=$(( $(date +%s) - start ))
python - "$wall" <<'PY'
import csv, glob, sys
rows = [(f, list(csv.reader(open(f), delimiter="\t"))[-1]) for f in glob.glob("benchmarks/**/*.tsv", recursive=True)]
cpu = sum(float(r[9]) for _, r in rows)
f, r = max(rows, key=lambda x: float(x[1][2]))
print(f"wall {int(sys.argv[1]) / 60:.1f} min (target at most 30), CPU of all jobs {cpu / 60:.1f} min, largest max_rss {float(r[2]):.0f} MB ({f}); "
      f"{len(rows)} jobs")
for line in open("results/fleet/fleet_bench/bands.csv"):
    if line.startswith("# grinding interval"):
        print(line.strip())
PY
rm -rf "$work"
