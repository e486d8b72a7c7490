# Shared by the command-line test scripts (sourced): a private temporary directory, removed on exit, with its
# own on-disk cache, and the tally of passed and failed checks.
set -u
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export IBLX_CACHE_DIR="$tmp/cache"
passed=0
failed=0
pass() { passed=$((passed + 1)); }
fail() { failed=$((failed + 1)); echo "FAIL: $*"; }

# A small study plan (tests/cli/study_test.sh, slurm_study_test.sh): two scenes (Lambert, GGX 0.3) x METHODS x
# SEQUENCES x two seeds, SIZE x SIZE, a fixed spp budget so that errors are deterministic.
# Usage: study_plan DIRECTORY SIZE SPP SEQUENCES METHODS   (the lists as TOML items: '"env-cdf", "mis"')
study_plan() {
  cat << EOF
title = "study test"
directory = "$1"
size = $2
max_spp = $3
seeds = 2
sequences = [$4]
methods = [$5]
target_relmse = 1e-2
[[scene]]
name = "lambert"
brdf = "lambert"
[[scene]]
name = "ggx"
brdf = "ggx"
params = { roughness = 0.3 }
EOF
}
# The sorted error rows of a merged study.csv (scene, id, label, sequence, seed, spp, mse, relmse), after their
# count: what must not depend on how the runs were split or interrupted.
study_errors() { python3 -c '
import csv, sys
rows = sorted((r["scene"], r["id"], r["label"], r["sequence"], r["seed"], r["spp"], r["mse"], r["relmse"])
              for r in csv.DictReader(open(sys.argv[1])))
print(len(rows)); [print(*r) for r in rows]' "$1"; }
