#!/usr/bin/env bash
# `weft sweep --slurm` on a real SLURM: a single-node cluster (munged, slurmctld, slurmd, no
# systemd) brought up in a temporary folder, then
#   1. a 3-case sweep submitted with sbatch records, case for case, the same bytes as a local
#      `weft sweep` of the same file, and `weft sweep --status` calls it complete;
#   2. a case stopped mid-run the way SLURM warns of a time limit (SIGTERM to the batch shell,
#      `--signal=B:TERM@...`) checkpoints, requeues itself, resumes from its checkpoint and ends
#      byte-identical to an uninterrupted local run.
# With --time-limit, step 2 lets SLURM's own time limit do it instead (`sbatch --time=2
# --signal=B:TERM@30` on a case of about 100 s; slow, about 5 minutes in all).
#
# Usage: tests/slurm/test_slurm.sh PATH/TO/weft [--time-limit]
# Installs slurm-wlm and munge with apt-get when they are missing (as root). Prints "SKIPPED: ..."
# and exits 0 when they cannot be installed or the daemons cannot start; every wait is bounded.
set -uo pipefail

weft=$(readlink -f "${1:?usage: test_slurm.sh PATH/TO/weft [--time-limit]}")
time_limit=0
[[ ${2:-} == --time-limit ]] && time_limit=1
root=$(cd "$(dirname "$0")/../.." && pwd)
start=$SECONDS

skip() {
  echo "SKIPPED: $*"
  exit 0
}
fail() {
  echo "FAILED: $*"
  for log in "${tmp:-/nonexistent}"/*.log; do [[ -f $log ]] && { echo "--- $log"; tail -n 20 "$log"; }; done
  exit 1
}
say() { echo "[$((SECONDS - start)) s] $*"; }
# Runs "$@" until it succeeds or `limit` seconds have passed.
wait_until() {
  local limit=$1 end=$((SECONDS + $1))
  shift
  until "$@"; do
    ((SECONDS < end)) || return 1
    sleep 0.5
  done
}

[[ -x $weft ]] || fail "$weft is not an executable"

# --- Packages --------------------------------------------------------------------------------
if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
  [[ $(id -u) == 0 ]] || skip "slurm-wlm and munge are not installed, and installing them needs root"
  say "installing slurm-wlm and munge"
  # Bounded so that ctest's 900 s are never reached: 300 s to install, 120 s to update first.
  if ! timeout 300 apt-get -o DPkg::Lock::Timeout=240 install -y slurm-wlm munge >/dev/null 2>&1; then
    timeout 120 apt-get -o DPkg::Lock::Timeout=60 update >/dev/null 2>&1
    timeout 300 apt-get -o DPkg::Lock::Timeout=240 install -y slurm-wlm munge >/dev/null 2>&1 ||
      skip "apt-get cannot install slurm-wlm munge"
  fi
fi
[[ $(id -u) == 0 ]] || skip "slurmd must run as root"

# --- A single-node cluster in a temporary folder ----------------------------------------------
tmp=$(mktemp -d /tmp/weft_slurm.XXXXXX)
chmod 755 "$tmp" # munged wants its socket's folders searchable by all
pid_files=("$tmp/slurmd.pid" "$tmp/slurmctld.pid" "$tmp/munge/munged.pid")
teardown() {
  if [[ -f $tmp/slurm.conf ]]; then
    local jobs
    jobs=$(timeout 10 squeue -h -o %A 2>/dev/null | sort -u)
    [[ -n $jobs ]] && timeout 10 scancel $jobs 2>/dev/null
  fi
  local pids=() file
  for file in "${pid_files[@]}"; do [[ -s $file ]] && pids+=("$(cat "$file")"); done
  ((${#pids[@]})) && kill "${pids[@]}" 2>/dev/null
  local end=$((SECONDS + 10)) pid
  for pid in "${pids[@]}"; do
    while kill -0 "$pid" 2>/dev/null && ((SECONDS < end)); do sleep 0.2; done
    kill -0 "$pid" 2>/dev/null && kill -9 "$pid" 2>/dev/null
  done
  [[ -n ${KEEP_SLURM_TMP:-} ]] && echo "kept $tmp" || rm -rf "$tmp"
}
trap teardown EXIT

mkdir -p "$tmp/munge/key" "$tmp/state" "$tmp/spool"
chmod 700 "$tmp/munge/key"
dd if=/dev/urandom bs=1024 count=1 of="$tmp/munge/key/munge.key" status=none
chmod 400 "$tmp/munge/key/munge.key"
socket=$tmp/munge/munge.socket
munged --key-file="$tmp/munge/key/munge.key" --socket="$socket" --pid-file="$tmp/munge/munged.pid" \
  --log-file="$tmp/munged.log" --seed-file="$tmp/munge/key/seed" ||
  skip "munged does not start: $(tail -n 1 "$tmp/munged.log" 2>/dev/null)"
wait_until 10 test -S "$socket" || skip "munged made no socket in 10 s"

host=$(hostname -s)
memory=$(($(free -m | awk '/^Mem:/ {print $2}') * 8 / 10))
port=$((20000 + RANDOM % 20000))
export SLURM_CONF=$tmp/slurm.conf
cat >"$SLURM_CONF" <<EOF
ClusterName=weft-test
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$port
SlurmdPort=$((port + 1))
AuthType=auth/munge
AuthInfo=socket=$socket,cred_expire=10
CredType=cred/munge
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/slurmctld.pid
SlurmdPidFile=$tmp/slurmd.pid
SlurmctldLogFile=$tmp/slurmctld.log
SlurmdLogFile=$tmp/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SwitchType=switch/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MinJobAge=600
NodeName=$host NodeAddr=127.0.0.1 CPUs=$(nproc) RealMemory=$memory State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
slurmctld -f "$SLURM_CONF" || skip "slurmctld does not start: $(tail -n 1 "$tmp/slurmctld.log" 2>/dev/null)"
slurmd -f "$SLURM_CONF" || skip "slurmd does not start: $(tail -n 1 "$tmp/slurmd.log" 2>/dev/null)"
node_idle() { timeout 5 sinfo -h -o %T 2>/dev/null | grep -q idle; }
wait_until 30 node_idle || skip "the node is not idle after 30 s: $(timeout 5 sinfo -h 2>&1 | head -n 1)"
[[ $(timeout 20 srun -N1 hostname 2>/dev/null) == "$host" ]] || skip "srun hostname does not run"
say "SLURM $(sinfo -V | cut -d' ' -f2) up on $host, $(nproc) CPUs"

# --- Helpers ------------------------------------------------------------------------------------
queue_empty() { [[ -z $(timeout 10 squeue -h -j "$1" 2>/dev/null) ]]; }
# A field of `scontrol show job` (Restarts, JobState, ...).
job_field() { timeout 10 scontrol show job "$1" 2>/dev/null | tr ' ' '\n' | sed -n "s/^$2=//p" | head -n 1; }
stats_rows() { [[ -f $1/stats.csv ]] && echo $(($(wc -l <"$1/stats.csv") - 1)) || echo 0; }
# Each case's .pc2 in sweep folder $1 equals the one in $2, byte for byte.
same_recordings() {
  local case_dir name n=0
  for case_dir in "$1"/[0-9][0-9][0-9]_*/; do
    name=$(basename "$case_dir")
    cmp -s "$case_dir/cloth.pc2" "$2/$name/cloth.pc2" || fail "$name: cloth.pc2 differs from the local run's"
    n=$((n + 1))
  done
  ((n > 0)) || fail "no cases in $1"
  echo "$n"
}

# --- 1. A sweep through sbatch against the same sweep run locally -------------------------------
cat >"$tmp/grid.json" <<EOF
{"scene": "$root/scenes/default.json", "frames": 30, "set": ["cloths.0.grid.resolution=[8,8]"],
 "grid": {"cloths.0.mass_damping": [0.1, 0.2, 0.3]},
 "slurm": {"time": "00:05:00", "memory": "100M"}}
EOF
script=$("$weft" sweep "$tmp/grid.json" --out "$tmp/grid" --slurm 2>/dev/null) || fail "weft sweep --slurm"
began=$SECONDS
job=$(timeout 10 sbatch --parsable "$script") || fail "sbatch $script"
wait_until 120 queue_empty "$job" || fail "job $job still queued after 120 s"
slurm_seconds=$((SECONDS - began))
status=$("$weft" sweep "$tmp/grid.json" --out "$tmp/grid" --status) ||
  fail "weft sweep --status after the array job: $status"
grep -q "grid: 3 of 3 complete" <<<"$status" || fail "status: $status"
began=$SECONDS
"$weft" sweep "$tmp/grid.json" --out "$tmp/grid_local" 2>"$tmp/grid_local.log" || fail "the local sweep"
local_seconds=$((SECONDS - began))
say "3 cases: array job $job in ${slurm_seconds} s, locally in ${local_seconds} s;" \
  "$(same_recordings "$tmp/grid" "$tmp/grid_local") .pc2 files byte-identical"

# --- 2. A case stopped before its time limit requeues itself and resumes ------------------------
if ((time_limit)); then frames=4000; else frames=800; fi
cat >"$tmp/long.json" <<EOF
{"scene": "$root/scenes/default.json", "frames": $frames, "set": ["cloths.0.grid.resolution=[16,16]"],
 "grid": {"cloths.0.mass_damping": [0.1]}, "slurm": {"time": "00:05:00", "memory": "100M"}}
EOF
script=$("$weft" sweep "$tmp/long.json" --out "$tmp/long" --slurm 2>/dev/null) || fail "weft sweep --slurm"
case_dir=$tmp/long/000_mass_damping-0.1
began=$SECONDS
if ((time_limit)); then
  # SLURM's own warning: SIGTERM to the batch shell 30 s before a 2-minute limit, or up to 60 s
  # earlier (SLURM checks every 30 s and sends it when due within the next 30 s), then the
  # script requeues the case; each run goes further.
  job=$(timeout 10 sbatch --parsable --time=2 --signal=B:TERM@30 "$script") || fail "sbatch $script"
  wait_until 600 queue_empty "$job" || fail "job $job still queued after 600 s"
else
  job=$(timeout 10 sbatch --parsable "$script") || fail "sbatch $script"
  past_frame() { (($(stats_rows "$case_dir") > $1)); }
  wait_until 60 past_frame 200 || fail "the case wrote no 200 frames in 60 s"
  status=$("$weft" sweep "$tmp/long.json" --out "$tmp/long" --status)
  grep -q "000_mass_damping-0.1  running on $host, pid [0-9]*: frame [0-9]* of $frames" <<<"$status" ||
    fail "status while the task runs: $status"
  # What --signal=B:TERM@... does before the time limit.
  timeout 10 scancel --batch --signal=TERM "${job}_0" || fail "scancel --signal=TERM"
  requeued() { [[ $(job_field "${job}_0" Restarts) -ge 1 && $(job_field "${job}_0" JobState) == PENDING ]]; }
  wait_until 60 requeued || fail "job ${job}_0 was not requeued: $(job_field "${job}_0" JobState)"
  stopped_at=$(stats_rows "$case_dir")
  status=$("$weft" sweep "$tmp/long.json" --out "$tmp/long" --status)
  grep -q "interrupted after frame $((stopped_at - 1)) of $frames; resumable from its checkpoint at frame $((stopped_at - 1))" <<<"$status" ||
    fail "status while the task waits in the queue: $status"
  say "stopped after frame $((stopped_at - 1)) of $frames; requeued, eligible at $(job_field "${job}_0" EligibleTime)"
  wait_until 180 queue_empty "$job" || fail "job $job still queued 180 s after its requeue"
fi
slurm_seconds=$((SECONDS - began))
restarts=$(job_field "${job}_0" Restarts)
log=$(cat "$tmp"/long/logs/*.log)
grep -q "requeueing ${job}_0" <<<"$log" || fail "the log does not say it requeued: $log"
grep -q "weft: resumed from frame " <<<"$log" || fail "the log does not say it resumed: $log"
[[ $restarts -ge 1 ]] || fail "Restarts=$restarts"
status=$("$weft" sweep "$tmp/long.json" --out "$tmp/long" --status) || fail "status after the requeue: $status"
began=$SECONDS
"$weft" sweep "$tmp/long.json" --out "$tmp/long_local" 2>"$tmp/long_local.log" || fail "the local long case"
local_seconds=$((SECONDS - began))
same_recordings "$tmp/long" "$tmp/long_local" >/dev/null
say "$frames frames: $restarts requeue(s) ($(grep -o 'resumed from frame [0-9]*' <<<"$log" | paste -sd, -))," \
  "${slurm_seconds} s through SLURM, ${local_seconds} s locally uninterrupted; .pc2 byte-identical"
echo "PASSED in $((SECONDS - start)) s"
