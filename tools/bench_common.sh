# Helpers shared by the benchmark scripts (sourced, not run): the median of numbers on stdin, and a numeric field
# of `iblx render --json` lines.
median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
field() { sed -E "s/.*\"$1\": ([^,}]+).*/\1/"; }
