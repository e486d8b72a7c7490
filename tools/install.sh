#!/usr/bin/env bash
# Quick start: installs what is missing (Debian 12 packages only), builds iblx in Release and renders the default
# scene (unit sphere, built-in GGX, assets/default_sky.exr) to render.png, printing samples per second and time.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(build-essential cmake ninja-build pkg-config
          libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers vulkan-tools
          glslang-dev glslang-tools spirv-tools libglm-dev libopenexr-dev libstb-dev libtinyobjloader-dev
          doctest-dev
          libopenblas-dev liblapacke-dev  # the dense fronts of the OT solver's grid LU (OpenBLAS, lapack.h)
          libglfw3-dev libimgui-dev xvfb xauth  # the viewer, and its test under Xvfb
          nlohmann-json3-dev  # every --json output (engine/core/json_output.h)
          libtomlplusplus-dev  # the plan files of `iblx study`
          libnanoflann-dev  # the k-d tree that resamples scattered ALTA data
          slurmctld slurmd slurm-client munge  # tests/cli/slurm_study_test.sh: a one-node Slurm cluster
          python3  # the study tests compare merged CSVs
          chromium  # the report.html test: the page loaded in a real browser, headless
          clang-14 libclang-rt-14-dev  # tools/fuzz.sh: libFuzzer (the sanitizer stage uses gcc's ASan/UBSan)
          blender-data)  # the CC0 HDRIs of the studies in docs/studies/ and the OT benchmarks (studiolights/world/*.exr)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "iblx: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}"
fi

cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)"
if [ "${1:-}" != "--no-render" ]; then
  ./build/iblx render
fi
