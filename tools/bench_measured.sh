#!/usr/bin/env bash
# Measured formats beyond MERL: load time and equal-time error of the BRDF techniques on fixtures written by
# `iblx measured-synth` (UTIA: BRDF Explorer's anisotropic Ward and GGX alpha = 0.3 metal; MIT .dat: the Ward;
# RGL-EPFL .bsdf: the GGX, and the Ward with 17 view azimuths; ALTA data: the GGX on a RUSIN_TH_TD_PD grid and
# the Ward on a SPHERICAL_TL_PL_TV_PV grid) and on an ALTA function file with a Ward lobe (written here),
# under the default environment; for each method (cosine, brdf-tab, the file's own sampler where it has one,
# env-cdf and mis), the MSE and relMSE over object pixels after the same wall time, median over seeds.
# Usage: tools/bench_measured.sh [SECONDS_PER_RUN (default 10)] [SEEDS (default 3)] [SIZE (default 128)]
# IBLX_BENCH_ENV=FILE uses another environment map (default: assets/default_sky.exr);
# IBLX_BENCH_MATERIALS="ward.bsdf ggx.data ..." restricts the materials (default: all).
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
"$iblx" measured-synth --format rgl --brdf ggx --param roughness=0.3 --param metallic=1 --out "$work/ggx.bsdf" > /dev/null
"$iblx" measured-synth --format rgl --anisotropic --brdf "$root/assets/brdf/ward.brdf" --out "$work/ward.bsdf" > /dev/null
"$iblx" measured-synth --format alta --brdf ggx --param roughness=0.3 --param metallic=1 --out "$work/ggx.data" > /dev/null
"$iblx" measured-synth --format alta --alta-param SPHERICAL_TL_PL_TV_PV --brdf "$root/assets/brdf/ward.brdf" \
  --out "$work/ward.data" > /dev/null
# BRDF Explorer's ward.brdf as an ALTA function: a diffuse lobe and Ward's (alphaX 0.15, alphaY 0.4).
printf '%s\n' "#ALTA FUNC HEADER" "#DIM 3 3" "#PARAM_IN RUSIN_TH_TD_PD" "#ALTA HEADER END" \
  "#FUNC nonlinear_function_diffuse" "kd 0.05" "kd 0.05" "kd 0.05" \
  "#FUNC nonlinear_function_ward" "Ks 0.8" "ax 0.15" "ay 0.4" "Ks 0.8" "ax 0.15" "ay 0.4" "Ks 0.8" "ax 0.15" "ay 0.4" \
  > "$work/ward.func"
materials=(${IBLX_BENCH_MATERIALS:-ward.bin ggx.bin ward.dat ggx.bsdf ward.bsdf ggx.data ward.data ward.func})

# shellcheck source=tools/bench_common.sh
source "$(dirname "$0")/bench_common.sh"

# Load time: --list-methods with the file against the same with a built-in BRDF (both start the process and
# print the registry), median of 5.
elapsed() { local s; s=$(date +%s.%N); "$@" > /dev/null 2>&1; awk -v s="$s" -v e="$(date +%s.%N)" 'BEGIN {print e - s}'; }
for k in 1 2 3 4 5; do elapsed "$iblx" render --list-methods --brdf lambert; done | median > "$work/builtin"
for file in "${materials[@]}"; do
  for k in 1 2 3 4 5; do elapsed "$iblx" render --list-methods --brdf "$work/$file"; done | median > "$work/file"
  echo "load $file ($(stat -c %s "$work/$file") bytes, checked and converted):" \
    "$(awk -v f="$(cat "$work/file")" -v b="$(cat "$work/builtin")" 'BEGIN {printf "%.1f ms", 1000 * (f - b)}')" \
    "(median of 5, process start subtracted)"
done

for material in "${materials[@]}"; do
  brdf="$work/$material"
  # The file's own sampler, where the format has one (rgl-vndf, isfunc); else brdf-tab.
  own=$("$iblx" render --list-methods --brdf "$brdf" 2>/dev/null | sed -nE 's/.*best sampler: ([a-z-]+)$/\1/p' | tail -1)
  methods=("brdf --brdf-sampler cosine" "brdf --brdf-sampler brdf-tab")
  [ "$own" != "brdf-tab" ] && methods+=("brdf --brdf-sampler $own")
  methods+=("env-cdf" "mis --env-sampler env-cdf --brdf-sampler $own")
  "$iblx" reference "${env[@]}" --brdf "$brdf" --size "${size}x${size}" --out "$work/$material-ref.exr" > /dev/null 2>&1
  echo "== $material under ${IBLX_BENCH_ENV:-the default sky}, ${size}x${size}, ${seconds} s per run, median of $seeds seeds"
  printf '%-55s %10s %12s %12s\n' "method" "spp" "MSE" "relMSE"
  for m in "${methods[@]}"; do
    equal_time_row "$work" "$seeds" "$m" "${env[@]}" --brdf "$brdf" --size "${size}x${size}" --spp 8 --time "$seconds" \
      --reference-file "$work/$material-ref.exr"
  done
done
