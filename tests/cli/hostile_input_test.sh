#!/usr/bin/env bash
# Command-line tests of inputs that try to break iblx, as an attacker or a careless user would: files that are
# not regular files, sizes beyond the device or the memory budget, values beyond float range, .brdf programs
# that would crash, stall or hang the GPU compiler or the device, outputs on a full device, and Ctrl-C. Each
# must end in one clear line and the right exit status, promptly; nothing partial is written.
# Usage: hostile_input_test.sh path/to/iblx
iblx="$1"
source "$(dirname "$0")/common.sh"

# expect_error "description" "substring of the first line of stderr" args...: non-zero exit within 60 s, and the
# message's first line holds the substring.
expect_error() {
  local what="$1" pattern="$2"
  shift 2
  local out status
  out=$(timeout 60 "$iblx" "$@" 2>&1 >/dev/null)
  status=$?
  if [ $status -ne 0 ] && [ $status -ne 124 ] && printf '%s\n' "$out" | grep -v "warning" | head -1 | grep -qF -- "$pattern"; then
    pass
  else
    fail "$what: exit $status, stderr: $out (expected a first line containing: $pattern)"
  fi
}

# Files that are not regular files: refused at once, never opened (a FIFO would block forever).
mkfifo "$tmp/fifo.exr"
ln -s /dev/zero "$tmp/zero.hdr"
ln -s /dev/zero "$tmp/zero.brdf"
ln -s /dev/zero "$tmp/zero.obj"
expect_error "FIFO as --env" "fifo.exr: it is a FIFO" render --env "$tmp/fifo.exr" --size 8x8 --out "$tmp/a.png"
expect_error "/dev/zero as .hdr" "zero.hdr: it is a device" render --env "$tmp/zero.hdr" --size 8x8 --out "$tmp/a.png"
expect_error "/dev/zero as .brdf" "zero.brdf: it is a device" render --brdf "$tmp/zero.brdf" --size 8x8 --out "$tmp/a.png"
expect_error "/dev/zero as .obj" "zero.obj: it is a device" render --object "$tmp/zero.obj" --size 8x8 --out "$tmp/a.png"

# Sizes: refused before anything is built, naming the flag and the figure.
expect_error "--size at the parser's maximum" "--size 16384x16384: the G-buffer needs 12 GiB" render --size 16384x16384 --out "$tmp/a.png"
expect_error "--size above the device's buffers" "images up to about" reference --size 3000x3000 --out "$tmp/a.exr"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4294967299\n' > "$tmp/wrap.obj"
expect_error "OBJ index that wraps" "wrap.obj:4: index 4294967299 is out of range" render --object "$tmp/wrap.obj" --size 8x8 --out "$tmp/a.png"
# converge --case with --size=WxH (one word) uses that size.
out=$(timeout 120 "$iblx" converge --case sun-1e4 --size=8x8 --method env-cdf --seq random --seeds 1 --max-spp 8 --out-dir "$tmp/c8" 2>&1 >/dev/null)
printf '%s' "$out" | grep -q ", 8x8)" && pass || fail "converge --case --size=8x8: $out"

# Values beyond float headroom: refused naming the file (one policy for every technique).
printf '#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 2\n\200\200\200\377\200\200\200\200' > "$tmp/e255.hdr"
expect_error "RGBE exponent 255" "e255.hdr: texel (0, 0) holds 8.51e+37, above the largest radiance" render --env "$tmp/e255.hdr" --size 8x8 --out "$tmp/a.png"
printf '#?RADIANCE\r\nFORMAT=32-bit_rle_rgbe\r\n\r\n-Y 1 +X 2\r\n\200\200\200\200\200\200\200\200' > "$tmp/crlf.hdr"
timeout 60 "$iblx" render --env "$tmp/crlf.hdr" --size 8x8 --spp 1 --passes 1 --out "$tmp/crlf.png" > /dev/null 2>&1 && [ -s "$tmp/crlf.png" ] \
  && pass || fail "a Radiance header with CR LF line ends was refused"
timeout 120 "$iblx" merl-synth --brdf lambert --out "$tmp/huge.binary" > /dev/null 2>&1
printf '\377\377\377\377\377\377\357\177' | dd of="$tmp/huge.binary" bs=1 seek=52 conv=notrunc status=none  # DBL_MAX in bin 5 (R)
expect_error "MERL value beyond 1e15" "huge.binary: bin 5 of channel R holds" render --brdf "$tmp/huge.binary" --size 8x8 --out "$tmp/a.png"

# .brdf files are programs for the GPU compiler: refused before compiling when they would crash or stall it.
{ printf 'analytic\n::begin shader\nvec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) {\n  return vec3(1.0'
  for _ in $(seq 400); do printf '+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0+1.0'; done
  printf ');\n}\n::end shader\n'; } > "$tmp/sum.brdf"
expect_error "20 000-term sum" "sum.brdf:4: a statement with more than 2000 operators" render --brdf "$tmp/sum.brdf" --size 8x8 --out "$tmp/a.png"
{ printf 'analytic\n::begin parameters\n'; seq -f 'float p%.0f 0 1 0.5' 1 300; printf '::end parameters\n'; } > "$tmp/params.brdf"
expect_error "300 parameters" "params.brdf:259: more than 256 parameters" render --brdf "$tmp/params.brdf" --size 8x8 --out "$tmp/a.png"
head -c 300000 /dev/zero | tr '\0' ' ' > "$tmp/large.brdf"
expect_error "a 300 KB .brdf" "large.brdf: the file is 293 KiB (300000 bytes), more than the 256 KiB" render --brdf "$tmp/large.brdf" --size 8x8 --out "$tmp/a.png"
# A BRDF() that never returns: the dispatch times out into one line and exit status 4, not a hang.
printf 'analytic\n::begin parameters\nfloat k 0 1 0.5\n::end parameters\n::begin shader\nvec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) {\n  float x = L.z;\n  while (x < 2.0) { x = x * k; }\n  return vec3(x);\n}\n::end shader\n' > "$tmp/loop.brdf"
out=$(IBLX_GPU_TIMEOUT_S=3 timeout 60 "$iblx" render --brdf "$tmp/loop.brdf" --size 8x8 --passes 1 --out "$tmp/loop.png" 2>&1 >/dev/null)
status=$?
[ $status -eq 4 ] && printf '%s' "$out" | grep -q "did not finish a dispatch within 3 s" && [ ! -e "$tmp/loop.png" ] \
  && pass || fail "a never-ending BRDF(): exit $status, $out"
# A compile past its time budget (here 1 ms, on an empty cache) ends the same way, naming the limit.
out=$(IBLX_COMPILE_TIMEOUT_S=0.001 IBLX_CACHE_DIR="$tmp/cold-cache" timeout 60 "$iblx" render --size 8x8 --passes 1 --out "$tmp/cold.png" 2>&1 >/dev/null)
status=$?
[ $status -eq 4 ] && printf '%s' "$out" | grep -q "took more than 0.001 s (IBLX_COMPILE_TIMEOUT_S" && [ ! -e "$tmp/cold.png" ] \
  && pass || fail "a compile past IBLX_COMPILE_TIMEOUT_S: exit $status, $out"
# Paths with a quote, a backslash or a newline compile; a GLSL error's first line names the file and line.
printf 'analytic\n::begin shader\nvec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) { return vec3(0.2); }\n::end shader\n' > "$tmp/q\"uo\\te.brdf"
cp "$tmp/q\"uo\\te.brdf" "$tmp/new"$'\n'"line.brdf"
timeout 120 "$iblx" render --brdf "$tmp/q\"uo\\te.brdf" --size 8x8 --spp 1 --passes 1 --out "$tmp/q.png" > /dev/null 2>&1 && pass || fail "a .brdf path with a quote and a backslash"
timeout 120 "$iblx" render --brdf "$tmp/new"$'\n'"line.brdf" --size 8x8 --spp 1 --passes 1 --out "$tmp/n.png" > /dev/null 2>&1 && pass || fail "a .brdf path with a newline"
printf 'analytic\n::begin shader\nvec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) {\n  return oops;\n}\n::end shader\n' > "$tmp/badglsl.brdf"
expect_error "GLSL error, first line" "badglsl.brdf:4: 'oops' : undeclared identifier" render --brdf "$tmp/badglsl.brdf" --size 8x8 --out "$tmp/a.png"
printf 'bparam %s\n' "$tmp/badglsl.brdf" > "$tmp/points.bparam"
printf 'bparam %s\n' "$tmp/params.brdf" > "$tmp/limits.bparam"
expect_error ".bparam to a bad .brdf names the .bparam" "limits.bparam:1: " render --brdf "$tmp/limits.bparam" --size 8x8 --out "$tmp/a.png"
# A BRDF that returns 1e38 renders; any warning about NaN/Inf estimates names the file, not only a sampler bug.
printf 'analytic\n::begin shader\nvec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) { return vec3(1e38); }\n::end shader\n' > "$tmp/bright.brdf"
out=$(timeout 120 "$iblx" render --brdf "$tmp/bright.brdf" --method env-cdf --size 8x8 --spp 4 --passes 1 --out "$tmp/b.png" 2>&1 >/dev/null)
status=$?
[ $status -eq 0 ] && { ! printf '%s' "$out" | grep -q "NaN/Inf" || printf '%s' "$out" | grep -q "bright.brdf may return values beyond float range"; } \
  && pass || fail "a BRDF returning 1e38: exit $status, $out"
# The same from an ALTA function file (any BRDF read from a file): its NaN/Inf estimates name the file.
printf '#ALTA FUNC HEADER\n#DIM 1 1\n#PARAM_IN COS_TH\n#ALTA HEADER END\n#FUNC rational_function\n#MIN 0\n#MAX 1\n#NP 1\n#NQ 1\n0 1e37\n0 1\n' > "$tmp/huge.func"
out=$(timeout 120 "$iblx" render --brdf "$tmp/huge.func" --method env-cdf --size 8x8 --spp 4 --passes 1 --out "$tmp/h.png" 2>&1 >/dev/null)
status=$?
[ $status -eq 0 ] && printf '%s' "$out" | grep -q "huge.func may return values beyond float range" \
  && pass || fail "an ALTA function returning 1e37: exit $status, $out"
[ ! -e "$tmp/a.png" ] && [ ! -e "$tmp/a.exr" ] && pass || fail "an output was written despite hostile input"

# Outputs on a full device (a file-size limit of 0 stands in for it): every writer exits non-zero naming its
# file, and leaves nothing behind.
full() { (trap '' XFSZ; ulimit -f 0; timeout 120 "$iblx" "$@"); }
mkdir -p "$tmp/full"
for out in img.png img.exr; do
  msg=$(full render --size 16x16 --spp 2 --passes 1 --out "$tmp/full/$out" 2>&1 >/dev/null)
  status=$?
  [ $status -ne 0 ] && printf '%s' "$msg" | grep -q "cannot write.*$out" && pass || fail "render $out on a full device: exit $status, $msg"
done
msg=$(full render --brdf "$tmp/q\"uo\\te.brdf" --size 8x8 --spp 1 --passes 1 --save-bparam "$tmp/full/s.bparam" --out "$tmp/q.png" 2>&1 >/dev/null)
[ $? -ne 0 ] && printf '%s' "$msg" | grep -q "cannot write.*s.bparam" && pass || fail "--save-bparam on a full device: $msg"
msg=$(full otmap --size 64 --out "$tmp/full/om.png" 2>&1 >/dev/null)
[ $? -ne 0 ] && printf '%s' "$msg" | grep -q "cannot write.*om.png" && pass || fail "otmap on a full device: $msg"
msg=$(full converge --brdf lambert --size 8x8 --method env-cdf --seq random --seeds 1 --max-spp 8 --out-dir "$tmp/full/conv" 2>&1 >/dev/null)
[ $? -ne 0 ] && printf '%s' "$msg" | grep -q "cannot write.*converge.csv" && pass || fail "converge on a full device: $msg"
msg=$(full samples --size 16x16 --pixel 8,8 --count 10 --out "$tmp/full/s.csv" 2>&1 >/dev/null)
[ $? -ne 0 ] && printf '%s' "$msg" | grep -q "cannot write.*s.csv" && pass || fail "samples on a full device: $msg"
leftover=$(find "$tmp/full" -type f | wc -l)
[ "$leftover" -eq 0 ] && pass || fail "files left on the full device: $(find "$tmp/full" -type f)"

# Ctrl-C: render writes the image accumulated so far and exits 130; converge interrupted in its ground truth
# exits 130 and writes nothing.
"$iblx" render --size 16x16 --spp 4 --passes 10000000 --out "$tmp/int.png" > /dev/null 2> "$tmp/int.err" &
pid=$!
sleep 4
kill -INT $pid
wait $pid
status=$?
[ $status -eq 130 ] && [ -s "$tmp/int.png" ] && grep -q "writing the image accumulated so far" "$tmp/int.err" \
  && pass || fail "Ctrl-C in render: exit $status, $(tr '\r' '\n' < "$tmp/int.err" | tail -2)"
"$iblx" converge --size 96x96 --brdf ggx --param roughness=0.01 --no-cache --time 1 --out-dir "$tmp/cint" > /dev/null 2> "$tmp/cint.err" &
pid=$!
sleep 4
kill -INT $pid
wait $pid
status=$?
[ $status -eq 130 ] && grep -q "interrupted: the ground truth was" "$tmp/cint.err" && [ ! -e "$tmp/cint" ] \
  && pass || fail "Ctrl-C in converge's ground truth: exit $status, $(tr '\r' '\n' < "$tmp/cint.err" | tail -2)"

echo "hostile inputs: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
