#!/usr/bin/env bash
# The load time of measured BRDF files (docs/BENCHMARKS.md, "Measured formats"): `iblx render --list-methods
# --brdf FILE` against the same with a built-in BRDF (both start the process and print the registry), median
# of 5, so the difference is the reader's and the conversion's time. The fixtures of docs/studies/measured.toml
# are in build/studies/measured/inputs/ once `iblx study plan docs/studies/measured.toml` has run.
# Usage: tools/bench_load_time.sh FILE...
set -euo pipefail
iblx="$(cd "$(dirname "$0")/.." && pwd)/build/iblx"
[ $# -gt 0 ] || { sed -n 's/^# Usage: //p' "$0" >&2; exit 2; }
median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
elapsed() { local s; s=$(date +%s.%N); "$@" > /dev/null 2>&1; awk -v s="$s" -v e="$(date +%s.%N)" 'BEGIN {print e - s}'; }
builtin=$(for _ in 1 2 3 4 5; do elapsed "$iblx" render --list-methods --brdf lambert; done | median)
for file in "$@"; do
  case "$file" in *.exr | *.hdr) continue ;; esac  # maps, not materials
  loaded=$(for _ in 1 2 3 4 5; do elapsed "$iblx" render --list-methods --brdf "$file"; done | median)
  echo "load $(basename "$file") ($(stat -c %s "$file") bytes, checked and converted):" \
    "$(awk -v f="$loaded" -v b="$builtin" 'BEGIN {printf "%.1f ms", 1000 * (f - b)}') (median of 5, process start subtracted)"
done
