#!/usr/bin/env bash
# Builds iblx (Release, with tests) and runs the whole test suite: CPU unit tests, GPU tests on the Vulkan device
# present (lavapipe without a GPU), and the command-line tests. Exits non-zero when any test fails.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install.sh --no-render
# Validation layers check every GPU test's Vulkan usage when installed (a validation error fails the test).
IBLX_VALIDATION=1 ctest --test-dir build --output-on-failure --timeout 1500
