#!/usr/bin/env bash
# The optimal-transport benchmarks: sampler figures in docs/BENCHMARKS.md ("Optimal-transport sampling"), solver
# figures in docs/ot_solver.md:
#   solver:   the grid LU alone (iblx_ot_bench --lu), then the OT solver's time and accuracy (iblx_ot_bench) on
#             the synthetic cases and on the CC0 HDRIs of Debian's blender-data, at the grid sizes given
#             (default 128,256);
#   converge: iblx converge of env-cdf, env-hier, env-ot-inv and env-ot-fwd, each with random and sobol, on a
#             Lambert and a GGX a = 0.1 sphere under forest.exr (no sun) and sunrise.exr (a strong sun), equal
#             wall-time budgets; writes docs/ot/<env>-<material>/ (summary.md, converge.csv, two plots).
# Usage: tools/bench_ot.sh [solver|converge|all] [SECONDS_PER_RUN (2)] [SEEDS (3)] [SIZE (64)] [SOLVER_SIZES]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
what="${1:-all}"
seconds="${2:-2}"
seeds="${3:-3}"
size="${4:-64}"
sizes="${5:-128,256}"
world=/usr/share/blender/datafiles/studiolights/world
[ -f "$world/forest.exr" ] || { echo "bench_ot.sh: $world/forest.exr missing: install blender-data (tools/install.sh)" >&2; exit 1; }

if [ "$what" = solver ] || [ "$what" = all ]; then
  "$root/build/iblx_ot_bench" --lu --sizes "$sizes"
  "$root/build/iblx_ot_bench" --sizes "$sizes" "$world"/*.exr 2> /dev/null
fi

if [ "$what" = converge ] || [ "$what" = all ]; then
  declare -A brdf=([lambert]="--brdf lambert" [ggx-0.1]="--brdf ggx --param roughness=0.1")
  for env in forest sunrise; do
    for material in lambert ggx-0.1; do
      dir="$root/docs/ot/$env-$material"
      rm -rf "$dir"
      # shellcheck disable=SC2086
      "$root/build/iblx" converge --env "$world/$env.exr" ${brdf[$material]} --size "${size}x${size}" \
        --time "$seconds" --seeds "$seeds" --target-relmse 1e-2 --method env-cdf --method env-hier \
        --method env-ot-inv --method env-ot-fwd --out-dir "$dir" > /dev/null
      find "$dir" -name 'heat-*.png' -delete
      rm -f "$dir/reference.exr" "$dir/mse_vs_time.png" "$dir/relmse_vs_spp.png"
      echo "## $env, $material"; echo; tail -n +3 "$dir/summary.md"; echo
    done
  done
fi
