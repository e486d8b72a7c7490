#!/usr/bin/env bash
# Builds iblx (Release, with tests) and runs the whole test suite: CPU unit tests, GPU tests on the Vulkan device
# present (lavapipe without a GPU), the command-line tests and the fuzz targets' short run; then the sanitizer
# stage. Exits non-zero when any test fails.
#
#   bash tools/test.sh                     # everything (.ci/run calls exactly this)
#   bash tools/test.sh --sanitizers-only   # only the sanitizer stage
# IBLX_JOBS sets the build's parallelism (default: every core).
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=${IBLX_JOBS:-$(nproc)}

# The sanitizer stage: the CPU suites (iblx_io_tests, iblx_sampling_tests, iblx_scene_tests) and the fuzz
# targets' short run in a separate AddressSanitizer + UndefinedBehaviorSanitizer build, build-asan/ (-O1, -g1:
# the line tables the reports' stack traces need, a third less compile time than -g; assertions on), so that a memory error, a leak or undefined behaviour fails the run: -fno-sanitize-recover
# makes UB abort, and ASan halts on its first report. CPU only: the GPU suites run their kernels in lavapipe,
# which is not instrumented, and would take many times the suite's budget under ASan. All of the CPU suites
# run, two at a time: under ASan they take about 65 s here (87 s one after another), so no test case needs to
# be left out. The short run replays 1000 mutated inputs per target (2000 in the Release build), as each ASan
# run of OpenEXR's header allocations costs a few milliseconds.
sanitizer_stage() {
  local started=$SECONDS
  # Chained: `set -e` does not apply inside a function called as `sanitizer_stage || ...`.
  cmake -S . -B build-asan -G Ninja -DIBLX_CPU_ONLY=ON -DIBLX_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DIBLX_FUZZ_SHORT_ITERATIONS=1000 > /dev/null &&
    cmake --build build-asan -j"$jobs" &&
    ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
      ctest --test-dir build-asan -j"$jobs" --output-on-failure --timeout 900 || return 1
  echo "iblx: sanitizer stage passed in $((SECONDS - started)) s"
}

if [ "${1:-}" = "--sanitizers-only" ]; then
  sanitizer_stage
  exit 0
fi

bash tools/install.sh --no-render
status=0
# Validation layers check every GPU test's Vulkan usage when installed (a validation error fails the test).
# The suites that render take turns (their RESOURCE_LOCK, tests/CMakeLists.txt); the CPU suites run beside them.
IBLX_VALIDATION=1 ctest --test-dir build -j"$jobs" --output-on-failure --timeout 1500 || status=1
sanitizer_stage || status=1
exit $status
