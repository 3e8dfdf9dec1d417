#!/usr/bin/env bash
# Stop the test cluster of start_cluster.sh by its pidfiles, and remove its configuration link.
D=${SLURM_TEST_DIR:-/tmp/slurm-test}
for f in "$D/slurmd.pid" "$D/slurmctld.pid" "$D/munge/munged.pid"; do
    [ -f "$f" ] && kill "$(cat "$f")" 2>/dev/null || true
done
if [ -L /etc/slurm/slurm.conf ] && [ "$(readlink /etc/slurm/slurm.conf)" = "$D/etc/slurm.conf" ]; then rm -f /etc/slurm/slurm.conf; fi
