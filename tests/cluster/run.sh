#!/usr/bin/env bash
# Cluster test (issue 23), run by .ci/run: a one-node SLURM cluster on this machine (Debian's munge,
# slurmctld, slurmd, slurm-client; no cgroups, no accounting; daemons stopped by their pidfiles on
# exit), then a figure and a small growth target built through profiles/slurm, with one scancel in
# the middle of the growth job: the profile retries it, it resumes from its checkpoint, and the
# result must equal an uninterrupted local run bit for bit.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
here="$root/tests/cluster"
py=$(command -v python)
if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null || ! command -v sbatch >/dev/null; then
    if ! { apt-get install -y -q munge slurmctld slurmd slurm-client >/dev/null 2>&1 || \
           { apt-get update -q >/dev/null 2>&1 && apt-get install -y -q munge slurmctld slurmd slurm-client >/dev/null 2>&1; }; }; then
        echo "CLUSTER TEST NOT RUN: the SLURM packages could not be installed here (apt-get as root failed)."
        exit 0
    fi
fi
export SLURM_TEST_DIR=$(mktemp -d /tmp/slurm-test.XXXX)
trap 'bash "$here/stop_cluster.sh"' EXIT
bash "$here/start_cluster.sh"
export SLURM_CONF="$SLURM_TEST_DIR/etc/slurm.conf"

scenario='track:
  pad:
    stiffness: 2.0e+8
speeds: [40.0]
growth:
  passages: 400000
  save_every: 10000
'
work=$(mktemp -d /tmp/railgrowth-cluster.XXXX)
local=$(mktemp -d /tmp/railgrowth-local.XXXX)
for d in "$work" "$local"; do
    cp -r "$root/config" "$d/config"
    printf '%s' "$scenario" > "$d/config/scenarios/cluster_test.yaml"
done
target=results/growth/cluster_test/V40.nc
cd "$work"
start=$(date +%s)
"$py" -m snakemake -s "$root/Snakefile" --profile "$root/profiles/slurm" --slurm-init-seconds-before-status-checks 1 \
    results/figures/fig06.png "$target" > "$work/snakemake.log" 2>&1 &
smk=$!
# scancel the growth job once its first checkpoint is written
for i in $(seq 1 600); do
    if [ -f results/checkpoints/cluster_test_V40.npz ]; then break; fi
    if ! kill -0 $smk 2>/dev/null; then echo "snakemake ended before the growth job saved a checkpoint"; tail -30 "$work/snakemake.log"; exit 1; fi
    sleep 0.5
done
jobs=$(squeue -h -o %i)
echo "checkpoint written; scancel $jobs"
scancel $jobs
wait $smk || { echo "the cluster run failed:"; tail -40 "$work/snakemake.log"; exit 1; }
grep -q "resuming from" logs/growth/cluster_test/V40.log || { echo "the retried growth job did not resume from its checkpoint"; cat logs/growth/cluster_test/V40.log; exit 1; }
test -s results/figures/fig06.png
echo "cluster run: $(( $(date +%s) - start )) s"
cd "$local"
"$py" -m snakemake -s "$root/Snakefile" -j2 "$target" > "$local/snakemake.log" 2>&1 || { tail -30 "$local/snakemake.log"; exit 1; }
"$py" - "$work/$target" "$local/$target" <<'PY'
import sys
import numpy as np
import xarray as xr
with xr.open_dataset(sys.argv[1]) as a, xr.open_dataset(sys.argv[2]) as b:
    for name in ("Z_real", "Z_imag", "passage"):
        if not np.array_equal(a[name].values, b[name].values):
            sys.exit(f"cluster run with a scancel differs from the uninterrupted run in {name}")
print("cluster run with a scancel equals the uninterrupted local run bit for bit")
PY
