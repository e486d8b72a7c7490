#!/usr/bin/env bash
# Measured formats beyond MERL: load time and equal-time error of the BRDF techniques on fixtures written by
# `iblx measured-synth` (UTIA: BRDF Explorer's anisotropic Ward and GGX alpha = 0.3 metal; MIT .dat: the Ward)
# under the default environment; for each method, the MSE and relMSE over object pixels after the same wall time, median over
# seeds.
# Usage: tools/bench_measured.sh [SECONDS_PER_RUN (default 10)] [SEEDS (default 3)] [SIZE (default 128)]
# IBLX_BENCH_ENV=FILE uses another environment map (default: assets/default_sky.exr).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
iblx="$root/build/iblx"
seconds="${1:-10}"
seeds="${2:-3}"
size="${3:-128}"
env=()
[ -n "${IBLX_BENCH_ENV:-}" ] && env=(--env "$IBLX_BENCH_ENV")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

"$iblx" measured-synth --format utia --brdf "$root/assets/brdf/ward.brdf" --out "$work/ward.bin" > /dev/null
"$iblx" measured-synth --format utia --brdf ggx --param roughness=0.3 --param metallic=1 --out "$work/ggx.bin" > /dev/null
"$iblx" measured-synth --format mit --brdf "$root/assets/brdf/ward.brdf" --out "$work/ward.dat" > /dev/null

# shellcheck source=tools/bench_common.sh
source "$(dirname "$0")/bench_common.sh"

# Load time: --list-methods with the file against the same with a built-in BRDF (both start the process and
# print the registry), median of 5.
elapsed() { local s; s=$(date +%s.%N); "$@" > /dev/null 2>&1; awk -v s="$s" -v e="$(date +%s.%N)" 'BEGIN {print e - s}'; }
for k in 1 2 3 4 5; do elapsed "$iblx" render --list-methods --brdf lambert; done | median > "$work/builtin"
for file in ward.bin ward.dat; do
  for k in 1 2 3 4 5; do elapsed "$iblx" render --list-methods --brdf "$work/$file"; done | median > "$work/file"
  echo "load $file ($(stat -c %s "$work/$file") bytes, checked and converted):" \
    "$(awk -v f="$(cat "$work/file")" -v b="$(cat "$work/builtin")" 'BEGIN {printf "%.1f ms", 1000 * (f - b)}')" \
    "(median of 5, process start subtracted)"
done

methods=(
  "brdf --brdf-sampler cosine"
  "brdf --brdf-sampler brdf-tab"
  "env-cdf"
  "mis --env-sampler env-cdf --brdf-sampler brdf-tab"
)
for material in ward.bin ggx.bin ward.dat; do
  brdf="$work/$material"
  "$iblx" reference "${env[@]}" --brdf "$brdf" --size "${size}x${size}" --out "$work/$material-ref.exr" > /dev/null 2>&1
  echo "== $material under ${IBLX_BENCH_ENV:-the default sky}, ${size}x${size}, ${seconds} s per run, median of $seeds seeds"
  printf '%-55s %10s %12s %12s\n' "method" "spp" "MSE" "relMSE"
  for m in "${methods[@]}"; do
    equal_time_row "$work" "$seeds" "$m" "${env[@]}" --brdf "$brdf" --size "${size}x${size}" --spp 8 --time "$seconds" \
      --reference-file "$work/$material-ref.exr"
  done
done
