#!/usr/bin/env bash
# Long fuzzing runs (docs/ROBUSTNESS.md): builds every fuzz target of tests/fuzz with clang, libFuzzer,
# AddressSanitizer and UndefinedBehaviorSanitizer in build-fuzz/ (the full build, so the GLSL compiler's
# target is included), seeds each target's corpus with the inputs iblx_fuzz generates (its seeds, the saved
# regressions and the inputs of a short mutation run), then runs libFuzzer on each target for SECONDS and
# prints executions, coverage (libFuzzer's edge count "cov" and feature count "ft"), corpus size and time.
# Findings (crash-*, leak-*, timeout-*, oom-* inputs) are left in build-fuzz/findings/TARGET/, logs in
# build-fuzz/logs/; the exit status is non-zero when any target has a finding.
#
#   bash tools/fuzz.sh [SECONDS] [TARGET...]     # default: 60 s for every target
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
[ $# -gt 0 ] && shift
jobs=${IBLX_FUZZ_JOBS:-$(nproc)}

CC=clang-14 CXX=clang++-14 cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" -DIBLX_SANITIZE=ON -DIBLX_LIBFUZZER=ON > build-fuzz.configure.log
rm -f build-fuzz.configure.log
cmake --build build-fuzz -j"$jobs" --target iblx_libfuzzer iblx_fuzz

targets=("$@")
[ ${#targets[@]} -eq 0 ] && mapfile -t targets < <(build-fuzz/iblx_fuzz --list | cut -f1)

# The same limits as the short run (tests/CMakeLists.txt): a 1 GiB memory budget for iblx's own checks; single
# allocations up to 2.1 GB pass, because OpenEXR allocates what a header attribute claims (up to 2 GiB) before
# reading it (tests/fuzz/regressions/exr-opaque-attribute-claims-1.4GiB).
export IBLX_MEMORY_BUDGET_GIB=1 ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
mkdir -p build-fuzz/corpus build-fuzz/findings build-fuzz/logs
build-fuzz/iblx_fuzz --target "$(IFS=,; echo "${targets[*]}")" --iterations 500 --seed 1 \
  --regressions tests/fuzz/regressions --corpus-out build-fuzz/corpus \
  --findings build-fuzz/findings > /dev/null

printf '%-16s %12s %8s %8s %8s %8s %9s\n' target executions cov ft corpus seconds findings
status=0
for target in "${targets[@]}"; do
  mkdir -p "build-fuzz/findings/$target"
  log="build-fuzz/logs/$target.log"
  start=$SECONDS
  IBLX_FUZZ_TARGET=$target build-fuzz/iblx_libfuzzer -max_total_time="$seconds" -print_final_stats=1 \
    -timeout=30 -rss_limit_mb=4096 -malloc_limit_mb=2100 -max_len=1048576 \
    -artifact_prefix="build-fuzz/findings/$target/" "build-fuzz/corpus/$target" > "$log" 2>&1 || status=1
  executions=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  last=$(grep -E '^#[0-9]+' "$log" | tail -1)
  cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<< "$last")
  ft=$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<< "$last")
  corpus=$(find "build-fuzz/corpus/$target" -type f | wc -l)
  findings=$(find "build-fuzz/findings/$target" -type f | wc -l)
  [ "$findings" -gt 0 ] && status=1
  printf '%-16s %12s %8s %8s %8s %8s %9s\n' "$target" "${executions:-?}" "${cov:-?}" "${ft:-?}" "$corpus" \
    "$((SECONDS - start))" "$findings"
done
exit $status
