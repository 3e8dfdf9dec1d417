#!/usr/bin/env bash
# A one-node SLURM cluster on this machine for tests/cluster/run.sh: no cgroups, no accounting;
# munge key, configuration, logs and the daemons' pidfiles under $SLURM_TEST_DIR.
set -euo pipefail
D=${SLURM_TEST_DIR:-/tmp/slurm-test}
mkdir -p "$D"/{spool,state,log,munge,etc}
HOST=$(hostname -s)
CPUS=$(nproc)
MEM=$(( $(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 - 1024 ))
# munge: a key of our own, a socket in $D
dd if=/dev/urandom of="$D/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$D/munge/munge.key"
chown root:root "$D/munge/munge.key"
munged --key-file="$D/munge/munge.key" --socket="$D/munge/munge.socket" --pid-file="$D/munge/munged.pid" \
       --log-file="$D/log/munged.log" --seed-file="$D/munge/munge.seed" --force
cat > "$D/etc/slurm.conf" <<CONF
ClusterName=railgrowth-test
SlurmctldHost=$HOST
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$D/munge/munge.socket
CryptoType=crypto/munge
StateSaveLocation=$D/state
SlurmdSpoolDir=$D/spool
SlurmctldPidFile=$D/slurmctld.pid
SlurmdPidFile=$D/slurmd.pid
SlurmctldLogFile=$D/log/slurmctld.log
SlurmdLogFile=$D/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
ReturnToService=2
MpiDefault=none
NodeName=$HOST CPUs=$CPUS RealMemory=$MEM State=UNKNOWN
PartitionName=debug Nodes=$HOST Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$D/etc/slurm.conf"
# the job steps (srun inside a batch job) read the default location: link it there unless a site
# configuration exists (stop_cluster.sh removes the link)
mkdir -p /etc/slurm
if [ ! -e /etc/slurm/slurm.conf ] || [ -L /etc/slurm/slurm.conf ]; then ln -sfn "$SLURM_CONF" /etc/slurm/slurm.conf; fi
slurmctld -f "$SLURM_CONF"
slurmd -f "$SLURM_CONF"
for i in $(seq 1 30); do
    if sinfo -h -o %T 2>/dev/null | grep -q idle; then echo "cluster up: $(sinfo -h)"; exit 0; fi
    sleep 1
done
echo "cluster did not come up"; tail -20 "$D/log/slurmctld.log" "$D/log/slurmd.log"; exit 1
