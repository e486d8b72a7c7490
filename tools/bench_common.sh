# Helpers shared by the benchmark scripts (sourced, not run): the median of numbers on stdin, a numeric field of
# `iblx render --json` lines, and one equal-time table row.
median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
field() { sed -E "s/.*\"$1\": ([^,}]+).*/\1/"; }

# One row of an equal-time table: `$iblx render --method METHOD` (METHOD may carry its own flags, e.g. "mis
# --env-sampler env-cdf") for seeds 1..SEEDS with the remaining arguments, then the method's label and the
# median spp, MSE and relMSE. Usage: equal_time_row WORK_DIR SEEDS METHOD RENDER_ARGS...
equal_time_row() {
  local work="$1" seeds="$2" method="$3"
  shift 3
  : > "$work/runs"
  for seed in $(seq 1 "$seeds"); do
    # shellcheck disable=SC2086
    "$iblx" render --method $method --seed "$seed" --json --out "$work/out.exr" "$@" 2>/dev/null >> "$work/runs"
  done
  printf '%-55s %10s %12s %12s\n' "$(head -1 "$work/runs" | sed -E 's/.*"method": "([^"]*)".*/\1/')" \
    "$(field spp < "$work/runs" | median)" "$(field mse < "$work/runs" | median)" \
    "$(field relmse < "$work/runs" | median)"
}
