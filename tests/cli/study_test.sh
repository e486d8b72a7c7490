#!/usr/bin/env bash
# `iblx study` from the command line: a plan's errors name the file, line and scene; run ids are stable and
# adding a method keeps the others'; two shards merged equal one process; a failed run is recorded, the others
# go on, and a rerun retries it; and a task interrupted at random points (Ctrl-C, SIGTERM, SIGKILL) then run
# again ends with every run recorded, each with the errors of an uninterrupted run (errors at a fixed spp
# budget are deterministic). The Slurm path is tests/cli/slurm_study_test.sh.
# Usage: study_test.sh path/to/iblx
iblx=$(realpath "$1")
source "$(dirname "$0")/common.sh"
started=$SECONDS
cd "$tmp" || exit 1

# The small plan of common.sh with `sobol`, env-cdf and mis (and a third method when given).
plan_text() {  # DIRECTORY [EXTRA METHOD] (SIZE and SPP from the environment: 16 and 256)
  study_plan "$1" "${SIZE:-16}" "${SPP:-256}" '"sobol"' "\"env-cdf\", \"mis\"${2:+, \"$2\"}"
}
errors() { study_errors "$1"; }
expect_error() {  # EXPECTED-TEXT COMMAND...: exit status 1 and one line holding the text
  local expected="$1" out status
  shift
  out=$("$@" 2>&1)
  status=$?
  [ "$status" -eq 1 ] && [ "$(echo "$out" | wc -l)" -eq 1 ] && echo "$out" | grep -qF -- "$expected" && pass ||
    fail "'$*' (status $status): expected one line with '$expected', got: $out"
}

# The reference: the plan in one process.
plan_text "$tmp/one" > one.toml
"$iblx" study run one.toml > /dev/null 2> one.log && pass || fail "study run: $(cat one.log)"
"$iblx" study merge one.toml > /dev/null 2>&1 && pass || fail "study merge of a complete study"
errors one/study.csv > one.txt
[ "$(head -1 one.txt)" -gt 50 ] && pass || fail "too few error rows: $(head -1 one.txt)"
for f in tables.md study.json report.html lambert/summary.md ggx/converge.csv ggx/relmse_vs_time.png; do
  [ -s "one/$f" ] && pass || fail "merge wrote no $f"
done
grep -q '^## MSE at equal time over the best method' one/tables.md && pass || fail "tables.md has no equal-time matrix"
# Across the two scenes: both methods, each scene's best counted once per measure.
across=$(sed -n '/^## Across the scenes/,/^## Log-log/p' one/tables.md)
[ "$(echo "$across" | grep -c '^| \(env-cdf\|mis\) | sobol | 2 |')" -eq 2 ] &&
  [ "$(echo "$across" | awk -F'|' '/\| sobol \| 2 \|/ { split($5, b, "/"); m += b[1]; r += b[2] } END { print m, r }')" = "2 2" ] &&
  pass || fail "tables.md's table across the scenes: $across"
# A rerun has nothing to do.
out=$("$iblx" study run one.toml 2>&1)  # captured whole: `grep -q` in a pipe would cut the command off
echo "$out" | grep -q '8 runs, 8 already recorded, 0 to measure' && pass || fail "a rerun of a complete study measured again"

# Stable ids; a new method adds runs and renames none.
"$iblx" study plan one.toml 2> /dev/null | cut -d' ' -f1 > ids1.txt
"$iblx" study plan one.toml 2> /dev/null | cut -d' ' -f1 > ids2.txt
plan_text "$tmp/one" env-hier > more.toml
"$iblx" study plan more.toml 2> /dev/null | cut -d' ' -f1 > ids3.txt
[ "$(wc -l < ids1.txt)" -eq 8 ] && cmp -s ids1.txt ids2.txt && pass || fail "study plan lists other ids the second time"
[ "$(wc -l < ids3.txt)" -eq 12 ] && [ -z "$(comm -23 <(sort ids1.txt) <(sort ids3.txt))" ] && pass ||
  fail "adding a method renamed runs"
"$iblx" study plan more.toml 2> /dev/null | grep -c ' missing$' | grep -qx 4 && pass ||
  fail "study plan does not show the added method's 4 runs as missing"
# Flags before the plan; a shard lists its contiguous block.
[ "$("$iblx" study plan --shard 2/2 one.toml 2> /dev/null | cut -d' ' -f1)" = "$(tail -4 ids1.txt)" ] && pass ||
  fail "study plan --shard 2/2 PLAN does not list the last 4 runs"

# Two shards side by side, merged: the same errors.
plan_text "$tmp/shards" > shards.toml
"$iblx" study run shards.toml --shard 1/2 > /dev/null 2> shard1.log &
"$iblx" study run shards.toml --shard 2/2 > /dev/null 2> shard2.log
wait $! && pass || fail "shard 1/2: $(cat shard1.log)"
"$iblx" study merge shards.toml > /dev/null 2>&1 && errors shards/study.csv | cmp -s - one.txt && pass ||
  fail "two shards merged differ from one process"

# The decomposition of each method's equal-time loss against a baseline (engine/analysis/loss_decomposition.h).
{ study_plan "$tmp/decomposed" 16 256 '"random", "sobol"' '"env-cdf", "mis"'; printf '[report]\ndecompose_against = "env-cdf"\n'; } > decomposed.toml
"$iblx" study run decomposed.toml > /dev/null 2>&1 && "$iblx" study merge decomposed.toml > /dev/null 2>&1 &&
  grep -q '^## Where each method loses against env-cdf/sobol at equal time, in factors' decomposed/tables.md &&
  [ "$(grep -c '^- `mis`: R = [0-9.]* = pdf [0-9.]* × QMC [0-9.]* × cost [0-9.]*' decomposed/tables.md)" -eq 2 ] && pass ||
  fail "merge wrote no decomposition of mis against env-cdf on both scenes: $(grep -A3 'Where each' decomposed/tables.md)"

# Plan errors: one line naming the file (and line, scene, flag).
printf 'directory = "x"\nsize = 16\nbogus = 3\n[[scene]]\nname = "a"\n' > bad-key.toml
expect_error "bad-key.toml:3: unknown key 'bogus'" "$iblx" study plan bad-key.toml
printf 'directory = "x"\n[[scene]\nname = "a"\n' > bad-syntax.toml
expect_error "bad-syntax.toml:2:" "$iblx" study plan bad-syntax.toml
printf '[[scene]]\nname = "a"\n' > no-dir.toml
expect_error "no 'directory'" "$iblx" study plan no-dir.toml
printf 'directory = "x"\nmethods = ["nope"]\n[[scene]]\nname = "a"\nbrdf = "lambert"\n' > bad-method.toml
expect_error "scene a: " "$iblx" study plan bad-method.toml
printf 'directory = "x"\n[[scene]]\nname = "a"\n[[scene]]\nname = "a"\n' > twice.toml
expect_error "two scenes are named a" "$iblx" study plan twice.toml
expect_error "--shard 3/2: expected I/N" "$iblx" study run one.toml --shard 3/2
expect_error "--task 0123: no run of the plan" "$iblx" study run one.toml --task 0123
expect_error "no plan file" "$iblx" study merge
expect_error "unknown subcommand 'go'" "$iblx" study go

# A failed run is recorded with its error and the others go on; a rerun retries it.
plan_text "$tmp/failing" > failing.toml
printf '[[scene]]\nname = "later"\nenv = "%s"\n' "$tmp/sky-later.exr" >> failing.toml
"$iblx" study run failing.toml > /dev/null 2> failing.log
[ $? -eq 1 ] && grep -q 'study: 8 runs measured.*, 4 failed' failing.log && pass ||
  fail "a failing scene: $(tail -3 failing.log)"
"$iblx" study merge failing.toml > /dev/null 2> merge-failing.log
[ $? -eq 1 ] && grep -q '4 failed' merge-failing.log && grep -q 'later mis/sobol seed 2: failed: .*sky-later.exr' \
  failing/tables.md && pass || fail "merge does not report the failed runs: $(cat merge-failing.log)"
"$iblx" make-sky --out "$tmp/sky-later.exr" > /dev/null 2>&1
out=$("$iblx" study run failing.toml 2>&1)
echo "$out" | grep -q '12 runs, 8 already recorded, 4 to measure' && pass || fail "a rerun does not retry exactly the failed runs"
"$iblx" study merge failing.toml > /dev/null 2>&1 && pass || fail "the study is not complete after the rerun"

# Interrupted at random points, then run again: complete, and equal to the uninterrupted run. A run in flight
# is dropped, never half-recorded.
export SIZE=32 SPP=1024
plan_text "$tmp/warm" > warm.toml
"$iblx" study run warm.toml > /dev/null 2>&1 || fail "the study that computes the ground truths"
plan_text "$tmp/long" > long.toml
begun=$(date +%s%N)
"$iblx" study run long.toml > /dev/null 2>&1 && pass || fail "the uninterrupted long study"
# Its length with the ground truths cached, in centiseconds: the signals land at random fractions of it,
# whatever this machine's speed.
length=$((($(date +%s%N) - begun) / 10000000))
"$iblx" study merge long.toml > /dev/null 2>&1 || fail "merging the long study"
errors long/study.csv > long.txt
RANDOM=7  # a fixed sequence of signals and delays
outcomes=()
midway=0
signals=(INT TERM KILL)
for try in $(seq 10); do
  plan_text "$tmp/try$try" > "try$try.toml"
  signal=${signals[$((RANDOM % 3))]}
  centiseconds=$((length * (5 + RANDOM % 85) / 100))
  delay=$(printf '%d.%02d' $((centiseconds / 100)) $((centiseconds % 100)))
  "$iblx" study run "try$try.toml" > /dev/null 2> "try$try.log" &
  pid=$!
  sleep "$delay"
  kill -s "$signal" "$pid" 2> /dev/null
  { wait "$pid"; } 2> /dev/null
  status=$?
  recorded=$(find "try$try/runs" -name '*.json' 2> /dev/null | wc -l)
  outcomes+=("SIG$signal after ${delay} s: status $status, $recorded of 8 runs recorded")
  [ "$recorded" -lt 8 ] && midway=$((midway + 1))
  case "$signal:$status" in
    INT:130 | TERM:130 | KILL:137 | TERM:143 | *:0) pass ;;  # 143: ended before the handler was set
    *) fail "try $try: SIG$signal after $delay s: exit status $status: $(tail -2 "try$try.log")" ;;
  esac
  "$iblx" study run "try$try.toml" > /dev/null 2>> "try$try.log" || fail "try $try: the rerun failed"
  "$iblx" study merge "try$try.toml" > /dev/null 2>&1 && errors "try$try/study.csv" | cmp -s - long.txt && pass ||
    fail "try $try (SIG$signal after $delay s): the merged study differs from the uninterrupted one"
done
# The test means something only if most signals landed before the study's end.
[ "$midway" -ge 6 ] && pass || fail "only $midway of 10 signals landed before the study ended"

printf 'interrupted: %s\n' "${outcomes[@]}"
echo "study: $passed passed, $failed failed in $((SECONDS - started)) s"
[ "$failed" -eq 0 ]
