#!/usr/bin/env bash
# Submits an `iblx study` to Slurm: a job array of N tasks (tools/slurm/study.sbatch, one GPU each, task I
# measuring --shard I/N) and a merge job that starts once every task has ended (afterany: a merge over a
# failed task reports its missing runs; requeue the task, or submit again, and merge again). Prints the two
# job ids. Extra arguments go to both sbatch calls (e.g. --partition=gpu --time=4:00:00).
# Usage: tools/slurm/submit.sh PLAN N [SBATCH OPTIONS...]
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
[ $# -ge 2 ] || { sed -n 's/^# \{0,1\}Usage: //p' "$0" >&2; exit 2; }
plan=$(realpath "$1")
shards=$2
shift 2
[ -f "$plan" ] || { echo "submit.sh: $plan: no such plan" >&2; exit 2; }
[[ "$shards" =~ ^[1-9][0-9]*$ ]] || { echo "submit.sh: N must be a positive number of tasks, not '$shards'" >&2; exit 2; }
command -v sbatch > /dev/null || { echo "submit.sh: sbatch not found: run this on a Slurm login node" >&2; exit 2; }
array=$(IBLX_PLAN="$plan" IBLX_SHARDS="$shards" sbatch --parsable --export=ALL --array="1-$shards" "$@" \
  "$here/study.sbatch")
array=${array%%;*}
merge=$(IBLX_PLAN="$plan" sbatch --parsable --export=ALL --dependency="afterany:$array" --gres=none \
  --job-name=iblx-study-merge --output="iblx-study-merge-%j.out" "$@" "$here/study.sbatch" merge)
merge=${merge%%;*}
echo "array $array ($shards tasks), merge $merge"
