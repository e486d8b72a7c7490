#!/usr/bin/env bash
# The equal-time matrix of docs/RESULTS.md from tools/results.sh's summaries: one row per method and sequence,
# one column per scene, each cell the MSE at equal time over the best method's on that scene, or with --slopes
# the fitted log-log slope of MSE against spp. Usage: tools/results_matrix.sh [--slopes] [RESULTS_DIR]
set -euo pipefail
column=13  # "× best" in summary.md (fields split on '|', the first empty)
if [ "${1:-}" = "--slopes" ]; then column=10; shift; fi
dir="${1:-$(cd "$(dirname "$0")/.." && pwd)/docs/results}"
scenes=()
for env in forest sunrise; do
  for material in lambert ggx-0.3 ggx-0.05 merl-ggx-0.1; do scenes+=("$env-$material"); done
done
awk -F'|' -v column="$column" -v list="${scenes[*]}" '
  BEGIN { n = split(list, scene, " ") }
  FNR == 1 { s++ }
  /^\| / && !/^\| method/ && !/^\|---/ {
    method = $2; gsub(/^ +| +$/, "", method)
    # The BRDF technique differs per material (cosine, ggx-vndf, merl-table): one row for all.
    gsub(/\((cosine|ggx-vndf|merl-table)\)/, "", method)
    gsub(/\+(cosine|ggx-vndf|merl-table),/, "+BRDF,", method)
    seq = $3; gsub(/ /, "", seq)
    key = method " | " seq
    if (!(key in seen)) { seen[key] = 1; order[++rows] = key }
    value = $column; gsub(/ /, "", value); cell[key, s] = value
  }
  END {
    printf "| method | seq |"; for (i = 1; i <= n; ++i) printf " %s |", scene[i]; printf "\n|---|---|"
    for (i = 1; i <= n; ++i) printf "---:|"; printf "\n"
    for (r = 1; r <= rows; ++r) {
      printf "| %s |", order[r]
      for (i = 1; i <= n; ++i) printf " %s |", ((order[r], i) in cell) ? cell[order[r], i] : "—"
      printf "\n"
    }
  }' $(for s in "${scenes[@]}"; do echo "$dir/$s/summary.md"; done)
