#!/usr/bin/env bash
# `iblx study` on a real Slurm: a one-node cluster from Debian's packages (munged, slurmctld, slurmd, all on
# loopback ports of their own, state in a temporary folder) with four GPU slots (GRES on /dev/null: the
# tasks render on the machine's Vulkan device). tools/slurm/submit.sh submits a small plan as an array of
# three tasks plus the dependent merge. Shard 2's iblx is killed with SIGKILL after its first recorded run and
# the task fails, as on a lost node; the merge must then name the missing runs. Then the recovery submit.sh
# documents: the failed task is requeued and merged again. The study must end complete, the requeued task
# must not measure again what was recorded, and the merged errors (deterministic at a fixed spp budget) must
# equal those of the same plan run in one process. Every daemon started is stopped. (Requeueing the task
# while it ran raced with its end: under load Slurm could end it FAILED instead of pending again.)
# Usage: slurm_study_test.sh path/to/iblx
iblx=$(realpath "$1")
source "$(dirname "$0")/common.sh"
root=$(cd "$(dirname "$0")/../.." && pwd)
for program in munged slurmctld slurmd sbatch scontrol squeue; do
  command -v "$program" > /dev/null || { echo "FAIL: $program missing (tools/install.sh installs Slurm and munge)"; exit 1; }
done
started=$SECONDS
cluster="$tmp/cluster"
mkdir -p "$cluster/munge" "$cluster/state" "$cluster/spool" "$cluster/log" "$tmp/work"
chmod 700 "$cluster/munge"
# The daemons run in the foreground as this script's children, so that it stops and reaps each one.
daemons=()
stop_cluster() {
  # This cluster's jobs first (SLURM_CONF names it), so that no job step outlives the daemons.
  if [ ${#daemons[@]} -gt 1 ] && [ -n "${SLURM_CONF:-}" ]; then
    scancel --full --quiet --user="$(id -un)" 2> /dev/null
    for _ in $(seq 50); do [ -z "$(squeue -h 2> /dev/null)" ] && break; sleep 0.1; done
  fi
  for ((i = ${#daemons[@]} - 1; i >= 0; --i)); do kill "${daemons[i]}" 2> /dev/null; done
  for pid in "${daemons[@]}"; do
    for _ in $(seq 50); do kill -0 "$pid" 2> /dev/null || break; sleep 0.1; done
    kill -KILL "$pid" 2> /dev/null
    wait "$pid" 2> /dev/null
  done
  rm -rf "$tmp"
}
trap stop_cluster EXIT

# munge: a fresh key and a socket of this test's own.
head -c 1024 /dev/urandom > "$cluster/munge/munge.key"
chmod 400 "$cluster/munge/munge.key"
munged --foreground --force --socket="$cluster/munge/socket" --key-file="$cluster/munge/munge.key" \
  --pid-file="$cluster/munge/munged.pid" --log-file="$cluster/munge/munged.log" --seed-file="$cluster/munge/seed" \
  > /dev/null 2>&1 &
daemons+=($!)
for _ in $(seq 50); do [ -S "$cluster/munge/socket" ] && break; sleep 0.1; done
[ -S "$cluster/munge/socket" ] || { echo "FAIL: munged did not start: $(cat "$cluster/munge/munged.log")"; exit 1; }

# Two free loopback ports.
free_port() {
  local port
  while :; do
    port=$((20000 + RANDOM % 20000))
    (exec 3<> "/dev/tcp/127.0.0.1/$port") 2> /dev/null || { echo "$port"; return; }
  done
}
ctld_port=$(free_port)
slurmd_port=$(free_port)
while [ "$slurmd_port" = "$ctld_port" ]; do slurmd_port=$(free_port); done
node=$(hostname -s)
for i in 0 1 2 3; do ln -s /dev/null "$cluster/gpu$i"; done
cat > "$cluster/slurm.conf" << EOF
ClusterName=iblxtest
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=$(id -un)
SlurmdUser=$(id -un)
AuthType=auth/munge
AuthInfo=socket=$cluster/munge/socket
CredType=cred/munge
StateSaveLocation=$cluster/state
SlurmdSpoolDir=$cluster/spool
SlurmctldPidFile=$cluster/slurmctld.pid
SlurmdPidFile=$cluster/slurmd.pid
SlurmctldLogFile=$cluster/log/slurmctld.log
SlurmdLogFile=$cluster/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MinJobAge=600
GresTypes=gpu
NodeName=$node NodeAddr=127.0.0.1 CPUs=$(nproc) Gres=gpu:4 State=UNKNOWN
PartitionName=iblx Nodes=ALL Default=YES MaxTime=INFINITE State=UP OverSubscribe=YES
EOF
printf 'AutoDetect=off\nNodeName=%s Name=gpu File=%s/gpu[0-3]\n' "$node" "$cluster" > "$cluster/gres.conf"
export SLURM_CONF="$cluster/slurm.conf"
slurmctld -D -c -f "$SLURM_CONF" > /dev/null 2>&1 &
daemons+=($!)
slurmd -D -f "$SLURM_CONF" > /dev/null 2>&1 &
daemons+=($!)
for _ in $(seq 100); do
  sinfo -h -o %T 2> /dev/null | grep -qx idle && break
  sleep 0.2
done
sinfo -h -o %T | grep -qx idle && pass || { fail "the node did not come up: $(sinfo 2>&1; tail -5 "$cluster/log/slurmctld.log")"; exit 1; }

# The plan: common.sh's two scenes x env-cdf and mis x random and sobol x two seeds, a fixed spp budget.
plan_text() { study_plan "$1" 24 512 '"random", "sobol"' '"env-cdf", "mis"'; }
plan_text "$tmp/work/cluster-study" > "$tmp/work/plan.toml"
plan_text "$tmp/work/one-process" > "$tmp/work/one.toml"

# Shard 2's first attempt is killed after its first recorded run and fails.
cat > "$tmp/work/iblx-wrapper.sh" << EOF
#!/usr/bin/env bash
if [[ "\$*" == *"--shard 2/3"* && ! -e "$tmp/work/killed" ]]; then
  "$iblx" "\$@" 2> "$tmp/work/shard2-first.log" &
  pid=\$!
  until grep -q 'study: \[1/' "$tmp/work/shard2-first.log" 2> /dev/null || ! kill -0 \$pid 2> /dev/null; do sleep 0.02; done
  kill -KILL \$pid
  wait \$pid
  echo \$? > "$tmp/work/killed"
  exit 1
fi
exec "$iblx" "\$@"
EOF
chmod +x "$tmp/work/iblx-wrapper.sh"

cd "$tmp/work" || exit 1
submitted=$(IBLX_BINARY="$tmp/work/iblx-wrapper.sh" "$root/tools/slurm/submit.sh" plan.toml 3 --cpus-per-task=1 2>&1)
echo "$submitted" | grep -qE '^array [0-9]+ \(3 tasks\), merge [0-9]+$' && pass || fail "submit.sh: $submitted"
array=$(echo "$submitted" | sed -nE 's/^array ([0-9]+).*/\1/p')
merge=$(echo "$submitted" | sed -nE 's/.*merge ([0-9]+)$/\1/p')

# Meanwhile the same plan in one process: the expected result.
"$iblx" study run one.toml > /dev/null 2>&1 && "$iblx" study merge one.toml > /dev/null 2>&1 && pass ||
  fail "the plan did not run in one process"

# An empty queue, from an squeue that answered (a busy controller's failed call prints nothing too).
wait_for_empty_queue() {
  local jobs
  for _ in $(seq 1800); do
    jobs=$(squeue -h 2> /dev/null) && [ -z "$jobs" ] && break
    sleep 0.1
  done
  jobs=$(squeue -h 2>&1) && [ -z "$jobs" ] && pass || fail "jobs still queued after 3 min: $jobs"
}
state() { scontrol show job "$1" 2> /dev/null | sed -nE 's/.*JobState=([A-Z_]+).*/\1/p' | head -1; }
wait_for_empty_queue
[ "$(cat killed 2> /dev/null)" = 137 ] && pass || fail "shard 2 was not killed mid-run ($(cat killed 2> /dev/null))"
for task in 1 3; do
  [ "$(state "${array}_$task")" = COMPLETED ] && pass || fail "task $task ended $(state "${array}_$task")"
done
[ "$(state "${array}_2")" = FAILED ] && pass || fail "the killed task 2 ended $(state "${array}_2")"
# The merge ran once the array had ended, and names what the failed task left unmeasured.
[ "$(state "$merge")" = FAILED ] && grep -q "runs missing" "iblx-study-merge-$merge.out" && pass ||
  fail "the merge over a failed task ended $(state "$merge"): $(cat "iblx-study-merge-$merge.out")"

# The recovery: requeue the failed task, and merge again once it has ended.
scontrol requeue "${array}_2" && pass || fail "scontrol requeue ${array}_2"
for _ in $(seq 100); do
  squeue -h -j "${array}_2" -o %T 2> /dev/null | grep -q PENDING && break
  sleep 0.1
done
# A requeued job waits before it may start again; now.
scontrol update jobid="${array}_2" StartTime=now > /dev/null 2>&1
remerge=$(IBLX_PLAN="$tmp/work/plan.toml" IBLX_BINARY="$iblx" sbatch --parsable --export=ALL --dependency="afterany:${array}_2" \
  --gres=none --job-name=iblx-study-merge --output="iblx-study-merge-%j.out" "$root/tools/slurm/study.sbatch" \
  merge 2>&1)
remerge=${remerge%%;*}
[[ "$remerge" =~ ^[0-9]+$ ]] && pass || fail "sbatch of the second merge: $remerge"
wait_for_empty_queue
[ "$(state "${array}_2")" = COMPLETED ] && pass || fail "the requeued task 2 ended $(state "${array}_2")"
[ "$(state "$remerge")" = COMPLETED ] && pass ||
  fail "the second merge ended $(state "$remerge"): $(cat "iblx-study-merge-$remerge.out")"
# The requeued task measured only what the killed attempt had not recorded.
recorded=$(sed -nE 's/.*: ([0-9]+) runs, ([0-9]+) already recorded.*/\2/p' "iblx-study-${array}_2.out" | tail -1)
[ -n "$recorded" ] && [ "$recorded" -ge 1 ] && pass ||
  fail "the requeued task did not keep the killed attempt's runs: $(cat "iblx-study-${array}_2.out")"
grep -q "attempt 2" "iblx-study-${array}_2.out" && pass ||
  fail "task 2 did not run a second time: $(cat "iblx-study-${array}_2.out")"

# Nothing lost: every run merged, with the errors of the one-process run at every recorded spp.
grep -q '"missing": 0' cluster-study/study.json && grep -q '"failed": 0' cluster-study/study.json && pass ||
  fail "the merged study is incomplete: $(grep -o '"done": [0-9]*, "skipped": [0-9]*, "failed": [0-9]*, "missing": [0-9]*' cluster-study/study.json)"
study_errors cluster-study/study.csv > cluster.txt
study_errors one-process/study.csv > one.txt
[ "$(head -1 cluster.txt)" -gt 100 ] && cmp -s cluster.txt one.txt && pass ||
  fail "the merged errors differ from the one-process run: $(diff cluster.txt one.txt | head -5)"
# The tables' error columns likewise (times differ between runs; the matrices of equal-time ratios need not).
grep -c '^| ' cluster-study/tables.md > /dev/null && pass || fail "no tables in the merged tables.md"

echo "slurm study: $passed passed, $failed failed in $((SECONDS - started)) s"
[ "$failed" -eq 0 ]
