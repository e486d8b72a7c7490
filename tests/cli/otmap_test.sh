#!/usr/bin/env bash
# `iblx otmap` end to end: a small synthetic sky at n = 64 converges with no folded quad, writes its figure, and
# the second run reads the map from the cache (--no-cache solves again). Usage: otmap_test.sh path/to/iblx
iblx="$1"
source "$(dirname "$0")/common.sh"
check() {  # check "description" command...
  local what="$1"
  shift
  if "$@"; then pass; else fail "$what"; fi
}
field() {  # field JSON NAME: the value of one top-level field of a flat JSON object
  printf '%s' "$1" | sed -n "s/.*\"$2\": \\([^,}]*\\).*/\\1/p"
}

"$iblx" make-sky --size 128x64 --out "$tmp/sky.exr" > /dev/null || { echo "FAIL: make-sky"; exit 1; }

json=$("$iblx" otmap --env "$tmp/sky.exr" --size 64 --json --out "$tmp/map.png" 2> "$tmp/err")
status=$?
echo "first run: $json"
check "exit status $status" [ $status -eq 0 ]
check "converged: $(field "$json" converged)" [ "$(field "$json" converged)" = true ]
check "folded: $(field "$json" folded)" [ "$(field "$json" folded)" = 0 ]
check "from_cache on the first run" [ "$(field "$json" from_cache)" = false ]
check "n" [ "$(field "$json" n)" = 64 ]
check "l2 <= 1e-7: $(field "$json" l2)" awk -v x="$(field "$json" l2)" 'BEGIN { exit !(x != "" && x <= 1e-7) }'
check "l1 <= 1e-3: $(field "$json" l1)" awk -v x="$(field "$json" l1)" 'BEGIN { exit !(x != "" && x <= 1e-3) }'
# A PNG of the announced size (IHDR width and height, big-endian, at bytes 16-23).
check "the PNG exists" [ -s "$tmp/map.png" ]
check "PNG signature" [ "$(head -c 8 "$tmp/map.png" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ]
size=$(od -An -tu1 -j16 -N8 "$tmp/map.png" | awk '{ print $3 * 256 + $4 "x" $7 * 256 + $8 }')
check "PNG size $size" [ "$size" = "$(field "$json" out_width)x$(field "$json" out_height)" ]
check "no warning on the first run: $(cat "$tmp/err")" [ ! -s "$tmp/err" ]
# Per-level diagnostics: the coarse-to-fine levels 16, 32, 64 in order, the finest one's L2 the map's (the
# solver's running sum against the one recomputed from the vertices: equal to rounding).
grids=$(printf '%s' "$json" | grep -o '"grid": [0-9]*' | awk '{ printf "%s ", $2 }')
check "levels 16 32 64: '$grids'" [ "$grids" = "16 32 64 " ]
curved=$(printf '%s' "$json" | grep -o '"curved_steps": [0-9]*' | wc -l)
check "every level reports its curved steps ($curved)" [ "$curved" = 3 ]
finest_l2=$(printf '%s' "$json" | grep -o '"level_l2": [^,}]*' | tail -1 | awk '{ print $2 }')
check "finest level's L2 $finest_l2 is the map's $(field "$json" l2)" \
  awk -v a="$finest_l2" -v b="$(field "$json" l2)" 'BEGIN { exit !(a != "" && (a - b) ^ 2 <= (1e-6 * b) ^ 2) }'

json2=$("$iblx" otmap --env "$tmp/sky.exr" --size 64 --json --out "$tmp/map2.png" 2> /dev/null)
check "second run from the cache: $json2" [ "$(field "$json2" from_cache)" = true ]
check "no levels from the cache" grep -q '"levels": \[\]' <<< "$json2"
check "same iterations from the cache" [ "$(field "$json2" iterations)" = "$(field "$json" iterations)" ]
check "same figure from the cache" cmp -s "$tmp/map.png" "$tmp/map2.png"
json3=$("$iblx" otmap --env "$tmp/sky.exr" --size 64 --json --no-cache --out "$tmp/map3.png" 2> /dev/null)
check "--no-cache solves: $json3" [ "$(field "$json3" from_cache)" = false ]

text=$("$iblx" otmap --env "$tmp/sky.exr" --size 64 --out "$tmp/map4.png" 2>&1)
check "text output: $text" grep -q "^converged: yes" <<< "$text"
check "text output names the cache" grep -q "from the cache: yes" <<< "$text"
check "text output folded" grep -q "^quads: 0 folded" <<< "$text"

# --sun-clip: the make-sky sun is split off, and the map of the rest needs less untangling than the whole map's.
check "no sun split by default: $json" [ "$(field "$json" sun_texels)" = 0 ]
json5=$("$iblx" otmap --env "$tmp/sky.exr" --size 64 --sun-clip 100 --json --out "$tmp/map5.png" 2> /dev/null)
check "--sun-clip 100 splits texels off: $json5" awk -v x="$(field "$json5" sun_texels)" 'BEGIN { exit !(x > 0) }'
check "--sun-clip 100 sun share in (0, 1)" awk -v x="$(field "$json5" sun_share)" 'BEGIN { exit !(x > 0 && x < 1) }'
check "--sun-clip 100 converged" [ "$(field "$json5" converged)" = true ]
check "--sun-clip lowers the sampler map's L1: $(field "$json5" sampler_l1) vs $(field "$json" sampler_l1)" \
  awk -v a="$(field "$json5" sampler_l1)" -v b="$(field "$json" sampler_l1)" 'BEGIN { exit !(a < b) }'
"$iblx" otmap --env "$tmp/sky.exr" --size 64 --sun-clip 0.5 --out "$tmp/map6.png" > /dev/null 2> "$tmp/err6"
check "--sun-clip below 1 is refused: $(cat "$tmp/err6")" grep -q -- "--sun-clip" "$tmp/err6"

# --diagnose: one JSON line per sampler on the make-sky sky (its sun split off); the texel samplers' chi^2 is
# 0 up to float rounding (env-ot's too: it is texel-exact), the map-pdf OT samplers' positive, and every
# sampler's texel probabilities sum to 1.
diagnose=$("$iblx" otmap --env "$tmp/sky.exr" --diagnose --json 2> "$tmp/err7")
check "--diagnose exit status: $(cat "$tmp/err7")" [ -n "$diagnose" ]
samplers=$(printf '%s\n' "$diagnose" | sed -n 's/.*"sampler": "\([^"]*\)".*/\1/p' | tr '\n' ' ')
check "--diagnose samplers: '$samplers'" [ "$samplers" = "env-cdf env-hier env-ot env-ot-inv env-ot-fwd " ]
while IFS= read -r line; do
  sampler=$(field "$line" sampler)
  check "$sampler sampler mass 1: $(field "$line" sampler_mass)" \
    awk -v x="$(field "$line" sampler_mass)" 'BEGIN { exit !(x > 0.999 && x < 1.001) }'
  case "$sampler" in
    *env-cdf* | *env-hier*)
      check "$sampler chi2 below 1e-6: $(field "$line" chi2)" awk -v x="$(field "$line" chi2)" 'BEGIN { exit !(x < 1e-6 && x > -1e-6) }'
      check "$sampler has no map: $(field "$line" non_convex_share)" [ "$(field "$line" non_convex_share)" = null ] ;;
    \"env-ot\")
      check "$sampler chi2 below 1e-6: $(field "$line" chi2)" awk -v x="$(field "$line" chi2)" 'BEGIN { exit !(x < 1e-6 && x > -1e-6) }'
      check "$sampler evaluates no map per sample: $(field "$line" round_trip_max)" [ "$(field "$line" round_trip_max)" = null ] ;;
    *)
      check "$sampler chi2 positive: $(field "$line" chi2)" awk -v x="$(field "$line" chi2)" 'BEGIN { exit !(x > 0) }'
      check "$sampler round trip: $(field "$line" round_trip_max)" awk -v x="$(field "$line" round_trip_max)" 'BEGIN { exit !(x >= 0 && x < 0.1) }' ;;
  esac
done <<< "$diagnose"
text=$("$iblx" otmap --env "$tmp/sky.exr" --diagnose 2> /dev/null)
check "--diagnose text names every sampler" [ "$(grep -cE '^env-(cdf|hier|ot|ot-inv|ot-fwd) ' <<< "$text")" = 5 ]

echo "otmap cli: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
