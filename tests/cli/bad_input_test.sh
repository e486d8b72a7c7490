#!/usr/bin/env bash
# Command-line tests: each class of bad input gives one clear line naming the culprit and a non-zero exit,
# and nothing is written. Usage: bad_input_test.sh path/to/iblx
set -u
iblx="$1"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
passed=0
failed=0

# expect_error "description" "substring of the message" args...
expect_error() {
  local what="$1" pattern="$2"
  shift 2
  local out status
  out=$("$iblx" "$@" 2>&1 >/dev/null)
  status=$?
  if [ $status -ne 0 ] && [ "$(printf '%s\n' "$out" | grep -c .)" -ge 1 ] && printf '%s' "$out" | grep -qF -- "$pattern"; then
    passed=$((passed + 1))
  else
    failed=$((failed + 1))
    echo "FAIL: $what: exit $status, stderr: $out (expected to contain: $pattern)"
  fi
}

expect_ok() {
  local what="$1"
  shift
  if out=$("$iblx" "$@" 2>&1); then
    passed=$((passed + 1))
  else
    failed=$((failed + 1))
    echo "FAIL: $what: $out"
  fi
}

printf 'this is not an exr file at all' > "$tmp/garbage.exr"
: > "$tmp/empty.hdr"
printf '#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 64 +X 128\n\001\002' > "$tmp/truncated.hdr"

expect_error "missing env file" "$tmp/nope.exr" render --env "$tmp/nope.exr" --out "$tmp/a.png"
expect_error "corrupt exr" "garbage.exr" render --env "$tmp/garbage.exr" --out "$tmp/a.png"
expect_error "empty hdr" "empty.hdr" render --env "$tmp/empty.hdr" --out "$tmp/a.png"
expect_error "truncated hdr" "truncated.hdr" render --env "$tmp/truncated.hdr" --out "$tmp/a.png"
expect_error "unsupported env format" "nope.jpg" render --env "$tmp/nope.jpg" --out "$tmp/a.png"
expect_error "unknown method" "unknown --method 'bogus'" render --method bogus
expect_error "unknown method lists valid" "env-cdf" render --method bogus
expect_error "unknown brdf" "unknown --brdf 'velvet'" render --brdf velvet
expect_error "unknown parameter" "has no parameter 'shininess'" render --brdf ggx --param shininess=3
expect_error "bad parameter value" "not a number" render --brdf ggx --param roughness=abc
expect_error "parameter out of range" "out of range" render --brdf ggx --param roughness=2
expect_error "bad color" "expected a color" render --brdf lambert --param albedo=0.1,0.2
expect_error "unknown flag" "unknown flag '--bogus'" render --bogus
expect_error "missing value" "--spp needs a value" render --spp
expect_error "spp out of range" "--spp 0" render --spp 0
expect_error "bad size" "expected WIDTHxHEIGHT" render --size 64
expect_error "negative size" "--size" render --size -4x8
expect_error "bad sequence" "unknown --seq 'halton'" render --seq halton
expect_error "bad heuristic" "--mis-heuristic" render --mis-heuristic maximum
expect_error "bad split" "--mis-split" render --mis-split 1.5
expect_error "ris candidates" "--ris-candidates" render --method ris --ris-candidates 65
expect_error "inapplicable technique" "does not apply to BRDF 'lambert'" render --brdf lambert --method brdf --brdf-sampler ggx-vndf
expect_error "unknown env sampler" "unknown --env-sampler" render --method mis --env-sampler nope
expect_error "bad output format" "unsupported image format" render --out "$tmp/x.jpg"
expect_error "output dir missing" "does not exist" render --out "$tmp/no/such/dir.png"
expect_error "reference needs exr" "use .exr" reference --out "$tmp/x.png"
expect_error "bad device" "no usable Vulkan device" render --device no-such-gpu --size 8x8 --passes 1 --out "$tmp/d.png"
# One line, naming each device and why it was not chosen; an index too long for a number matches nothing.
for selector in 99 99999999999999999999999; do
  out=$("$iblx" render --device "$selector" --size 8x8 --passes 1 --out "$tmp/d.png" 2>&1)
  [ "$(printf '%s\n' "$out" | wc -l)" -eq 1 ] && printf '%s' "$out" | grep -q "\[0\] .*does not match the device selector '$selector'" &&
    passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: --device $selector: $out"; }
done
expect_error "unknown command" "unknown command" frobnicate
# One line, naming the commands (it printed the whole usage after the error).
[ "$("$iblx" frobnicate 2>&1 | wc -l)" -eq 1 ] && "$iblx" frobnicate 2>&1 | grep -q "commands: render, .*study" &&
  passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: an unknown command is not reported in one line"; }
expect_error "too many color values" "too many values" render --brdf lambert --param albedo=1,1,1,1
expect_error "trailing comma" "trailing comma" render --brdf lambert --param albedo=0.5,
expect_error "spp cap" "out of range" render --spp 5000
expect_error "sample index wrap" "exceeds 2^32" render --spp 4096 --passes 16000000
[ ! -e "$tmp/a.png" ] && passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: an image was written despite errors"; }

expect_ok "list methods" render --list-methods
# The listing reads the strategies' capabilities: which methods take an env or a BRDF technique of the user's
# choice, and every material file format.
listing=$("$iblx" render --list-methods 2>&1)
if grep -q "env techniques (--env-sampler, used by mis, ris;" <<< "$listing" &&
  grep -q "BRDF techniques (--brdf-sampler, used by brdf, mis, product-mis)" <<< "$listing" &&
  grep -q "merl .binary, UTIA .bin, ALTA data, MIT CSAIL .dat, RGL-EPFL .bsdf or ALTA function file" <<< "$listing"; then
  passed=$((passed + 1))
else
  failed=$((failed + 1)); echo "FAIL: --list-methods does not derive its words from the registry: $listing"
fi
expect_ok "tiny render" render --size 16x16 --spp 4 --passes 2 --out "$tmp/ok.png"
[ -s "$tmp/ok.png" ] && passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: tiny render wrote no image"; }
json=$("$iblx" render --size 16x16 --spp 4 --passes 2 --json --reference --out "$tmp/ok.exr" 2>/dev/null)
if printf '%s' "$json" | grep -q '"relmse"' && printf '%s' "$json" | grep -q '"samples_per_s"'; then
  passed=$((passed + 1))
else
  failed=$((failed + 1)); echo "FAIL: --json --reference output: $json"
fi

# --reference-file: the error against a stored ground truth, with no warning; a size mismatch is an error.
"$iblx" reference --size 16x16 --out "$tmp/ref16.exr" > /dev/null 2>&1
json=$("$iblx" render --size 16x16 --spp 4 --passes 2 --json --reference-file "$tmp/ref16.exr" --out "$tmp/r.exr" 2>"$tmp/r.err")
if printf '%s' "$json" | grep -q '"relmse"' && [ ! -s "$tmp/r.err" ]; then
  passed=$((passed + 1))
else
  failed=$((failed + 1)); echo "FAIL: --reference-file: $json $(cat "$tmp/r.err")"
fi
warning=$("$iblx" render --size 16x16 --spp 1 --passes 1 --reference --reference-file "$tmp/ref16.exr" --out "$tmp/r3.exr" 2>&1 >/dev/null)
if printf '%s' "$warning" | grep -q -- "--reference is ignored"; then
  passed=$((passed + 1))
else
  failed=$((failed + 1)); echo "FAIL: --reference with --reference-file: $warning"
fi
expect_error "reference-file size" "does not match --size" render --size 8x8 --reference-file "$tmp/ref16.exr" --out "$tmp/r2.exr"
expect_error "reference-file missing" "--reference-file: cannot" render --size 8x8 --reference-file "$tmp/none.exr" --out "$tmp/r2.exr"

# A flag the chosen method does not use is reported (and the render still happens).
warning=$("$iblx" render --method env-cdf --env-sampler env-hier --size 8x8 --passes 1 --spp 1 --out "$tmp/w.png" 2>&1 >/dev/null)
if printf '%s' "$warning" | grep -q -- "--env-sampler is ignored by --method env-cdf" && [ -s "$tmp/w.png" ]; then
  passed=$((passed + 1))
else
  failed=$((failed + 1)); echo "FAIL: ignored-flag warning: $warning"
fi

# MERL materials: merl-synth writes a valid file that renders; each kind of bad file gives its own message.
expect_ok "merl-synth" merl-synth --brdf lambert --param albedo=0.5 --out "$tmp/lambert.binary"
[ "$(stat -c %s "$tmp/lambert.binary" 2>/dev/null)" = 34992012 ] && passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: merl-synth file size"; }
expect_ok "merl render" render --brdf "$tmp/lambert.binary" --method brdf --brdf-sampler merl-thetah --size 8x8 --spp 2 --passes 1 --out "$tmp/m.png"
expect_ok "merl render mis" render --brdf "$tmp/lambert.binary" --size 8x8 --spp 2 --passes 1 --out "$tmp/m.png"
# A measured table larger than the device's largest buffer (here capped at 1 MiB) is reported naming its file.
IBLX_MAX_BUFFER_MIB=1 expect_error "measured table over the device limit" "buffer 'BRDF $tmp/lambert.binary" \
  render --brdf "$tmp/lambert.binary" --method env-cdf --size 8x8 --spp 2 --passes 1 --out "$tmp/m.png"
head -c 1000000 "$tmp/lambert.binary" > "$tmp/truncated.binary"
mkdir -p "$tmp/dir.binary"
{ cat "$tmp/lambert.binary"; printf '12345678'; } > "$tmp/oversized.binary"
{ printf '\132\0\0\0\132\0\0\0\132\0\0\0'; tail -c +13 "$tmp/lambert.binary"; } > "$tmp/header.binary"
: > "$tmp/empty.binary"
expect_error "missing merl file" "no such file" render --brdf "$tmp/none.binary" --out "$tmp/b.png"
expect_error "truncated merl file" "truncated" render --brdf "$tmp/truncated.binary" --out "$tmp/b.png"
expect_error "oversized merl file" "oversized" render --brdf "$tmp/oversized.binary" --out "$tmp/b.png"
expect_error "merl header" "header" render --brdf "$tmp/header.binary" --out "$tmp/b.png"
expect_error "empty merl file" "empty.binary" render --brdf "$tmp/empty.binary" --out "$tmp/b.png"
expect_error "merl name without file" "read from a file" render --brdf merl --out "$tmp/b.png"
expect_error "merl technique on ggx" "does not apply" render --brdf ggx --method brdf --brdf-sampler merl-table
expect_error "ggx technique on merl" "does not apply" render --brdf "$tmp/lambert.binary" --method brdf --brdf-sampler ggx-vndf
expect_error "merl params" "has no parameter" render --brdf "$tmp/lambert.binary" --param roughness=0.1
expect_error "merl-synth of a file" "not a MERL file" merl-synth --brdf "$tmp/lambert.binary" --out "$tmp/c.binary"
# UTIA materials: measured-synth writes a .bin that renders, recognised by its size whatever its name; bad files
# and flags give their messages.
expect_ok "measured-synth utia" measured-synth --format utia --brdf lambert --param albedo=0.5 --out "$tmp/lambert.bin"
[ "$(stat -c %s "$tmp/lambert.bin" 2>/dev/null)" = 1990656 ] && passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: measured-synth utia file size"; }
expect_ok "utia render" render --brdf "$tmp/lambert.bin" --size 8x8 --spp 2 --passes 1 --out "$tmp/u.png"
cp "$tmp/lambert.bin" "$tmp/lambert-utia.data"
expect_ok "utia recognised by content" render --brdf "$tmp/lambert-utia.data" --param scale=2 --size 8x8 --spp 2 --passes 1 --out "$tmp/u.png"
expect_ok "measured-synth from a measured file" measured-synth --format merl --brdf "$tmp/lambert.bin" --out "$tmp/from-utia.binary"
expect_ok "utia save-bparam" render --brdf "$tmp/lambert.bin" --param srgb=1 --size 8x8 --spp 2 --passes 1 --out "$tmp/u.png" --save-bparam "$tmp/utia.bparam"
expect_ok "utia bparam render" render --brdf "$tmp/utia.bparam" --size 8x8 --spp 2 --passes 1 --out "$tmp/u.png"
listing=$("$iblx" render --list-methods --brdf "$tmp/lambert.bin" 2>&1)
if printf '%s' "$listing" | grep -q "UTIA measured anisotropic BRDF .*6 theta x 48 phi" &&
   printf '%s' "$listing" | grep -q "srgb (bool"; then
  passed=$((passed + 1))
else
  failed=$((failed + 1)); echo "FAIL: utia --list-methods: $listing"
fi
head -c 1000 "$tmp/lambert.bin" > "$tmp/truncated.bin"
expect_error "truncated utia file" "truncated UTIA file: 1000 bytes" render --brdf "$tmp/truncated.bin" --out "$tmp/b.png"
expect_error "missing utia file" "none.bin: no such file" render --brdf "$tmp/none.bin" --out "$tmp/b.png"
expect_error "utia params" "has no parameter 'roughness'" render --brdf "$tmp/lambert.bin" --param roughness=0.1
expect_error "measured-synth format" "--format bogus: unknown; valid: utia, mit, rgl, alta, merl, alta-func" measured-synth --format bogus --out "$tmp/c.bin"
expect_error "measured-synth extension" "must end in .bin" measured-synth --out "$tmp/c.binary"
# MIT CSAIL .dat materials: recognised by their header whatever their name.
expect_ok "measured-synth mit" measured-synth --format mit --brdf lambert --param albedo=0.5 --out "$tmp/lambert.dat"
[ "$(stat -c %s "$tmp/lambert.dat" 2>/dev/null)" = 10077760 ] && passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: measured-synth mit file size"; }
expect_ok "mit render" render --brdf "$tmp/lambert.dat" --param scale=2 --size 8x8 --spp 2 --passes 1 --out "$tmp/d.png"
# A valid table larger than any buffer of the device (151 MB against lavapipe's 128 MiB; a sparse file, so it
# costs no disk) is refused from its header, before its body is read.
head -c 64 "$tmp/lambert.dat" > "$tmp/huge.dat"
printf '\x1c\x02\x00\x00' | dd of="$tmp/huge.dat" bs=1 seek=12 conv=notrunc status=none  # 540 phi_in bins
truncate -s 151165504 "$tmp/huge.dat"
IBLX_MAX_BUFFER_MIB=128 expect_error "mit table over the device limit" "huge.dat: the 12597120-bin table needs 144 MiB, more than the device's largest storage buffer (128 MiB)" \
  render --brdf "$tmp/huge.dat" --size 8x8 --spp 2 --passes 1 --out "$tmp/d.png"
rm -f "$tmp/huge.dat"
cp "$tmp/lambert.dat" "$tmp/lambert-mit.measured"
expect_ok "mit recognised by its header" render --brdf "$tmp/lambert-mit.measured" --size 8x8 --spp 2 --passes 1 --out "$tmp/d.png"
head -c 100000 "$tmp/lambert.dat" > "$tmp/truncated.dat"
expect_error "truncated mit file" "truncated MIT .dat file: 100000 bytes, expected 10077760" render --brdf "$tmp/truncated.dat" --out "$tmp/b.png"
{ printf '\22\0\0\0\22\0\0\0\110\0\0\0\44\0\0\0\0\0\0\0\0\0\0\0\2\0\0\0'; tail -c +29 "$tmp/lambert.dat"; } > "$tmp/param.dat"
expect_error "mit header" "header field 6 (parameterisation) is 2, expected 1" render --brdf "$tmp/param.dat" --out "$tmp/b.png"
expect_error "missing mit file" "none.dat: no such file" render --brdf "$tmp/none.dat" --out "$tmp/b.png"
# RGL-EPFL .bsdf materials: recognised by the tensor_file magic whatever their name; a damaged container names
# the field at fault.
expect_ok "measured-synth rgl" measured-synth --format rgl --brdf lambert --param albedo=0.5 --out "$tmp/lambert.bsdf"
[ "$(stat -c %s "$tmp/lambert.bsdf" 2>/dev/null)" = 213427 ] && passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: measured-synth rgl file size"; }
expect_ok "rgl render" render --brdf "$tmp/lambert.bsdf" --size 8x8 --spp 2 --passes 1 --out "$tmp/g.png"
cp "$tmp/lambert.bsdf" "$tmp/lambert-rgl.measured"
expect_ok "rgl recognised by its magic" render --brdf "$tmp/lambert-rgl.measured" --method brdf --brdf-sampler rgl-vndf --size 8x8 --spp 2 --passes 1 --out "$tmp/g.png"
expect_ok "measured-synth rgl anisotropic" measured-synth --format rgl --anisotropic --rgl-alpha 0.3 --brdf ggx --out "$tmp/aniso.bsdf"
listing=$("$iblx" render --list-methods --brdf "$tmp/aniso.bsdf" 2>&1)
if printf '%s' "$listing" | grep -q "RGL-EPFL measured anisotropic BRDF .*(17 phi_i x 10 theta_i views" &&
   printf '%s' "$listing" | grep -q "best sampler: rgl-vndf"; then
  passed=$((passed + 1))
else
  failed=$((failed + 1)); echo "FAIL: rgl --list-methods: $listing"
fi
head -c 200000 "$tmp/lambert.bsdf" > "$tmp/truncated.bsdf"
expect_error "truncated rgl file" "truncated.bsdf: field 'vndf''s data (40960 bytes at offset 172467) lies outside the 200000-byte file" render --brdf "$tmp/truncated.bsdf" --out "$tmp/b.png"
{ printf 'tensor_fila'; tail -c +12 "$tmp/lambert.bsdf"; } > "$tmp/magic.bsdf"
expect_error "rgl magic" 'magic.bsdf: not a tensor file (an RGL-EPFL .bsdf starts with "tensor_file")' render --brdf "$tmp/magic.bsdf" --out "$tmp/b.png"
# Byte 140 is the dtype of 'ndf' (the writer stores the fields in name order): 11, f64.
cp "$tmp/lambert.bsdf" "$tmp/f64.bsdf"
printf '\013' | dd of="$tmp/f64.bsdf" bs=1 seek=140 conv=notrunc status=none
expect_error "rgl dtype" "f64.bsdf: field 'ndf' holds f64 values, expected f32" render --brdf "$tmp/f64.bsdf" --out "$tmp/b.png"
expect_error "missing rgl file" "none.bsdf: no such file" render --brdf "$tmp/none.bsdf" --out "$tmp/b.png"
expect_error "rgl technique on ggx" "--brdf-sampler rgl-vndf does not apply to BRDF 'ggx'" render --brdf ggx --method brdf --brdf-sampler rgl-vndf --out "$tmp/b.png"
expect_error "measured-synth rgl extension" "must end in .bsdf" measured-synth --format rgl --out "$tmp/c.bin"
expect_error "measured-synth rgl alpha" "--rgl-alpha 0: out of range [0.001, 4]" measured-synth --format rgl --rgl-alpha 0 --out "$tmp/c.bsdf"
[ ! -e "$tmp/c.bsdf" ] && passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: measured-synth rgl wrote a file despite a bad flag"; }
# ALTA data files: text and binary, every parametrisation measured-synth writes; scattered samples are
# resampled with a warning; a .dat file that is ALTA text is not taken for an MIT file.
expect_ok "measured-synth alta" measured-synth --format alta --brdf lambert --param albedo=0.5 --out "$tmp/lambert.data"
expect_ok "alta render" render --brdf "$tmp/lambert.data" --size 8x8 --spp 2 --passes 1 --out "$tmp/a.png"
expect_ok "measured-synth alta binary" measured-synth --format alta --alta-param ISOTROPIC_TV_TL_DPHI --alta-output INV_STERADIAN_COSINE_FACTOR --alta-binary --brdf ggx --out "$tmp/ggx.data"
expect_ok "alta binary render" render --brdf "$tmp/ggx.data" --size 8x8 --spp 2 --passes 1 --out "$tmp/a.png"
cp "$tmp/lambert.data" "$tmp/lambert-alta.dat"
expect_ok "alta .dat recognised by its header" render --brdf "$tmp/lambert-alta.dat" --size 8x8 --spp 2 --passes 1 --out "$tmp/a.png"
expect_ok "measured-synth alta cartesian" measured-synth --format alta --alta-param CARTESIAN --alta-scattered 2000 --brdf lambert --out "$tmp/cart.data"
warning=$("$iblx" render --brdf "$tmp/cart.data" --size 8x8 --spp 2 --passes 1 --out "$tmp/a.png" 2>&1 >/dev/null)
printf '%s' "$warning" | grep -q "the 2000 CARTESIAN samples, read as SPHERICAL_TL_PL_TV_PV coordinates, are directions; resampled onto a 16 x 16 x 16 x 16 SPHERICAL_TL_PL_TV_PV grid" &&
  passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: alta resampling warning: $warning"; }
printf '#DIM 1 1\n#PARAM_IN COS_TLV\n-1 0.5\n0 1\n1 2\n' > "$tmp/tlv.data"
expect_ok "alta COS_TLV data" render --brdf "$tmp/tlv.data" --size 8x8 --spp 2 --passes 1 --out "$tmp/a.png"
printf '#DIM 1 1\n#PARAM_IN COS_TLX\n0 1\n' > "$tmp/tlx.data"
expect_error "alta data parametrisation" "tlx.data:2: unknown #PARAM_IN 'COS_TLX'; ALTA's parametrisations are RUSIN_TH_PH_TD_PD" render --brdf "$tmp/tlx.data" --out "$tmp/b.png"
# A parametrisation without a grid of its own is written as scattered samples in its coordinates (its
# coordinates were once written as SPHERICAL_TL_PL_TV_PV's four under its two-value header).
expect_ok "measured-synth alta NEUMANN_2D" measured-synth --format alta --alta-param NEUMANN_2D --brdf ggx --out "$tmp/neumann.data"
[ "$(sed -n 2p "$tmp/neumann.data" | grep -c "PARAM_IN NEUMANN_2D")$(grep -v '^#' "$tmp/neumann.data" | head -1 | wc -w)" = "15" ] &&
  passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: measured-synth NEUMANN_2D rows: $(head -5 "$tmp/neumann.data")"; }
expect_ok "alta NEUMANN_2D render" render --brdf "$tmp/neumann.data" --size 8x8 --spp 2 --passes 1 --out "$tmp/a.png"
# Shaped like ALTA's own example files: a 1D COS_TH slice with a doubled blank after #PARAM_IN, and
# retro-reflection measurements over ISOTROPIC_TL_TV_PROJ_DPHI without a #PARAM_OUT line.
{ printf '#DIM 1 3\n#PARAM_IN  COS_TH\n#PARAM_OUT RGB_COLOR\n'
  for c in 0.2 0.4 0.6 0.8 0.9 0.95 1.0; do printf '%s 0.1 0.2 %s\n' "$c" "$c"; done; } > "$tmp/felt-1d.alta"
expect_ok "alta COS_TH data" render --brdf "$tmp/felt-1d.alta" --size 8x8 --spp 2 --passes 1 --out "$tmp/felt.png"
awk 'BEGIN { srand(3); print "#DIM 3 1"; print "#PARAM_IN ISOTROPIC_TL_TV_PROJ_DPHI";
  for (i = 0; i < 3000; i++) { tl = rand() * 1.4; tv = rand() * 1.4; d = rand() * 6.283;
    printf "%.6f %.6f %.6f %.6f\n", tl, tv * cos(d), tv * sin(d), 0.1 + exp(-4 * tv * tv) } }' > "$tmp/retro.dat"
warning=$("$iblx" render --brdf "$tmp/retro.dat" --size 8x8 --spp 2 --passes 1 --out "$tmp/retro.png" 2>&1 >/dev/null)
printf '%s' "$warning" | grep -q "the 3000 ISOTROPIC_TL_TV_PROJ_DPHI samples, read as ISOTROPIC_TV_TL_DPHI coordinates, do not lie on a regular grid; resampled onto a 32 x 32 x 32 ISOTROPIC_TV_TL_DPHI grid by inverse-distance weighting of the 8 nearest samples (leave-one-out error" &&
  passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: alta retro resampling warning: $warning"; }
"$iblx" render --list-methods --brdf "$tmp/retro.dat" 2>/dev/null | grep -q "leave-one-out error" &&
  passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: --list-methods does not give the resampling's leave-one-out error"; }
printf '#DIM 3 1\n#PARAM_IN RUSIN_TH_TD_PD\n0 0 0 1\n0 0 zero 1\n' > "$tmp/nan.data"
expect_error "alta data number" "nan.data:4: 'zero' is not a number" render --brdf "$tmp/nan.data" --out "$tmp/b.png"
printf '#DIM 3 1\n#PARAM_IN RUSIN_TH_TD_PD\n#FORMAT binary\n#VERSION 0\n#PRECISION ieee754-double\n#ENDIAN little\n#SAMPLE_COUNT 9\n#BEGIN_STREAM\n12345678\n#END_STREAM\n' > "$tmp/short.data"
expect_error "alta binary stream length" "but #SAMPLE_COUNT 9 x 4 doubles needs 288" render --brdf "$tmp/short.data" --out "$tmp/b.png"
expect_error "missing alta data file" "none.data: no such file" render --brdf "$tmp/none.data" --out "$tmp/b.png"
expect_error "measured-synth alta param" "--alta-param COS_THX: valid: RUSIN_TH_PH_TD_PD" measured-synth --format alta --alta-param COS_THX --out "$tmp/c.data"

# ALTA function files: measured-synth writes an exact diffuse lobe for Lambert and a rational fit otherwise;
# recognised by their first line whatever their name; bad files are refused naming FILE:LINE.
expect_ok "measured-synth alta-func lambert" measured-synth --format alta-func --brdf lambert --param albedo=0.5 --out "$tmp/lambert.func"
grep -q "^#FUNC nonlinear_function_diffuse" "$tmp/lambert.func" && passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: measured-synth alta-func lambert wrote no diffuse lobe"; }
fit=$("$iblx" measured-synth --format alta-func --brdf ggx --param roughness=0.6 --fit-degree 3,2 --out "$tmp/ggx.func" 2>&1)
if printf '%s' "$fit" | grep -q "RMS relative error" && grep -q "^#FUNC rational_function" "$tmp/ggx.func"; then
  passed=$((passed + 1))
else
  failed=$((failed + 1)); echo "FAIL: measured-synth alta-func ggx: $fit"
fi
expect_ok "alta-func render" render --brdf "$tmp/lambert.func" --param diffuse_kd=0.2 --size 8x8 --spp 2 --passes 1 --out "$tmp/a.png"
expect_ok "alta-func rational render" render --brdf "$tmp/ggx.func" --size 8x8 --spp 2 --passes 1 --out "$tmp/a.png"
cp "$tmp/lambert.func" "$tmp/lambert-alta.txt"
expect_ok "alta-func recognised by its first line" render --brdf "$tmp/lambert-alta.txt" --method brdf --brdf-sampler isfunc --size 8x8 --spp 2 --passes 1 --out "$tmp/a.png"
listing=$("$iblx" render --list-methods --brdf "$tmp/ggx.func" 2>&1)
if printf '%s' "$listing" | grep -q "ALTA function file .*rational (RUSIN_TH_TD_PD, Chebyshev" &&
   printf '%s' "$listing" | grep -q "rational_scale"; then
  passed=$((passed + 1))
else
  failed=$((failed + 1)); echo "FAIL: alta-func --list-methods: $listing"
fi
printf '#ALTA FUNC HEADER\n#DIM 3 3\n#ALTA HEADER END\n#FUNC nonlinear_function_lafortune\n' > "$tmp/plugin.func"
expect_error "alta-func unknown plugin" "plugin.func:4: unknown plugin 'nonlinear_function_lafortune'" render --brdf "$tmp/plugin.func" --out "$tmp/b.png"
printf '#ALTA FUNC HEADER\n#DIM 3 3\n#ALTA HEADER END\n#FUNC nonlinear_function_blinn\nKs 1\nKs 2\n' > "$tmp/count.func"
expect_error "alta-func parameter count" "count.func:6: expected 'N <value>' (channel 1 of the blinn lobe)" render --brdf "$tmp/count.func" --out "$tmp/b.png"
printf '#ALTA FUNC HEADER\n#DIM 1 1\n#PARAM_IN STARK_9D\n#ALTA HEADER END\n#FUNC rational_function\n#MIN 0\n#MAX 1\n' > "$tmp/param.func"
expect_error "alta-func parametrisation" "param.func:3: #PARAM_IN STARK_9D: not one of ALTA's parametrisations: RUSIN_TH_PH_TD_PD" render --brdf "$tmp/param.func" --out "$tmp/b.png"
# A rational fit over STARK_2D, as ALTA's documentation fits gold-metallic-paint.
printf '#ALTA FUNC HEADER\n#CMD ALTA --func rational_function_chebychev\n#DIM 2 1\n#PARAM_IN  STARK_2D\n#ALTA HEADER END\n#FUNC rational_function\n#MIN 0 0\n#MAX 1 1\n#NP 2\n#NQ 1\n0 0 0.3\n1 0 0.1\n0 0 1\n' > "$tmp/stark.func"
expect_ok "alta-func over STARK_2D" render --brdf "$tmp/stark.func" --size 8x8 --spp 2 --passes 1 --out "$tmp/stark.png"
head -n 12 "$tmp/ggx.func" > "$tmp/cut.func"
expect_error "alta-func truncated" "cut.func:12: truncated file" render --brdf "$tmp/cut.func" --out "$tmp/b.png"
expect_error "missing alta-func file" "none.func: no such file" render --brdf "$tmp/none.func" --out "$tmp/b.png"
expect_error "alta-func params" "has no parameter 'roughness'" render --brdf "$tmp/lambert.func" --param roughness=0.1
expect_error "measured-synth fit degree" "--fit-degree 3: expected two integers P,Q in [0, 10]" measured-synth --format alta-func --fit-degree 3 --out "$tmp/c.func"
expect_error "measured-synth alta-func extension" "must end in .func" measured-synth --format alta-func --out "$tmp/c.bin"
expect_error "merl-synth extension" "must end in .binary" merl-synth --out "$tmp/c.bin"
expect_error "merl-synth fraction" "--invalid-fraction" merl-synth --invalid-fraction 2 --out "$tmp/c.binary"
warning=$("$iblx" merl-synth --brdf lambert --seed 3 --out "$tmp/seed.binary" 2>&1 >/dev/null)
if printf '%s' "$warning" | grep -q -- "--seed is ignored without --invalid-fraction"; then
  passed=$((passed + 1))
else
  failed=$((failed + 1)); echo "FAIL: merl-synth --seed warning: $warning"
fi
expect_error "merl file is a directory" "directory" render --brdf "$tmp/dir.binary" --out "$tmp/b.png"
[ ! -e "$tmp/b.png" ] && [ ! -e "$tmp/c.binary" ] && passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: output written despite a bad MERL input"; }

# BRDF Explorer files: a good one renders with every sampler that applies, can be saved as a .bparam that
# renders in turn; each kind of bad file names its line.
printf 'analytic\n::begin parameters\nfloat n 1 100 20\n::end parameters\n::begin shader\nvec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) {\n  vec3 R = reflect(-L, N);\n  return vec3(0.2) + vec3(0.3) * pow(max(dot(R, V), 0.0), n);\n}\n::end shader\n' > "$tmp/shiny.brdf"
expect_ok "brdf file render" render --brdf "$tmp/shiny.brdf" --param n=30 --size 8x8 --spp 2 --passes 1 --out "$tmp/s.png" --save-bparam "$tmp/shiny30.bparam"
grep -q "^float n 1 100 30$" "$tmp/shiny30.bparam" && passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: --save-bparam: $(cat "$tmp/shiny30.bparam")"; }
expect_ok "bparam render" render --brdf "$tmp/shiny30.bparam" --method brdf --size 8x8 --spp 2 --passes 1 --out "$tmp/s.png"
printf 'analytic\n::begin parameters\nvec3 c 1 1 1\n::end parameters\n' > "$tmp/badtype.brdf"
printf 'analytic\n::begin shader\nvec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) {\n  return oops;\n}\n::end shader\n' > "$tmp/badglsl.brdf"
printf 'analytic\n::begin shader\nvec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) { return L; }\n' > "$tmp/open.brdf"
printf 'bparam %s\n' "$tmp/none.brdf" > "$tmp/dangling.bparam"
expect_ok "merl-synth of a .brdf" merl-synth --brdf "$tmp/shiny.brdf" --param n=10 --out "$tmp/shiny.binary"
[ "$(stat -c %s "$tmp/shiny.binary" 2>/dev/null)" = 34992012 ] && passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: merl-synth of a .brdf: file size"; }
expect_error "brdf file missing" "none.brdf: no such file" render --brdf "$tmp/none.brdf" --out "$tmp/b.png"
expect_error "brdf parameter type" "badtype.brdf:3: unknown parameter type 'vec3'" render --brdf "$tmp/badtype.brdf" --out "$tmp/b.png"
expect_error "brdf glsl error" "badglsl.brdf:4" render --brdf "$tmp/badglsl.brdf" --size 8x8 --passes 1 --out "$tmp/b.png"
expect_error "brdf open section" "open.brdf:2: section 'shader' is never closed" render --brdf "$tmp/open.brdf" --out "$tmp/b.png"
expect_error "bparam target missing" "none.brdf: no such file" render --brdf "$tmp/dangling.bparam" --out "$tmp/b.png"
expect_error "brdf isfunc missing" "does not apply" render --brdf "$tmp/shiny.brdf" --method brdf --brdf-sampler isfunc --out "$tmp/b.png"
expect_error "save-bparam of a built-in" "--save-bparam: BRDF 'ggx' is built in" render --save-bparam "$tmp/g.bparam" --out "$tmp/b.png"
[ ! -e "$tmp/b.png" ] && [ ! -e "$tmp/g.bparam" ] && passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: output written despite a bad .brdf input"; }

# Objects and the camera: a good teapot, plane and OBJ render; each kind of bad --object, --orbit, --zoom and
# OBJ file gives its message.
expect_ok "teapot render" render --object teapot --size 16x16 --spp 4 --passes 1 --out "$tmp/teapot.png"
[ -s "$tmp/teapot.png" ] && passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: teapot render wrote no image"; }
expect_ok "grazing plane render" render --object plane --orbit 30,80 --zoom 2 --size 16x16 --spp 4 --passes 1 --out "$tmp/plane.png"
expect_ok "make-teapot" make-teapot --subdivisions 3 --out "$tmp/coarse.obj"
grep -q "^f " "$tmp/coarse.obj" && passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: make-teapot wrote no faces"; }
expect_ok "obj render" render --object "$tmp/coarse.obj" --orbit -30,20 --size 16x16 --spp 4 --passes 1 --out "$tmp/coarse.png"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n' > "$tmp/badface.obj"
printf 'v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n' > "$tmp/nan.obj"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\n' > "$tmp/nofaces.obj"
printf 'v 1 1 1\nv 1 1 1\nv 1 1 1\nf 1 2 3\n' > "$tmp/point.obj"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n' > "$tmp/range.obj"
expect_error "unknown object" "unknown --object 'cube'; valid: sphere, plane, teapot" render --object cube --out "$tmp/o.png"
expect_error "missing obj" "$tmp/none.obj: no such file" render --object "$tmp/none.obj" --out "$tmp/o.png"
expect_error "obj parse error" "badface.obj:4: bad 'f' line" render --object "$tmp/badface.obj" --out "$tmp/o.png"
expect_error "obj non-finite" "nan.obj:2: coordinate 'nan' is not finite" render --object "$tmp/nan.obj" --out "$tmp/o.png"
expect_error "obj without faces" "nofaces.obj: no faces" render --object "$tmp/nofaces.obj" --out "$tmp/o.png"
expect_error "degenerate obj" "point.obj: all vertices are at one point" render --object "$tmp/point.obj" --out "$tmp/o.png"
expect_error "obj index range" "range.obj: face 1 refers to vertex 7" reference --object "$tmp/range.obj" --out "$tmp/o.exr"
expect_error "orbit without comma" "--orbit 30: expected AZ,EL" render --orbit 30 --out "$tmp/o.png"
expect_error "orbit three values" "expected AZ,EL" render --orbit 1,2,3 --out "$tmp/o.png"
expect_error "orbit not a number" "not a number" render --orbit north,10 --out "$tmp/o.png"
expect_error "orbit elevation" "out of range [-90, 90]" render --orbit 0,95 --out "$tmp/o.png"
expect_error "zoom zero" "--zoom 0: must be > 0" render --zoom 0 --out "$tmp/o.png"
expect_error "zoom negative" "out of range" render --zoom -2 --out "$tmp/o.png"
expect_error "zoom not a number" "not a number" bench --zoom big
expect_error "make-teapot extension" "must end in .obj" make-teapot --out "$tmp/teapot.txt"
expect_error "make-teapot subdivisions" "--subdivisions 0" make-teapot --subdivisions 0 --out "$tmp/t.obj"
expect_error "make-teapot patch file" "none.txt: no such file" make-teapot --patches "$tmp/none.txt" --out "$tmp/t.obj"
[ ! -e "$tmp/o.png" ] && [ ! -e "$tmp/o.exr" ] && [ ! -e "$tmp/t.obj" ] && passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: output written despite a bad object or camera"; }

# samples: one pixel's samples as CSV; a bad pixel, count or output names the flag, and nothing is written.
expect_error "samples without pixel" "--pixel X,Y is required" samples --size 16x16 --out "$tmp/p.csv"
expect_error "samples pixel format" "--pixel 3.5,2: expected X,Y" samples --size 16x16 --pixel 3.5,2 --out "$tmp/p.csv"
expect_error "samples pixel one value" "--pixel 8: expected X,Y" samples --size 16x16 --pixel 8 --out "$tmp/p.csv"
expect_error "samples pixel outside" "--pixel 16,8: outside the 16x16 image" samples --size 16x16 --pixel 16,8 --out "$tmp/p.csv"
expect_error "samples pixel negative" "--pixel -1,8: outside" samples --size 16x16 --pixel -1,8 --out "$tmp/p.csv"
expect_error "samples pixel background" "--pixel 0,0: background" samples --size 16x16 --pixel 0,0 --out "$tmp/p.csv"
expect_error "samples count zero" "--count 0: out of range" samples --size 16x16 --pixel 8,8 --count 0 --out "$tmp/p.csv"
expect_error "samples count too large" "--count 20000000: out of range" samples --size 16x16 --pixel 8,8 --count 20000000 --out "$tmp/p.csv"
expect_error "samples count not a number" "--count many: not an integer" samples --size 16x16 --pixel 8,8 --count many --out "$tmp/p.csv"
expect_error "samples output format" "use a .csv file name" samples --size 16x16 --pixel 8,8 --out "$tmp/p.txt"
expect_error "samples output dir" "does not exist" samples --size 16x16 --pixel 8,8 --out "$tmp/no/dir/p.csv"
expect_error "samples unknown method" "unknown --method 'bogus'" samples --size 16x16 --pixel 8,8 --method bogus --out "$tmp/p.csv"
[ ! -e "$tmp/p.csv" ] && [ ! -e "$tmp/p.txt" ] && passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: samples wrote a file despite bad input"; }
expect_ok "samples mis" samples --size 16x16 --pixel 8,8 --count 100 --spp 16 --mis-split 0.3 --out "$tmp/s.csv"
# A header and one row per sample, both techniques, 7 passes of 16 (the last one of 4).
if [ "$(wc -l < "$tmp/s.csv")" -eq 101 ] && head -1 "$tmp/s.csv" | grep -q "^index,pass,technique,dir_x,dir_y,dir_z,u,v,pdf," \
  && grep -q ",env-cdf," "$tmp/s.csv" && grep -q ",ggx-vndf," "$tmp/s.csv" && tail -1 "$tmp/s.csv" | grep -q "^99,6,"; then
  passed=$((passed + 1))
else
  failed=$((failed + 1)); echo "FAIL: samples CSV: $(head -3 "$tmp/s.csv")"
fi
rows=$("$iblx" samples --size 16x16 --pixel 8,8 --count 5 --method brdf --seq sobol --out - 2>/dev/null | grep -c ",ggx-vndf,")
[ "$rows" -eq 5 ] && passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: samples --out - gave $rows rows"; }
# product-mis: its product rows name the chosen node (column, row, P in (0, 1]), its BRDF rows leave them empty.
"$iblx" samples --size 16x16 --pixel 8,8 --count 6 --method product-mis --out "$tmp/pn.csv" > /dev/null 2>&1
nodes=$(awk -F, 'NR == 1 { ok = $NF == "product_node_p" } NR > 1 && $3 == "product" && $22 ~ /^[0-9]+$/ && $23 ~ /^[0-9]+$/ && $24 > 0 && $24 <= 1 { n++ }
  NR > 1 && $3 != "product" && ($22 != "" || $24 != "") { ok = 0 } END { print ok ? n + 0 : -1 }' "$tmp/pn.csv")
[ "$nodes" -eq 6 ] && passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: samples product nodes: $nodes of 6: $(head -3 "$tmp/pn.csv")"; }

# converge and hardcases: bad input, a small run's files, and Ctrl-C keeping what was measured.
export IBLX_CACHE_DIR="$tmp/cache"
expect_error "converge unknown case" "unknown hard case 'sunny'; valid: sun-1e3" converge --case sunny
expect_error "converge bad method word" "--method mis:bogus: unknown option 'bogus'" converge --method mis:bogus
expect_error "converge bad M" "M must be 1-64" converge --method ris:M=99
expect_error "converge method for another BRDF" "merl-table" converge --brdf lambert --method brdf:merl-table --size 8x8 --out-dir "$tmp/c0"
expect_error "converge spp above budget" "--spp 64 exceeds --max-spp 16" converge --spp 64 --max-spp 16
expect_error "converge oracle stride alone" "--oracle-stride: needs --oracle" converge --oracle-stride 4
expect_error "converge oracle stride 0" "--oracle-stride" converge --oracle --oracle-stride 0
# tools/oracle_grid.sh refuses a bad size or stride before it measures anything.
oracle_grid=$(dirname "$0")/../../tools/oracle_grid.sh
for args in "--size x" "--size 0" "--stride -1" "--size 64 --stride 0" "--sizes 64"; do
  # shellcheck disable=SC2086 # the flags are words
  out=$(bash "$oracle_grid" $args "$(dirname "$iblx")" "$tmp/oracle-grid" 2>&1)
  status=$?
  if [ $status -eq 2 ] && [ "$(printf '%s\n' "$out" | grep -c .)" -eq 1 ] && [ ! -e "$tmp/oracle-grid" ]; then
    passed=$((passed + 1))
  else
    failed=$((failed + 1))
    echo "FAIL: oracle_grid.sh $args: exit $status, output: $out"
  fi
done
# Its --help is the header's usage alone (regression: it printed every comment of the script after it).
help=$(bash "$oracle_grid" --help)
if [ "$(printf '%s\n' "$help" | grep -c .)" -eq 2 ] && [ "${help%%$'\n'*}" != "${help#Usage: }" ]; then
  passed=$((passed + 1))
else
  failed=$((failed + 1))
  echo "FAIL: oracle_grid.sh --help: $help"
fi
expect_error "hardcases unknown case" "unknown hard case" hardcases --case nope
"$iblx" reference --size 8x8 --out "$tmp/ref8.exr" > /dev/null 2>&1
expect_error "converge reference size" "does not match the scene's 16x16" converge --size 16x16 --reference-file "$tmp/ref8.exr" --out-dir "$tmp/c1"
[ ! -e "$tmp/c0" ] && [ ! -e "$tmp/c1" ] && passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: converge created its output directory despite bad input"; }
# An --out-dir that cannot be created is reported before the ground truth is computed.
: > "$tmp/a-file"
IBLX_CACHE_DIR="$tmp/cache-od" expect_error "converge out-dir under a file" "--out-dir $tmp/a-file/sub: cannot create it: $tmp/a-file is not a directory" \
  converge --brdf lambert --size 8x8 --method env-cdf --max-spp 8 --out-dir "$tmp/a-file/sub"
[ ! -e "$tmp/cache-od/references" ] && passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: converge computed the ground truth before finding its --out-dir unusable"; }
expect_ok "converge small" converge --brdf lambert --size 16x16 --method env-cdf --method mis:power --seq sobol --seeds 2 --spp 4 --max-spp 32 --out-dir "$tmp/conv"
for f in converge.csv summary.md reference.exr mse_vs_spp.png relmse_vs_time.png heat-01-env-cdf-sobol.png; do
  [ -s "$tmp/conv/$f" ] && passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: converge did not write $f"; }
done
# 2 methods x 2 seeds x the points 4, 5, 6, 7, 8, 10, ..., 27, 32 (4 per octave over 3 octaves: 13) + the header.
rows=$(wc -l < "$tmp/conv/converge.csv")
[ "$rows" -eq 53 ] && passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: converge.csv has $rows lines, expected 53"; }
grep -q "from the cache" <("$iblx" converge --brdf lambert --size 16x16 --method env-cdf --seq random --seeds 1 --max-spp 8 --out-dir "$tmp/conv2" 2>&1) \
  && passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: the second converge did not use the cached reference"; }
# SIGTERM once the runs have begun (the reference is in the cache): exit 130 with the rows measured so far, as
# for Ctrl-C, which shares its handler (tools/cli/measurement.cpp; study_test.sh sends both). A job scheduler
# stops work with SIGTERM; it used to end the process and lose every finished run.
IBLX_CACHE_DIR="$tmp/cache-int" "$iblx" converge --size 32x32 --method uniform --seq random --seeds 50 --time 2 \
  --out-dir "$tmp/int" > /dev/null 2>&1 &
pid=$!
for _ in $(seq 300); do compgen -G "$tmp/cache-int/references/*.exr" > /dev/null && break; sleep 0.2; done
# A second converge into the same --out-dir meanwhile is refused (both used to exit 0, their files mixed).
IBLX_CACHE_DIR="$tmp/cache-int" expect_error "converge into a directory another converge writes" \
  "--out-dir $tmp/int is being written by another iblx" converge --size 32x32 --method uniform --seq random \
  --seeds 1 --max-spp 8 --out-dir "$tmp/int"
# So is a hardcases run (it had no lock).
expect_error "hardcases into a directory a converge writes" "--out-dir $tmp/int is being written by another iblx" \
  hardcases --case zero-half --quick --method env-cdf --seq sobol --max-spp 16 --out-dir "$tmp/int"
sleep 2
kill -TERM $pid
wait $pid
status=$?
lines=$(wc -l < "$tmp/int/converge.csv" 2>/dev/null || echo 0)
[ $status -eq 130 ] && [ "$lines" -gt 1 ] && passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: SIGTERM: exit $status, $lines CSV lines"; }
expect_ok "hardcases quick" hardcases --case zero-half --quick --method env-cdf --seq sobol --max-spp 64 --out-dir "$tmp/hard"
[ -s "$tmp/hard/hardcases.md" ] && [ -s "$tmp/hard/zero-half.csv" ] && passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: hardcases wrote no report"; }
# A case where every method asked for is skipped at a device limit (here a 1 MiB buffer cap) is reported as such,
# and the next case still runs.
out=$(IBLX_MAX_BUFFER_MIB=1 "$iblx" hardcases --case sun-1e3 --case zero-half --method env-ot --seq sobol --max-spp 32 2>&1)
if [ "$(grep -c "Nothing ran on" <<< "$out")" -eq 2 ] && grep -q "needs 3 MiB, more than this device's largest storage buffer (1 MiB)" <<< "$out" \
  && grep -q "every method that ran passed; 2 skipped at a device limit" <<< "$out"; then
  passed=$((passed + 1))
else
  failed=$((failed + 1)); echo "FAIL: hardcases with every method skipped: $out"
fi
IBLX_MAX_BUFFER_MIB=lots expect_error "buffer cap not a number" "IBLX_MAX_BUFFER_MIB='lots': use a whole number of MiB from 1 to 4095" render --size 8x8 --out "$tmp/cap.png"

# otmap: a missing map, a grid size out of range or an output that is not a PNG names the culprit; nothing is
# written.
expect_error "otmap missing env" "$tmp/nope.exr" otmap --env "$tmp/nope.exr" --out "$tmp/om.png"
expect_error "otmap corrupt env" "garbage.exr" otmap --env "$tmp/garbage.exr" --out "$tmp/om.png"
expect_error "otmap size too small" "--size 32: out of range [64, 1024]" otmap --size 32 --out "$tmp/om.png"
expect_error "otmap size too large" "--size 2048: out of range [64, 1024]" otmap --size 2048 --out "$tmp/om.png"
expect_error "otmap size not a number" "--size big: not an integer" otmap --size big --out "$tmp/om.png"
expect_error "otmap bad floor" "--floor 0: out of range" otmap --floor 0 --out "$tmp/om.png"
expect_error "otmap bad max-iter" "--max-iter 0: out of range" otmap --max-iter 0 --out "$tmp/om.png"
expect_error "otmap output not png" "use a .png file name" otmap --out "$tmp/om.exr"
expect_error "otmap output dir" "does not exist" otmap --out "$tmp/no/dir/om.png"
# --diagnose reports on the samplers' own map: a flag that shapes or draws another map is refused, and so is
# --subgrid without it.
expect_error "otmap diagnose with a grid size" "--size does not apply" otmap --diagnose --size 128
expect_error "otmap diagnose with a figure" "--out does not apply" otmap --diagnose --out "$tmp/om.png"
expect_error "otmap subgrid without diagnose" "--subgrid: only with --diagnose" otmap --subgrid 4 --out "$tmp/om.png"
expect_error "otmap diagnose subgrid out of range" "--subgrid 0: out of range [1, 16]" otmap --diagnose --subgrid 0
[ ! -e "$tmp/om.png" ] && [ ! -e "$tmp/om.exr" ] && passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: otmap wrote a file despite bad input"; }

# The viewer: flags are checked before a window opens; without a display it says so (no crash).
expect_error "view: screenshot not png" "--screenshot" view --frames 1 --screenshot "$tmp/shot.jpg"
expect_error "view: bad tonemap" "--tonemap" view --tonemap filmic
expect_error "view: zero frames" "--frames" view --frames 0
expect_error "view: bad gamma" "--gamma" view --gamma 9
expect_error "view: unknown method" "nope" view --method nope --frames 1
expect_error "view: unknown flag" "--passes" view --passes 3
out=$(env -u DISPLAY -u WAYLAND_DISPLAY "$iblx" view --frames 1 2>&1 >/dev/null)
status=$?
[ $status -ne 0 ] && printf '%s' "$out" | grep -qF "cannot open a window" && passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: view without a display: exit $status, $out"; }
[ ! -e "$tmp/shot.jpg" ] && passed=$((passed + 1)) || { failed=$((failed + 1)); echo "FAIL: view wrote a .jpg"; }

echo "cli: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
