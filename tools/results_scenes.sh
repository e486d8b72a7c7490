# The eight scenes of docs/RESULTS.md, shared by tools/results.sh and tools/mis_compare.sh (sourced, not run;
# needs $iblx): two blender-data HDRIs in $world (forest, sunrise) and the materials in the array `brdf`, as
# `iblx` flags, the synthetic MERL material written to the temporary folder $work (removed on exit).
world=/usr/share/blender/datafiles/studiolights/world
[ -f "$world/forest.exr" ] || { echo "$(basename "$0"): $world/forest.exr missing: install blender-data (tools/install.sh)" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$iblx" merl-synth --brdf ggx --param roughness=0.1 --param metallic=1 --out "$work/ggx-0.1-metal.binary" > /dev/null
declare -A brdf=(
  [lambert]="--brdf lambert"
  [ggx-0.3]="--brdf ggx --param roughness=0.3"
  [ggx-0.05]="--brdf ggx --param roughness=0.05"
  [merl-ggx-0.1]="--brdf $work/ggx-0.1-metal.binary"
)
