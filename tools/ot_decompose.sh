#!/usr/bin/env bash
# Where each environment sampler loses at equal time against env-hier with sobol, in factors (docs/BENCHMARKS.md,
# "Optimal-transport sampling"). For every map and material (Lambert, GGX a = 0.1 sphere) it runs `iblx converge`
# of the samplers with random and sobol, `iblx otmap --diagnose` per map and, unless --fast,
# tools/instructions_per_sample.sh per map and sampler (Lambert, sobol), and prints per map x material a table:
#   (i)   C: MSE = C / spp fitted to the random runs (slope fixed at -1): the variance per sample, the pdf alone;
#   (ii)  Q = MSE_sobol(N) / (C / N) at the spp N the sampler reaches at equal time: its interaction with QMC;
#         and the free log-log slopes of MSE against spp with random and with sobol;
#   (iii) ns per sample: GPU timestamps over spp x the object's pixels (the sobol runs); instructions per
#         sample (callgrind, Lambert only);
#   (iv)  chi^2(p_texel || p_sampler), the non-convex quads of an OT sampler's map, the round trip of its map.
# Curves are the medians over seeds, point by point; fits skip the first two points of six or more, as
# `iblx converge` does.
#
# Attribution. Equal time is the GPU time T of the shortest sobol run; N_s = the spp sampler s reaches at T
# and M_s(N) its sobol MSE at spp N (log-log interpolation of its curve, extrapolated with its fitted slope).
# The equal-time loss against env-hier (h) splits exactly as
#   R = M_s(N_s) / M_h(N_h)
#     = [C_s / C_h]                                 pdf:  variance per sample, random numbers
#     x [(M_s(N_s) N_s / C_s) / (M_h(N_s) N_s / C_h)]  QMC:  Q_s / Q_h, both at the same spp N_s
#     x (N_h / N_s)^(-b_h)                          cost: env-hier's MSE with N_s instead of N_h samples, b_h its
#                                                         fitted sobol slope (N_h / N_s: the cost per sample ratio)
#     x residual                                    M_h(N_s) / M_h(N_h) / (N_h / N_s)^(-b_h): env-hier's sobol
#                                                         curve off its fitted power law between N_s and N_h.
# The first two factors multiply to M_s(N_s) / M_h(N_s) whatever the fit, so the residual is 1 when env-hier's
# sobol MSE follows its power law.
#
# Usage: tools/ot_decompose.sh [--seconds S (2)] [--seeds K (2)] [--size N (64)] [--methods A,B,...]
#                              [--maps NAME|FILE,... (forest,sunrise,city,courtyard)] [--out DIR (/tmp/ot-decompose)]
#                              [--fast (no callgrind)]
# The methods default to IBLX_DECOMPOSE_METHODS, else env-cdf,env-hier,env-ot-inv,env-ot-fwd, plus env-ot when
# `iblx render --list-methods` lists it; env-hier must be among them. A map NAME is a file of Blender's studio
# lights (/usr/share/blender/datafiles/studiolights/world/NAME.exr). The raw outputs go under DIR: per map and
# material converge.csv and summary.md, per map the diagnostics (JSON lines) and instruction counts, the tables
# (report.md).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
iblx="$root/build/iblx"
world=/usr/share/blender/datafiles/studiolights/world
seconds=2
seeds=2
size=64
methods="${IBLX_DECOMPOSE_METHODS:-}"
maps=forest,sunrise,city,courtyard
out=/tmp/ot-decompose
fast=0

usage() { sed -n '/^# Usage:/,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; }
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) seconds="${2:?--seconds needs a value}"; shift 2 ;;
    --seeds) seeds="${2:?--seeds needs a value}"; shift 2 ;;
    --size) size="${2:?--size needs a value}"; shift 2 ;;
    --methods) methods="${2:?--methods needs a value}"; shift 2 ;;
    --maps) maps="${2:?--maps needs a value}"; shift 2 ;;
    --out) out="${2:?--out needs a value}"; shift 2 ;;
    --fast) fast=1; shift ;;
    -h | --help) usage; exit 0 ;;
    *) echo "ot_decompose.sh: unknown argument '$1'" >&2; usage >&2; exit 2 ;;
  esac
done
[ -x "$iblx" ] || { echo "ot_decompose.sh: $iblx missing: build it first (README)" >&2; exit 1; }
if [ -z "$methods" ]; then
  methods=env-cdf,env-hier,env-ot-inv,env-ot-fwd
  if "$iblx" render --list-methods 2> /dev/null | grep -q '^  env-ot '; then methods="$methods,env-ot"; fi
fi
case ",$methods," in *,env-hier,*) ;; *) echo "ot_decompose.sh: --methods must include env-hier (the baseline)" >&2; exit 1 ;; esac
[ "$fast" = 1 ] || command -v valgrind > /dev/null || { echo "ot_decompose.sh: valgrind missing (or use --fast)" >&2; exit 1; }
IFS=, read -r -a method_list <<< "$methods"
IFS=, read -r -a map_list <<< "$maps"
mkdir -p "$out"
started=$SECONDS

# Pixels of the sphere at size x size that the integrator shades: pixel centres inside the unit disc
# (pixelToImagePlane and sphereNormalAt of engine/core/sphere_mapping.h).
pixels=$(awk -v n="$size" 'BEGIN { for (j = 0; j < n; ++j) for (i = 0; i < n; ++i) {
  x = 2 * (i + 0.5) / n - 1; y = 1 - 2 * (j + 0.5) / n; c += (x * x + y * y < 1) } print c }')

declare -A brdf=([lambert]="--brdf lambert" [ggx-0.1]="--brdf ggx --param roughness=0.1")
{
  echo "# tools/ot_decompose.sh: $seconds s per run, $seeds seeds, ${size}x${size}, $(date -u '+%Y-%m-%d %H:%M UTC')"
  echo
  echo "Methods $methods; maps $maps$([ "$fast" = 1 ] && echo '; --fast (no instruction counts)')."
  echo
} > "$out/report.md"
for map in "${map_list[@]}"; do
  if [ -f "$map" ]; then file="$map"; name="$(basename "${map%.*}")"; else file="$world/$map.exr"; name="$map"; fi
  [ -f "$file" ] || { echo "ot_decompose.sh: $file missing: install blender-data (tools/install.sh)" >&2; exit 1; }
  echo "ot_decompose: $name: offline diagnostics" >&2
  "$iblx" otmap --env "$file" --diagnose --json > "$out/$name-diagnose.jsonl" 2> "$out/$name-diagnose.log"
  : > "$out/$name-instructions.txt"
  : > "$out/$name-instructions.log"
  if [ "$fast" = 0 ]; then
    for method in "${method_list[@]}"; do
      echo "ot_decompose: $name: instructions per sample of $method (callgrind)" >&2
      # A second try before giving up on a count: a failed one leaves "—" in its column, not a lost run.
      line=""
      for _ in 1 2; do
        if line=$("$root/tools/instructions_per_sample.sh" "$method" --env "$file" --brdf lambert --seq sobol \
          2>> "$out/$name-instructions.log"); then break; fi
        line=""
      done
      count=$(sed -nE 's/.*: ([0-9]+) instructions per sample$/\1/p' <<< "$line")
      [ -n "$count" ] || echo "ot_decompose.sh: no instruction count of $method on $name (see $out/$name-instructions.log)" >&2
      echo "$method $count" >> "$out/$name-instructions.txt"
    done
  fi
  for material in lambert ggx-0.1; do
    dir="$out/$name-$material"
    mkdir -p "$dir"
    echo "ot_decompose: $name, $material: converge (${#method_list[@]} methods x random, sobol x $seeds seeds x $seconds s)" >&2
    method_flags=()
    for method in "${method_list[@]}"; do method_flags+=(--method "$method"); done
    # shellcheck disable=SC2086  # the material's flags are words
    "$iblx" converge --env "$file" ${brdf[$material]} --size "${size}x${size}" --time "$seconds" --seeds "$seeds" \
      --seq random --seq sobol "${method_flags[@]}" --target-relmse 1e-2 --no-plots --out-dir "$dir" \
      > /dev/null 2> "$dir/converge.log"
    rm -f "$dir/reference.exr"
    instructions="$out/$name-instructions.txt"
    [ "$material" = lambert ] || instructions=/dev/null
    {
      echo "## $name, $material"
      echo
      awk -v methods="$methods" -v pixels="$pixels" -v csv="$dir/converge.csv" -v diag="$out/$name-diagnose.jsonl" \
        -v instr="$instructions" -f /dev/stdin "$dir/converge.csv" "$out/$name-diagnose.jsonl" "$instructions" <<'AWK'
# Reads converge.csv, the diagnostics' JSON lines and "METHOD COUNT" lines; prints the table and the attribution.
function isnum(v) { return v ~ /^[-+]?[0-9.]+([eE][-+]?[0-9]+)?$/ }
function jfield(line, key,    m) {  # the value of "key": in a flat JSON line ("" when absent)
  if (!match(line, "\"" key "\": [^,}]*")) return ""
  m = substr(line, RSTART + length(key) + 4, RLENGTH - length(key) - 4)
  return m == "null" ? "" : m
}
function median(a, n,    i, j, t) {  # sorts a[1..n] in place
  for (i = 2; i <= n; ++i) for (j = i; j > 1 && a[j - 1] > a[j]; --j) { t = a[j]; a[j] = a[j - 1]; a[j - 1] = t }
  return n % 2 ? a[(n + 1) / 2] : (a[n / 2] + a[n / 2 + 1]) / 2
}
function fmt(v, f) { return v == "" ? "—" : sprintf(f == "" ? "%.3g" : f, v) }
# Fits over the curve's tail (the first two points skipped when it has six or more).
function first(k) { return cN[k] >= 6 ? 3 : 1 }
function fitC(k,    i, s, c) { for (i = first(k); i <= cN[k]; ++i) { s += log(cMse[k, i] * cSpp[k, i]); ++c } return c ? exp(s / c) : "" }
function fitSlope(k,    i, x, y, sx, sy, sxx, sxy, c) {
  for (i = first(k); i <= cN[k]; ++i) { x = log(cSpp[k, i]); y = log(cMse[k, i]); sx += x; sy += y; sxx += x * x; sxy += x * y; ++c }
  return c >= 3 ? (c * sxy - sx * sy) / (c * sxx - sx * sx) : ""
}
# MSE at spp n: log-log interpolation, extrapolated with the fitted slope beyond either end.
function mseAt(k, n,    i, t) {
  if (n <= cSpp[k, 1]) return cMse[k, 1] * exp(slope[k] * log(n / cSpp[k, 1]))
  for (i = 2; i <= cN[k]; ++i)
    if (n <= cSpp[k, i]) {
      t = log(n / cSpp[k, i - 1]) / log(cSpp[k, i] / cSpp[k, i - 1])
      return exp(log(cMse[k, i - 1]) + t * log(cMse[k, i] / cMse[k, i - 1]))
    }
  return cMse[k, cN[k]] * exp(slope[k] * log(n / cSpp[k, cN[k]]))
}
# spp at GPU time t: linear in time between the recorded points (proportional before the first).
function sppAt(k, t,    i) {
  if (t <= cGpu[k, 1]) return cSpp[k, 1] * t / cGpu[k, 1]
  for (i = 2; i <= cN[k]; ++i)
    if (t <= cGpu[k, i]) return cSpp[k, i - 1] + (cSpp[k, i] - cSpp[k, i - 1]) * (t - cGpu[k, i - 1]) / (cGpu[k, i] - cGpu[k, i - 1])
  return cSpp[k, cN[k]] * t / cGpu[k, cN[k]]
}
FILENAME == csv && FNR > 1 {
  # The method label is quoted (labels may hold commas): cut it off first.
  close_quote = index(substr($0, 2), "\"")
  method = substr($0, 2, close_quote - 1)
  split(substr($0, close_quote + 3), f, ",")  # sequence, seed, pass, spp, gpu_s, wall_s, mse, relmse
  k = method SUBSEP f[1]
  if (!((k, f[2]) in seedSeen)) { seedSeen[k, f[2]] = 1; seedList[k] = seedList[k] " " f[2] }
  spp[k, f[3]] = f[4]; gpu[k, f[3], f[2]] = f[5]; mse[k, f[3], f[2]] = f[7]
  if (f[3] > last[k, f[2]]) last[k, f[2]] = f[3]
  next
}
FILENAME == diag { s = jfield($0, "sampler"); gsub(/"/, "", s); chi2[s] = jfield($0, "chi2"); convex[s] = jfield($0, "non_convex_share")
  tripMax[s] = jfield($0, "round_trip_max"); tripMean[s] = jfield($0, "round_trip_mean"); next }
FILENAME == instr && NF == 2 { instructions[$1] = $2; next }
END {
  count = split(methods, order, ",")
  # Median curves over seeds, over the passes every seed reached, skipping points below the reference's noise.
  for (m = 1; m <= count; ++m) for (q = 1; q <= 2; ++q) {
    k = order[m] SUBSEP (q == 1 ? "random" : "sobol")
    ns = split(seedList[k], sl, " ")
    if (ns == 0) { print "ot_decompose.sh: no runs of " order[m] " in " csv > "/dev/stderr"; exit 1 }
    passes = last[k, sl[1]]
    for (i = 2; i <= ns; ++i) if (last[k, sl[i]] < passes) passes = last[k, sl[i]]
    for (p = 1; p <= passes; ++p) {
      nm = ng = 0
      for (i = 1; i <= ns; ++i) {
        v = mse[k, p, sl[i]]; if (isnum(v) && v > 0) ms[++nm] = v
        tg[++ng] = gpu[k, p, sl[i]]
      }
      if (nm == 0) continue
      n = ++cN[k]; cSpp[k, n] = spp[k, p]; cMse[k, n] = median(ms, nm); cGpu[k, n] = median(tg, ng)
    }
    if (cN[k] < 3) { print "ot_decompose.sh: fewer than 3 points for " order[m] "/" (q == 1 ? "random" : "sobol") > "/dev/stderr"; exit 1 }
    slope[k] = fitSlope(k)
  }
  # Equal time: the end of the shortest sobol curve.
  T = ""
  for (m = 1; m <= count; ++m) { k = order[m] SUBSEP "sobol"; if (T == "" || cGpu[k, cN[k]] < T) T = cGpu[k, cN[k]] }
  h = "env-hier"; hr = h SUBSEP "random"; hs = h SUBSEP "sobol"
  Ch = fitC(hr); Nh = sppAt(hs, T); Mh = mseAt(hs, Nh); bh = slope[hs]
  printf "Equal GPU time %.3g s (the shortest sobol run); %d object pixels; ns and instructions per sample with sobol.\n\n", T, pixels
  print "| sampler | (i) C = MSE·spp, random | (i) C / env-hier's | (ii) Q = sobol / random at equal spp | slopes random / sobol | (iii) ns / sample | (iii) instr. / sample | (iv) χ² | (iv) non-convex | (iv) round trip max / mean | equal-time MSE, sobol / env-hier's |"
  print "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
  for (m = 1; m <= count; ++m) {
    s = order[m]; kr = s SUBSEP "random"; ks = s SUBSEP "sobol"
    C[s] = fitC(kr); N[s] = sppAt(ks, T); M[s] = mseAt(ks, N[s])
    Q[s] = M[s] * N[s] / C[s]; Qh[s] = mseAt(hs, N[s]) * N[s] / Ch
    ns_per = cGpu[ks, cN[ks]] / (cSpp[ks, cN[ks]] * pixels) * 1e9
    trip = tripMax[s] == "" ? "—" : (tripMean[s] == "" ? fmt(tripMax[s]) : fmt(tripMax[s]) " / " fmt(tripMean[s]))
    printf "| %s | %s | %.2f | %.3g | %.2f / %.2f | %.1f | %s | %s | %s | %s | %.2f |\n", s, fmt(C[s]), C[s] / Ch, Q[s],
      slope[kr], slope[ks], ns_per, instructions[s] == "" ? "—" : instructions[s], fmt(chi2[s]),
      convex[s] == "" ? "—" : sprintf("%.2f %%", 100 * convex[s]), trip, M[s] / Mh
  }
  printf "\nAttribution of the equal-time loss against env-hier with sobol, R = pdf × QMC × cost × residual (slope of env-hier with sobol %.2f):\n\n", bh
  for (m = 1; m <= count; ++m) {
    s = order[m]; if (s == h) continue
    pdf = C[s] / Ch; qmc = Q[s] / Qh[s]; cost = exp(-bh * log(Nh / N[s])); R = M[s] / Mh
    printf "- `%s`: R = %.2f = pdf %.2f × QMC %.2f × cost %.2f (N = %d against env-hier's %d) × residual %.2f\n",
      s, R, pdf, qmc, cost, N[s], Nh, R / (pdf * qmc * cost)
  }
}
AWK
      echo
    } | tee -a "$out/report.md"
  done
done
echo "ot_decompose: $(( SECONDS - started )) s; raw outputs and report.md in $out" >&2
