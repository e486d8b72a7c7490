#!/usr/bin/env bash
# The oracle on the product grid's scenes (docs/studies/product_grid.toml's maps and materials) at one image
# size: each method's MSE·spp and relMSE·spp as a multiple of the oracle's, with `random` (i.i.d. samples:
# MSE·spp is the variance per sample), 2 s per method, the oracle computed on the centre pixel of every K×K
# block and each method measured on the same pixels (converge --oracle-stride, docs/MANUAL.md). K defaults to
# SIZE/16, so every size puts the oracle on 256 pixels at the same cost. Ground truths as the grid's (Monte
# Carlo, 20 s of mis/sobol; cached), with the grid's generated inputs where the grid made them. A scene already
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
    -h | --help) sed -n '/^# Usage:/,/^[^#]/s/^# \{0,1\}//p' "$0"; exit 0 ;;
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
study=$(dirname "$0")/../docs/studies/product_grid.toml
mkdir -p "$out"
# The grid's maps and materials, one "NAME<TAB>converge flags" line each, from the study file. An input the
# study generates (${inputs}/FILE) is taken from the study's own inputs when it ran, else generated here by
# the study's command for it.
scenes=$(python3 - "$study" "$build/studies/product-grid/inputs" "$out" "$iblx" <<'PY'
import pathlib, shlex, subprocess, sys, tomllib
study, inputs, out, iblx = sys.argv[1], pathlib.Path(sys.argv[2]), pathlib.Path(sys.argv[3]), sys.argv[4]
grid = tomllib.loads(pathlib.Path(study).read_text())
commands = {i["name"]: i["command"] for i in grid.get("input", [])}
def resolve(brdf):
    if not brdf.startswith("${inputs}/"):
        return brdf
    name = brdf[len("${inputs}/"):]
    for candidate in (inputs / name, out / name):
        if candidate.is_file() and candidate.stat().st_size > 0:
            return str(candidate)
    subprocess.run([iblx, *commands[name], "--out", str(out / name)], check=True, stdout=subprocess.DEVNULL)
    return str(out / name)
for m in grid["map"]:
    for mat in grid["material"]:
        flags = ["--env", m["env"], "--brdf", resolve(mat["brdf"])]
        for key, value in mat.get("params", {}).items():
            flags += ["--param", f"{key}={value}"]
        print(f"{m['name']}-{mat['name']}\t{shlex.join(flags)}")
PY
)
while IFS=$'\t' read -r name flags; do
  [ -s "$out/$name.json" ] && continue
  # shellcheck disable=SC2086 # the scene's flags are words (no file name of the grid holds a space)
  "$iblx" converge $flags --size "${size}x$size" --time 2 --seeds 1 --seq random \
    --method env-hier --method mis --method product --method product-mis --reference mc --reference-time 20 \
    --oracle --oracle-stride "$stride" --no-plots --json --out-dir "$out/$name" > "$out/$name.partial" 2> "$out/$name.log"
  mv "$out/$name.partial" "$out/$name.json"
  echo "$name: $(grep '^oracle:' "$out/$name.log")" >&2
done <<< "$scenes"
python3 - "$out" "$study" <<'PY'
import json, sys, pathlib, tomllib
out = pathlib.Path(sys.argv[1])
grid = tomllib.loads(pathlib.Path(sys.argv[2]).read_text())
maps = [m["name"] for m in grid["map"]]
materials = [m["name"] for m in grid["material"]]
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
