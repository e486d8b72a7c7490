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
