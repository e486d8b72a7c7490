#!/usr/bin/env bash
# The oracle on the product grid's 64x64 scenes (docs/studies/product_grid.toml's maps and materials): each
# method's MSE·spp and relMSE·spp as a multiple of the oracle's, with `random` (i.i.d. samples: MSE·spp is the
# variance per sample), 2 s per method, the oracle computed on the centre pixel of every 4x4 block and each
# method measured on the same pixels (converge --oracle-stride, docs/MANUAL.md). Ground truths as the grid's
# (Monte Carlo, 20 s of mis/sobol; cached). A scene already measured in OUT_DIR is not measured again.
# Prints one markdown table per measure (docs/RESULTS.md, "Against the limit").
# Usage: tools/oracle_grid.sh [BUILD_DIR] [OUT_DIR]
set -euo pipefail
build=$(realpath "${1:-build}")
out=${2:-$build/studies/oracle-grid}
iblx=$build/iblx
maps=/usr/share/blender/datafiles/studiolights/world
mkdir -p "$out"
merl=$out/ggx-0.1-metal.binary
[ -s "$merl" ] || "$iblx" merl-synth --brdf ggx --param roughness=0.1 --param metallic=1 --out "$merl" > /dev/null
materials=("ggx-0.005:--brdf ggx --param roughness=0.005" "ggx-0.01:--brdf ggx --param roughness=0.01"
           "ggx-0.02:--brdf ggx --param roughness=0.02" "ggx-0.05:--brdf ggx --param roughness=0.05"
           "ggx-0.1:--brdf ggx --param roughness=0.1" "ggx-0.3:--brdf ggx --param roughness=0.3"
           "ggx-1:--brdf ggx --param roughness=1.0" "lambert:--brdf lambert" "merl-ggx-0.1:--brdf $merl")
for map in forest sunrise courtyard night; do
  for entry in "${materials[@]}"; do
    name=$map-${entry%%:*}
    [ -s "$out/$name.json" ] && continue
    # shellcheck disable=SC2086 # the material's flags are words
    "$iblx" converge --env "$maps/$map.exr" ${entry#*:} --size 64x64 --time 2 --seeds 1 --seq random \
      --method env-hier --method mis --method product --method product-mis --reference mc --reference-time 20 \
      --oracle --oracle-stride 4 --no-plots --json --out-dir "$out/$name" > "$out/$name.partial" 2> "$out/$name.log"
    mv "$out/$name.partial" "$out/$name.json"
    echo "$name: $(grep '^oracle:' "$out/$name.log")" >&2
  done
done
python3 - "$out" <<'PY'
import json, sys, pathlib
out = pathlib.Path(sys.argv[1])
maps = ["forest", "sunrise", "courtyard", "night"]
materials = ["ggx-0.005", "ggx-0.01", "ggx-0.02", "ggx-0.05", "ggx-0.1", "ggx-0.3", "ggx-1", "lambert", "merl-ggx-0.1"]
rows = {}
for m in maps:
    for mat in materials:
        for line in (out / f"{m}-{mat}.json").read_text().splitlines():
            d = json.loads(line)
            rows.setdefault(mat, {}).setdefault(m, {})[d["method"].split("(")[0]] = d
for key, title in (("mse_spp_over_oracle", "MSE·spp"), ("relmse_spp_over_oracle", "relMSE·spp")):
    print(f"\n{title} over the oracle's, the best method's (and which), then `mis`'s:\n")
    print("| material | " + " | ".join(maps) + " |")
    print("|---|" + "---:|" * len(maps))
    for mat in materials:
        cells = []
        for m in maps:
            r = rows[mat][m]
            best = min(r, key=lambda k: r[k][key])
            cells.append(f"{r[best][key]:.3g} {best}, mis {r['mis'][key]:.3g}")
        print(f"| {mat} | " + " | ".join(cells) + " |")
PY
