// The hard-case suite (docs/DESIGN.md §5): named scenes that stress samplers (suns 1e3-1e6 over a few
// texels, an exactly-zero half, energy at a pole, grazing-only pixels, a near-mirror GGX, a file with NaN,
// Inf and negative texels, a map of more than 2^24 texels). `iblx hardcases` runs every method on each and
// checks finite output and convergence to the reference; `iblx converge --case NAME` measures one; the GPU
// tests run each at a small size.
#pragma once

#include "engine/scene/scene.h"

#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace iblx {

struct HardCase {
  std::string name;
  std::string description;
  SceneSpec scene;  // BRDF, parameters, object, camera and the full image size (envPath unused)
  // The environment at `width` texels across (height width/2); cases whose point is the map's size ignore it.
  std::function<EnvImage(int width)> environment;
  int envWidth = 256;     // full size
  int testEnvWidth = 64;  // test size
  bool viaFile = false;   // written as an EXR and read back, so the loader's sanitation is part of the case
  // False when the z-test cannot judge the estimators at a test's budget: the near-mirror lobe under a sun, where
  // GGX's long tail carries the sun's light into pixels whose mirror direction misses it. VNDF samples reach that
  // tail so rarely that at hundreds of spp the estimate has not seen it and its sample variance shows no sign of
  // it (the reference agrees with itself to 1e-5 between 24 and 50 sub-cells per texel; a pixel's estimate is
  // 1.19 against 2.16). Such a case still checks finite output; its z is reported, not judged.
  bool zTested = true;
  // Methods left out of the default list, and why (e.g. a light no sample of theirs reaches within a budget).
  std::vector<std::string> excludedMethods;
  std::string exclusionReason;
  // A closed-form ground truth (object pixels; background left 0), where the convolution would take minutes.
  std::function<std::vector<float>(const Scene&)> exactReference;
};

std::span<const HardCase> hardCases();
// Throws iblx::Error listing the valid names.
const HardCase& findHardCase(const std::string& name);

enum class HardCaseSize {
  Full,
  Test
};  // Test: testEnvWidth-wide maps, 24 px images (the huge map stays huge)

// The case's scene. A case with viaFile writes its map to a temporary EXR and loads it like --env would
// (warning with the count of repaired texels).
Scene makeHardCaseScene(const HardCase& hardCase, HardCaseSize size = HardCaseSize::Full);

}  // namespace iblx
