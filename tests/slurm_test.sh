#!/bin/bash
# The Slurm scripts (scripts/slurm/) on a real single-node Slurm: munged, slurmctld and slurmd
# started here, configured in a temporary directory on ports of their own (no system
# configuration read or changed), each stopped by its PID at the end. A 4-task job array of
# `sglab sweep specular --quick` shards and the merge job chained by afterok (submit_sweep.sh) must
# give the tables an unsharded run gives, byte for byte below their headers and but for the --out
# their command lines name, and the same per-point CSV; each shard runs within the one CPU it was given, and the
# merged manifest labels its summed seconds. Exit 77 (skipped) only when the daemons cannot start.
# Environment: SGLAB_EXE (the sglab binary), SGLAB_SOURCE_DIR (the checkout).
set -uo pipefail
exe=${SGLAB_EXE:?}
src=${SGLAB_SOURCE_DIR:?}
skip() { echo "SKIPPED: $*" >&2; exit 77; }
fail() { echo "FAILED: $*" >&2; for f in "$t"/*.log; do echo "== $f" >&2; tail -n 20 "$f" >&2; done; exit 1; }
for tool in munged munge slurmctld slurmd sbatch scontrol sinfo; do
  command -v "$tool" > /dev/null || skip "$tool is not installed (scripts/setup.sh --tests installs slurm-wlm and munge)"
done

t=$(mktemp -d /tmp/sglab-slurm-XXXXXX)
chmod 711 "$t"  # munged refuses a socket in a directory others cannot reach
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2> /dev/null; done
  for p in "${pids[@]}"; do wait "$p" 2> /dev/null; done
  rm -rf "$t"
}
trap cleanup EXIT
start=$SECONDS

# The same sweep unsharded, the reference of the merged one: started first, in the background, so
# that it runs while the daemons start and wait on the jobs (its one thread beside the shards' one
# CPU each; the values do not depend on the thread count).
mkdir "$t/whole_run" || fail "no directory for the unsharded run"
(cd "$t/whole_run" && exec "$exe" sweep specular --quick --out whole > /dev/null 2> whole.log) &
whole_pid=$!
pids+=($whole_pid)

# munge: a fresh key, its own socket.
head -c 1024 /dev/urandom > "$t/munge.key" && chmod 400 "$t/munge.key"
munged -F -f --key-file="$t/munge.key" --socket="$t/munge.socket" --pid-file="$t/munged.pid" \
  --log-file="$t/munged.log" --seed-file="$t/munged.seed" &
pids+=($!)
for _ in $(seq 250); do [ -S "$t/munge.socket" ] && break; sleep 0.02; done
munge -S "$t/munge.socket" -n > /dev/null 2>&1 || skip "munged did not start (see its log: $(tail -n 3 "$t/munged.log" 2> /dev/null))"

# Slurm: one node (this machine, as 127.0.0.1), one partition, no accounting, no cgroups. The
# scheduler's main loop every second (sched_interval, default 60 s): Slurm 22.05 started the array's
# next tasks and the merge job whose dependency had just been met only on that loop or after a
# delay of its own (measured with trivial jobs: 2.6 s between the two pairs of shards, 2.7 s from
# the last shard's end to the merge; with the 1 s loop, 1.0 s each).
node=$(hostname -s)
port=$((20000 + 2 * ($$ % 10000)))
user=$(id -un)
mkdir -p "$t/state" "$t/spool"
cat > "$t/slurm.conf" << CONF
ClusterName=sglabtest
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$port
SlurmdPort=$((port + 1))
AuthType=auth/munge
AuthInfo=socket=$t/munge.socket
CredType=cred/munge
SlurmUser=$user
SlurmdUser=$user
StateSaveLocation=$t/state
SlurmdSpoolDir=$t/spool
SlurmctldPidFile=$t/slurmctld.pid
SlurmdPidFile=$t/slurmd.pid
SlurmctldLogFile=$t/slurmctld.log
SlurmdLogFile=$t/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/builtin
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
MpiDefault=none
PlugStackConfig=/dev/null
ReturnToService=2
MinJobAge=600
KillWait=2
SchedulerParameters=sched_interval=1
NodeName=$node NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=sglabtest Nodes=$node Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$t/slurm.conf
slurmctld -D -i -f "$SLURM_CONF" > "$t/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" -N "$node" > "$t/slurmd.out" 2>&1 &
pids+=($!)
for _ in $(seq 400); do [ "$(sinfo -h -o %t 2> /dev/null)" = idle ] && break; sleep 0.05; done
[ "$(sinfo -h -o %t 2> /dev/null)" = idle ] ||
  skip "the Slurm daemons did not start: $(tail -n 3 "$t/slurmctld.log" "$t/slurmd.log" 2> /dev/null | tr '\n' ' ')"
echo "slurm up in $((SECONDS - start)) s (node $node, ports $port/$((port + 1)))"

# The sharded sweep on Slurm, from a working directory holding nothing but what it writes.
mkdir "$t/work" && cd "$t/work" || fail "no work directory"
ids=$(SGLAB="$exe" SGLAB_CPUS=1 "$src/scripts/slurm/submit_sweep.sh" 4 merged specular --quick) || fail "submit_sweep.sh: $ids"
read -r array merge <<< "$ids"
echo "array job $array, merge job $merge"
state=""
# Slurm is asked once a second (each scontrol costs CPU beside the jobs), and every 0.1 s once the
# merge has written its manifest (its last file); a failed or cancelled job is seen within a second.
for i in $(seq 600); do
  if [ -f merged/specular_sweep.json ] || [ $((i % 10)) -eq 0 ]; then
    state=$(scontrol show job "$merge" -o 2> /dev/null | grep -o 'JobState=[A-Z_]*' | cut -d= -f2)
    case "$state" in COMPLETED | FAILED | CANCELLED | TIMEOUT | NODE_FAIL | OUT_OF_MEMORY) break ;; esac
  fi
  sleep 0.1
done
[ "$state" = COMPLETED ] || fail "the merge job ended $state"
for i in 0 1 2 3; do
  log=$(ls sglab-sweep-"${array}"_"$i".log 2> /dev/null) || fail "no log of shard $i"
  grep -q "within the 1 CPU(s) given" "$log" || fail "shard $i did not keep to its one CPU: $(cat "$log")"
done

# The unsharded run started at the top.
wait "$whole_pid" || fail "the unsharded sweep: $(cat "$t/whole_run/whole.log")"
mv "$t/whole_run/whole" whole || fail "no output of the unsharded sweep"
# Below the header lines, with the --out each command line names set aside (the tables quote their command).
body() { grep -v '^#' "$1" | grep -v '^<!--' | sed -E 's/--out [^ `]+/--out OUT/g'; }
for f in specular_vs_roughness.csv specular_vs_roughness.md specular_summary.csv specular_points.csv; do
  [ -f "merged/$f" ] || fail "the merge wrote no $f"
  cmp -s <(body "merged/$f") <(body "whole/$f") || fail "merged $f differs from the unsharded run's: $(diff <(body merged/$f) <(body whole/$f) | head -5)"
done
grep -q '"seconds_are": "the sum of the 4 shards' merged/specular_sweep.json || fail "the merged manifest does not label its seconds: $(cat merged/specular_sweep.json)"
echo "slurm round trip: 4 shards + merge equal to the unsharded sweep; $((SECONDS - start)) s in all"
