#!/usr/bin/env bash
# The oracle on the product grid's scenes (docs/studies/product_grid.toml's maps and materials) at one image
# size: each method's MSE·spp and relMSE·spp as a multiple of the oracle's, with `random` (i.i.d. samples:
# MSE·spp is the variance per sample), 2 s per method, the oracle computed on the centre pixel of every K×K
# block and each method measured on the same pixels (converge --oracle-stride, docs/MANUAL.md). K defaults to
# SIZE/16, so every size puts the oracle on 256 pixels at the same cost. Ground truths as the grid's (Monte
# Carlo, 20 s of mis/sobol; cached), with the grid's MERL file where the grid made it. A scene already
# measured in OUT_DIR is not measured again. Prints one markdown table per measure (docs/RESULTS.md,
# "Against the limit").
# Usage: tools/oracle_grid.sh [--size SIZE] [--stride K] [BUILD_DIR] [OUT_DIR]
#        (SIZE 64 by default; OUT_DIR BUILD_DIR/studies/oracle-grid, oracle-grid-SIZE for other sizes)
set -euo pipefail
size=64
stride=
while [ $# -gt 0 ]; do
  case $1 in
    --size) size=${2:?--size needs a number of pixels}; shift 2 ;;
    --stride) stride=${2:?--stride needs a block width}; shift 2 ;;
    -h | --help) sed -n 's/^# \{0,1\}//p' "$0" | sed -n '/^Usage:/,$p'; exit 0 ;;
    -*) echo "oracle_grid.sh: unknown option $1 (--size, --stride)" >&2; exit 2 ;;
    *) break ;;
  esac
done
[[ "$size" =~ ^[1-9][0-9]*$ ]] || { echo "oracle_grid.sh: --size must be a number of pixels, not '$size'" >&2; exit 2; }
stride=${stride:-$(( size / 16 > 0 ? size / 16 : 1 ))}
[[ "$stride" =~ ^[1-9][0-9]*$ ]] || { echo "oracle_grid.sh: --stride must be a positive number, not '$stride'" >&2; exit 2; }
build=$(realpath "${1:-build}")
[ "$size" = 64 ] && default_out=$build/studies/oracle-grid || default_out=$build/studies/oracle-grid-$size
out=${2:-$default_out}
iblx=$build/iblx
[ -x "$iblx" ] || { echo "oracle_grid.sh: $iblx not found: build first (cmake --build build)" >&2; exit 2; }
maps=/usr/share/blender/datafiles/studiolights/world
mkdir -p "$out"
merl=$build/studies/product-grid/inputs/ggx-0.1-metal.binary
[ -s "$merl" ] || merl=$out/ggx-0.1-metal.binary
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
    "$iblx" converge --env "$maps/$map.exr" ${entry#*:} --size "${size}x$size" --time 2 --seeds 1 --seq random \
      --method env-hier --method mis --method product --method product-mis --reference mc --reference-time 20 \
      --oracle --oracle-stride "$stride" --no-plots --json --out-dir "$out/$name" > "$out/$name.partial" 2> "$out/$name.log"
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
