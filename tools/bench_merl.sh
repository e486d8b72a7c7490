#!/usr/bin/env bash
# Equal-time error of the MERL sampling methods (issue "Measured BRDFs", benchmark): two synthetic MERL
# materials written by `iblx merl-synth` (GGX alpha = 0.05 metal, Lambert 0.7) under the default environment;
# for each method, the MSE and relMSE over object pixels after the same wall time, median over seeds.
# Usage: tools/bench_merl.sh [SECONDS_PER_RUN (default 10)] [SEEDS (default 3)] [SIZE (default 128)]
# IBLX_BENCH_ENV=FILE uses another environment map (default: assets/default_sky.exr).
set -euo pipefail
iblx="$(cd "$(dirname "$0")/.." && pwd)/build/iblx"
seconds="${1:-10}"
seeds="${2:-3}"
size="${3:-128}"
env=()
[ -n "${IBLX_BENCH_ENV:-}" ] && env=(--env "$IBLX_BENCH_ENV")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

"$iblx" merl-synth --brdf ggx --param roughness=0.05 --param metallic=1 --out "$work/glossy.binary" > /dev/null
"$iblx" merl-synth --brdf lambert --param albedo=0.7 --out "$work/diffuse.binary" > /dev/null

methods=(
  "brdf --brdf-sampler merl-thetah"
  "brdf --brdf-sampler merl-table"
  "env-cdf"
  "mis --env-sampler env-cdf --brdf-sampler merl-thetah"
  "mis --env-sampler env-cdf --brdf-sampler merl-table"
)
# shellcheck source=tools/bench_common.sh
source "$(dirname "$0")/bench_common.sh"

for material in glossy diffuse; do
  brdf="$work/$material.binary"
  start=$(date +%s.%N)
  "$iblx" reference "${env[@]}" --brdf "$brdf" --size "${size}x${size}" --out "$work/$material-ref.exr" > /dev/null 2>&1
  echo "== $material ($(basename "$brdf")) under ${IBLX_BENCH_ENV:-the default sky}, ${size}x${size}, ${seconds} s per run, median of $seeds seeds" \
       "(reference $(awk -v s="$start" -v e="$(date +%s.%N)" 'BEGIN {printf "%.1f", e - s}') s)"
  printf '%-55s %10s %12s %12s\n' "method" "spp" "MSE" "relMSE"
  for m in "${methods[@]}"; do
    equal_time_row "$work" "$seeds" "$m" "${env[@]}" --brdf "$brdf" --size "${size}x${size}" --spp 8 \
      --time "$seconds" --reference-file "$work/$material-ref.exr"
  done
done
