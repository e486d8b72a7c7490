#!/usr/bin/env bash
# Sampling quality of the BRDF techniques on BRDF Explorer files (issue "BRDF Explorer compatibility",
# benchmark): for library BRDFs of assets/brdf/, the variance per sample (MSE x spp at a fixed spp, against the
# convolution reference) of `brdf` with cosine, brdf-tab and the file's own isfunc, and of `mis` (env-cdf +
# the default sampler), under a sky without its sun (BRDF sampling's home ground) - median over seeds - plus
# brdf-tab's build time (the render's setup_s minus that of cosine).
# Usage: tools/bench_brdf_files.sh [SPP (default 256)] [SEEDS (default 3)] [SIZE (default 96)]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
iblx="$root/build/iblx"
spp="${1:-256}"
seeds="${2:-3}"
size="${3:-96}"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$iblx" make-sky --sun-radiance 0 --size 128x64 --out "$work/sky.exr" > /dev/null

# name | file | parameters
cases=(
  "phong n=200|phong.brdf|--param exponent=200"
  "blinn-phong n=500|blinn_phong.brdf|--param exponent=500"
  "ward 0.05 x 0.3 (anisotropic)|ward.brdf|--param alphaX=0.05 --param alphaY=0.3"
  "cook-torrance m=0.1|cook_torrance.brdf|--param m=0.1"
  "ggx a=0.1|ggx.brdf|--param alpha=0.1"
  "disney rough=0.3|disney.brdf|--param roughness=0.3"
  "oren-nayar|oren_nayar.brdf|"
)
# shellcheck source=tools/bench_common.sh
source "$(dirname "$0")/bench_common.sh"

printf '%-32s %-44s %14s %12s %10s\n' "BRDF" "method" "MSE x spp" "Msamples/s" "setup s"
for c in "${cases[@]}"; do
  IFS='|' read -r name file params <<< "$c"
  brdf="$root/assets/brdf/$file"
  # shellcheck disable=SC2086
  "$iblx" reference --env "$work/sky.exr" --brdf "$brdf" $params --size "${size}x${size}" --out "$work/ref.exr" > /dev/null 2>&1
  methods=("brdf --brdf-sampler cosine" "brdf --brdf-sampler brdf-tab")
  # shellcheck disable=SC2086
  if "$iblx" render --brdf "$brdf" --list-methods 2>/dev/null | grep -q "best sampler: isfunc"; then
    methods+=("brdf --brdf-sampler isfunc")
  fi
  methods+=("mis")
  for m in "${methods[@]}"; do
    : > "$work/runs"
    for seed in $(seq 1 "$seeds"); do
      # shellcheck disable=SC2086
      "$iblx" render --env "$work/sky.exr" --brdf "$brdf" $params --method $m --size "${size}x${size}" \
        --spp "$((spp / 8))" --passes 8 --seed "$seed" --reference-file "$work/ref.exr" --json --out "$work/out.exr" \
        2>/dev/null >> "$work/runs"
    done
    mse=$(field mse < "$work/runs" | median)
    printf '%-32s %-44s %14.4g %12s %10s\n' "$name" "$(head -1 "$work/runs" | sed -E 's/.*"method": "([^"]*)".*/\1/')" \
      "$(awk -v m="$mse" -v s="$spp" 'BEGIN {print m * s}')" "$(field samples_per_s < "$work/runs" | median | awk '{printf "%.2f", $1 / 1e6}')" \
      "$(field setup_s < "$work/runs" | median | awk '{printf "%.2f", $1}')"
  done
done
