// Named environment-map fixtures shared by every sampler test: the hard cases of docs/DESIGN.md §5 at small sizes
// (the generators are engine/io/synthetic_envs.h).
#pragma once

#include "engine/io/synthetic_envs.h"

#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

namespace iblx::test {

struct NamedEnv {
  std::string name;
  EnvImage image;
};

// The list every environment-sampler test loops over: smooth, sun + zero half, pole energy, at a power-of-two
// size and at an odd size (padding in env-hier, cells not aligned with texels).
inline std::vector<NamedEnv> samplerTestEnvs() {
  std::vector<NamedEnv> envs;
  for (const auto& [w, h] : {std::pair{64, 32}, std::pair{50, 25}}) {
    const std::string size = std::to_string(w) + "x" + std::to_string(h);
    envs.push_back({"smooth-" + size, smoothSky(w, h)});
    envs.push_back({"sun-zero-" + size, sunAndZeroHalf(w, h)});
    envs.push_back({"pole-" + size, poleEnergy(w, h)});
  }
  return envs;
}

}  // namespace iblx::test
