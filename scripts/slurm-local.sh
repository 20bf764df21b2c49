#!/usr/bin/env bash
# A sharded sweep on a real SLURM cluster: starts a one-node cluster on localhost (munged,
# slurmctld, slurmd from Debian's slurm-wlm and munge, installed when absent), lets
# `hdgear sweep --slurm 4` write the job array and merge job, submits them, waits, and checks that
# the merged file equals the same sweep run on one machine, byte for byte. Then stops every daemon
# it started (by pid) and removes its state.
#
#   scripts/slurm-local.sh [PATH/TO/hdgear]     (default: target/release/hdgear, built if absent)
#
# Needs root (to install packages and run slurmd): without it, it says SKIPPED and exits 0, or
# fails under CI=true. Exit 1 when the check fails.
set -euo pipefail

if [ "$(id -u)" != 0 ]; then
    if [ "${CI:-}" = true ]; then
        echo "slurm-local: FAILED: CI must run as root (to install slurm-wlm and munge, and run slurmd)"
        exit 1
    fi
    echo "slurm-local: SKIPPED (needs root to install slurm-wlm and munge and to run slurmd)"
    exit 0
fi
root=$(cd "$(dirname "$0")/.." && pwd)
hdgear=${1:-$root/target/release/hdgear}
if [ ! -x "$hdgear" ]; then
    (cd "$root" && cargo build --release --quiet)
fi
hdgear=$(realpath "$hdgear")

if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
    echo "slurm-local: installing slurm-wlm and munge"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq >/dev/null
    apt-get install -y -qq slurm-wlm munge >/dev/null
fi

state=$(mktemp -d /tmp/hdgear-slurm.XXXXXX)
pids=()
cleanup() {
    local code=$?
    for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
    for pid in "${pids[@]}"; do
        for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
        kill -9 "$pid" 2>/dev/null || true
    done
    rm -rf "$state"
    exit $code
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

host=$(hostname -s)
cpus=$(nproc)
mkdir -p "$state/ctld" "$state/spool" "$state/work"
chmod 700 "$state"
head -c 1024 /dev/urandom >"$state/munge.key"
chmod 400 "$state/munge.key"
munged -F --force --socket="$state/munge.sock" --key-file="$state/munge.key" \
    --pid-file="$state/munged.pid" --log-file="$state/munged.log" \
    --seed-file="$state/munge.seed" 2>>"$state/munged.log" &
pids+=($!)

# ports outside SLURM's defaults (6817/6818), so that a real cluster's daemons are not disturbed
cat >"$state/slurm.conf" <<EOF
ClusterName=hdgear-local
SlurmctldHost=$host
SlurmctldPort=16817
SlurmdPort=16818
SlurmUser=root
AuthType=auth/munge
AuthInfo=socket=$state/munge.sock
CredType=cred/munge
StateSaveLocation=$state/ctld
SlurmdSpoolDir=$state/spool
SlurmctldPidFile=$state/slurmctld.pid
SlurmdPidFile=$state/slurmd.pid
SlurmctldLogFile=$state/slurmctld.log
SlurmdLogFile=$state/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
MpiDefault=none
ReturnToService=2
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=local Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$state/slurm.conf"
for _ in $(seq 50); do [ -S "$state/munge.sock" ] && break; sleep 0.1; done
slurmctld -D -i -f "$SLURM_CONF" >>"$state/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" >>"$state/slurmd.out" 2>&1 &
pids+=($!)

up=
for _ in $(seq 150); do
    if sinfo -h -N -o '%t' 2>/dev/null | grep -qE '^(idle|mix|alloc)'; then up=1; break; fi
    sleep 0.2
done
if [ -z "$up" ]; then
    echo "slurm-local: the cluster did not come up; its logs:"
    tail -n 20 "$state"/*.log "$state"/*.out 2>/dev/null || true
    exit 1
fi
echo "slurm-local: one-node cluster up ($host, $cpus CPUs): $(sinfo -h -o '%P %D %t')"

# a directory whose name a shell and sbatch would both mangle unquoted (a space, a `%x`)
mkdir -p "$state/work/sweep dir %x"
cd "$state/work/sweep dir %x"
grid=(--param gamma=0.1:30:200:log --param delta=8:16:3 --rtol 1e-8)
"$hdgear" sweep "${grid[@]}" --out map.csv --slurm 4 --time 10:00 --quiet
t0=$(date +%s.%N)
bash map.slurm-submit.sh
for _ in $(seq 600); do
    [ -z "$(squeue -h -o %i 2>/dev/null)" ] && break
    sleep 0.5
done
t1=$(date +%s.%N)
if [ -n "$(squeue -h -o %i)" ]; then
    echo "slurm-local: jobs still queued after 300 s:"; squeue; exit 1
fi
echo "slurm-local: job array and merge finished in $(echo "$t1 - $t0" | bc) s"
for log in map.shard-*-of-4.log map.merge.log; do
    echo "  $log: $(tail -n 1 "$log")"
done
if [ ! -f map.csv ]; then
    echo "slurm-local: FAILED: no merged map.csv; the logs:"; tail -n 5 ./*.log; exit 1
fi
"$hdgear" sweep "${grid[@]}" --out single.csv --quiet 2>/dev/null
if cmp map.csv single.csv; then
    echo "slurm-local: PASSED: the merged map.csv ($(($(wc -l <map.csv) - 1)) rows) equals a single-machine run byte for byte"
else
    echo "slurm-local: FAILED: the merged file differs from the single-machine run"; exit 1
fi
left=$(ls)
expected=$(printf '%s\n' map.csv map.merge.log map.shard-{0,1,2,3}-of-4.csv map.shard-{0,1,2,3}-of-4.log map.slurm-{array,merge,submit}.sh single.csv | sort)
if [ "$left" != "$expected" ]; then
    echo "slurm-local: FAILED: unexpected files left: $left"; exit 1
fi
