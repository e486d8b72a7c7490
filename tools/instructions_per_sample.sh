#!/usr/bin/env bash
# Deterministic cost of a method on lavapipe: x86 instructions per sample, from callgrind's totals for 1 and 3
# passes of a 64x64 render at 64 spp (their difference is two passes of the integrator alone). Unlike timings on a
# shared 2-core machine it does not vary between runs, so it is the figure to compare small changes with.
# Needs valgrind (Debian package valgrind). Usage: tools/instructions_per_sample.sh METHOD [render flags...]
set -euo pipefail
iblx="$(dirname "$0")/../build/iblx"
method="$1"
shift
run() {
  local passes="$1"
  shift
  # LP_NUM_THREADS=0: lavapipe runs in the calling thread, so no spinning worker threads add to the count.
  # MESA_SHADER_CACHE_DISABLE: both runs JIT-compile the pipeline (Mesa's disk cache is written asynchronously,
  # so whether a run finds the entry would otherwise vary).
  MESA_SHADER_CACHE_DISABLE=true LP_NUM_THREADS=0 valgrind --tool=callgrind --callgrind-out-file=/dev/null "$iblx" render --method "$method" \
    --size 64x64 --spp 64 --passes "$passes" --out /tmp/iblx_ips.exr "$@" 2>&1 | awk '/Collected/ {print $4}'
}
# Warm the SPIR-V cache first so no run includes the GLSL compilation.
"$iblx" render --method "$method" --size 8x8 --spp 1 --passes 1 --out /tmp/iblx_ips.exr "$@" > /dev/null
one=$(run 1 "$@")
three=$(run 3 "$@")
json=$("$iblx" render --method "$method" --size 64x64 --spp 64 --passes 2 --json --out /tmp/iblx_ips.exr "$@")
samples=$(sed -E 's/.*"spp": ?([0-9]+).*/\1/' <<< "$json")
pixels=$(sed -E 's/.*"object_pixels": ?([0-9]+).*/\1/' <<< "$json")  # the object's, of the scene given
echo "$method $*: $(( (three - one) / (pixels * samples) )) instructions per sample"
