#!/usr/bin/env bash
# Brings up a one-node Slurm cluster on this machine (munged, slurmctld and slurmd on
# 127.0.0.1, state in a temporary directory), submits a small `bench retrieval` sweep as
# a 4-task job array with scripts/slurm/sweep.sbatch, waits, merges the shards and
# checks them against the same sweep run unsharded, run by run (all but the times).
#
#   scripts/test-slurm.sh PATH/TO/cluttertamp [WORKDIR]
#
# Exit code 0: the merged shards are the unsharded run; 1: they differ or Slurm failed;
# 77: Slurm cannot be brought up here (not installed: scripts/install-deps.sh --slurm;
# not root; ports taken), with the reason.
set -uo pipefail
cli=$(realpath "${1:?usage: test-slurm.sh CLUTTERTAMP [WORKDIR]}")
here=$(cd "$(dirname "$0")" && pwd)
work=${2:-$(mktemp -d /tmp/cluttertamp-slurm-XXXXXX)}
mkdir -p "$work"
work=$(realpath "$work")
skip() { echo "test-slurm: skipped: $*"; exit 77; }

for tool in munged munge slurmctld slurmd sbatch squeue sinfo; do
  command -v "$tool" > /dev/null || skip "$tool is not installed (scripts/install-deps.sh --slurm)"
done
[ "$(id -u)" -eq 0 ] || skip "bringing up slurmctld and slurmd needs root"
ctld_port=16817
slurmd_port=16818
for port in $ctld_port $slurmd_port; do
  if (exec 3<> "/dev/tcp/127.0.0.1/$port") 2> /dev/null; then skip "port $port is in use"; fi
done

started=()
cleanup() {  # the daemons this script started, stopped before it returns
  for pid in "${started[@]}"; do kill "$pid" 2> /dev/null; done
  for pid in "${started[@]}"; do
    for _ in $(seq 100); do kill -0 "$pid" 2> /dev/null || break; sleep 0.1; done
  done
}
trap cleanup EXIT

# munge: the node's credentials. Debian's package makes the key; start the daemon as
# its own user unless one already answers.
if ! munge -n 2> /dev/null | unmunge > /dev/null 2>&1; then
  mkdir -p /run/munge && chown munge:munge /run/munge
  su -s /bin/sh munge -c "/usr/sbin/munged --pid-file=/run/munge/test-slurm.pid" || skip "munged does not start"
  sleep 1
  started+=("$(cat /run/munge/test-slurm.pid)")
  munge -n | unmunge > /dev/null || skip "munge does not answer"
fi

node=$(hostname -s)
rm -rf "$work/state" "$work/spool" "$work/log" "$work/out"
mkdir -p "$work/state" "$work/spool" "$work/log" "$work/out"
cat > "$work/slurm.conf" << CONF
ClusterName=cluttertamp-test
SlurmctldHost=$node(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/log/slurmctld.log
SlurmdLogFile=$work/log/slurmd.log
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MpiDefault=none
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
NodeName=$node NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=test Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$work/slurm.conf
slurmctld -f "$SLURM_CONF" -i || skip "slurmctld does not start (see $work/log/slurmctld.log)"
sleep 1
started+=("$(cat "$work/slurmctld.pid")")
slurmd -f "$SLURM_CONF" || skip "slurmd does not start (see $work/log/slurmd.log)"
sleep 1
started+=("$(cat "$work/slurmd.pid")")
for _ in $(seq 30); do
  sinfo -h -o %t 2> /dev/null | grep -q idle && break
  sleep 1
done
sinfo -h -o %t | grep -q idle || skip "the node does not come up: $(sinfo 2>&1 | tail -1)"

sweep=(--sizes 12 --scenes 1 --runs 2 --planner retrieval_graph --time-limit 600)
job=$(CLUTTERTAMP="$cli" sbatch --parsable --array=0-3 --output="$work/log/task-%a.out" \
  "$here/slurm/sweep.sbatch" "$work/out" retrieval "${sweep[@]}") || { echo "test-slurm: sbatch failed"; exit 1; }
echo "test-slurm: submitted job array $job (4 tasks)"
for _ in $(seq 600); do
  [ -z "$(squeue -h -j "$job" 2> /dev/null)" ] && break
  sleep 1
done
[ -z "$(squeue -h -j "$job" 2> /dev/null)" ] || { echo "test-slurm: the array did not finish in 10 minutes"; exit 1; }
for k in 0 1 2 3; do
  [ -f "$work/out/shard-$k.jsonl" ] || { echo "test-slurm: task $k wrote no records:"; cat "$work/log/task-$k.out"; exit 1; }
done

"$cli" bench merge -q "$work"/out/shard-*.jsonl --csv "$work/merged.csv" || exit 1
"$cli" bench retrieval -q "${sweep[@]}" --csv "$work/whole.csv" || exit 1
# Every column but the three times (time_s, task_s, motion_s).
if diff <(cut -d, -f1-6,10- "$work/whole.csv") <(cut -d, -f1-6,10- "$work/merged.csv"); then
  echo "test-slurm: the 4 shards of job array $job merged are the unsharded run, run by run"
else
  echo "test-slurm: the merged shards differ from the unsharded run (above)"
  exit 1
fi
