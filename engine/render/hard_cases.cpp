// The hard-case suite (engine/render/hard_cases.h).
#include "engine/render/hard_cases.h"

#include "engine/core/error.h"
#include "engine/core/join.h"
#include "engine/io/image_write.h"
#include "engine/io/synthetic_envs.h"
#include "engine/io/latlong_texel.h"
#include "engine/core/sphere_mapping.h"

#include <unistd.h>

#include <cmath>
#include <filesystem>

namespace iblx {
namespace {

using Params = std::vector<std::pair<std::string, std::string>>;

SceneSpec sceneOf(std::string brdf, Params params, std::string object = "sphere", CameraSpec camera = {}) {
  SceneSpec spec;
  spec.brdf = std::move(brdf);
  spec.params = std::move(params);
  spec.object = std::move(object);
  spec.camera = camera;
  spec.width = spec.height = 64;
  return spec;
}

// A smooth sky, w x w/2, with a sun `ratio` times its mean in 2 x 2 texels at (w/3, w/5).
EnvImage skyWithSun(int w, double ratio) {
  return sunOverSky(w, w / 2, ratio, 2, w / 3, w / 5);
}
EnvImage skyWithSun1e4(int w) {
  return skyWithSun(w, 1e4);
}

HardCase sunCase(const std::string& exponent, double ratio) {
  return {"sun-" + exponent,
          "smooth sky with a sun " + exponent + " times its mean in 2x2 texels; GGX a = 0.2, metal",
          sceneOf("ggx", {{"roughness", "0.2"}, {"metallic", "1"}}),
          [ratio](int w) { return skyWithSun(w, ratio); }};
}

// More than 2^24 texels: 6144 x 3072 (18.9 M), a constant sky of 1 and a sun of 1e6 in 3 x 3 texels at row
// 2800, whose flat texel indices (about 1.72e7) are beyond what a float counts exactly. Its radiance (216
// MiB) exceeds lavapipe's largest storage buffer, so it also exercises the chunked upload.
constexpr int kHugeWidth = 6144, kHugeHeight = 3072, kHugeSunX = 1000, kHugeSunY = 2800, kHugeSunTexels = 3;
constexpr double kHugeSun = 1e6;

EnvImage hugeEnvironment(int) {
  EnvImage image{kHugeWidth, kHugeHeight,
                 std::vector<float>(3 * std::size_t(kHugeWidth) * kHugeHeight, 1.0f)};
  for (int y = kHugeSunY; y < kHugeSunY + kHugeSunTexels; ++y)
    for (int x = kHugeSunX; x < kHugeSunX + kHugeSunTexels; ++x)
      for (int c = 0; c < 3; ++c) image.rgb[3 * image.index(x, y) + c] = float(kHugeSun);
  return image;
}

// Lambert under the huge map: rho (1 + sum over sun texels of (L - 1) / pi * integral of max(0, n.w) dw),
// the integral by a 16 x 16 midpoint rule in the texel's (phi, cos theta) square (texelToDirection).
std::vector<float> hugeLambertReference(const Scene& scene) {
  const auto albedo = scene.params.at("albedo");
  std::vector<float> rgb(3 * scene.gbuffer.pixels.size(), 0.0f);
  constexpr int kPoints = 16;
  for (std::size_t i = 0; i < scene.gbuffer.pixels.size(); ++i) {
    const auto& pixel = scene.gbuffer.pixels[i];
    if (pixel.normal.w == 0.0f) continue;
    const glm::dvec3 n = worldToEnv(
        glm::normalize(glm::dvec3(pixel.normal.x, pixel.normal.y, pixel.normal.z)), scene.envRotationDeg);
    double sunIrradiance = 0.0;
    for (int y = kHugeSunY; y < kHugeSunY + kHugeSunTexels; ++y) {
      const double omega = latLongTexelSolidAngle(y, kHugeWidth, kHugeHeight);
      for (int x = kHugeSunX; x < kHugeSunX + kHugeSunTexels; ++x)
        for (int a = 0; a < kPoints; ++a)
          for (int b = 0; b < kPoints; ++b) {
            const glm::dvec3 w =
                texelToDirection(x, y, {(a + 0.5) / kPoints, (b + 0.5) / kPoints}, kHugeWidth, kHugeHeight);
            sunIrradiance += std::max(0.0, glm::dot(n, w)) * omega / (kPoints * kPoints);
          }
    }
    const double radiance = 1.0 + (kHugeSun - 1.0) * sunIrradiance / kPi;
    for (int c = 0; c < 3; ++c) rgb[3 * i + c] = float(albedo[c] * radiance);
  }
  return rgb;
}

// NaN, +Inf, -Inf and negative texels sprinkled over a smooth sky with a sun.
EnvImage brokenEnvironment(int w) {
  EnvImage image = skyWithSun1e4(w);
  const float broken[] = {std::nanf(""), INFINITY, -INFINITY, -5.0f};
  for (std::size_t i = 0, k = 0; i < image.rgb.size(); i += 97, ++k) image.rgb[i] = broken[k % 4];
  return image;
}

std::vector<HardCase> makeHardCases() {
  std::vector<HardCase> cases = {sunCase("1e3", 1e3), sunCase("1e4", 1e4), sunCase("1e5", 1e5),
                                 sunCase("1e6", 1e6)};
  cases.push_back({"zero-half",
                   "sky of 1 on the upper half, a 1e6 sun in 2 texels, the lower half exactly 0; Lambert",
                   sceneOf("lambert", {}), [](int w) { return sunAndZeroHalf(w, w / 2); }});
  cases.push_back({"pole", "energy in the two top rows (1000x), 1e-3 elsewhere; GGX a = 0.05 dielectric",
                   sceneOf("ggx", {{"roughness", "0.05"}, {"metallic", "0"}}),
                   [](int w) { return poleEnergy(w, w / 2); }});
  cases.push_back(
      {"grazing",
       "a plane seen 85 degrees from its normal (every pixel has n.wo = 0.087) under a 1e4 sun; GGX "
       "a = 0.3",
       sceneOf("ggx", {{"roughness", "0.3"}}, "plane", {0.0, 85.0, 1.0}), skyWithSun1e4});
  HardCase mirror{"mirror", "GGX a = 1e-3, metal (a near-mirror lobe) under a smooth sky with a 1e4 sun",
                  sceneOf("ggx", {{"roughness", "0.001"}, {"metallic", "1"}}), skyWithSun1e4};
  // The reference's cost grows with (texel / lobe)^2 per texel near the mirror direction: on 64-texel-wide
  // maps a 1e-3 lobe needs 197^2 sub-cells per texel (minutes), on 256-wide ones 49^2 (seconds).
  mirror.testEnvWidth = 256;
  mirror.zTested = false;
  cases.push_back(mirror);
  HardCase broken{
      "bad-texels",
      "an EXR with NaN, +Inf, -Inf and negative texels (1 in 97 values), repaired at load; GGX a = 0.3",
      sceneOf("ggx", {{"roughness", "0.3"}}), brokenEnvironment};
  broken.viaFile = true;
  cases.push_back(broken);
  HardCase huge{
      "huge-map",
      "6144 x 3072 (18.9 M texels): a constant sky and a 1e6 sun at texel indices above 2^24; Lambert, "
      "with a closed-form reference",
      sceneOf("lambert", {}), hugeEnvironment};
  huge.scene.width = huge.scene.height = 32;
  huge.exactReference = hugeLambertReference;
  huge.excludedMethods = {"uniform", "cosine", "brdf"};
  huge.exclusionReason =
      "the sun covers 2.5e-6 sr: uniform, cosine and BRDF samples almost never reach it, so their images "
      "carry no "
      "variance to judge them by";
  cases.push_back(huge);
  return cases;
}

}  // namespace

std::span<const HardCase> hardCases() {
  static const std::vector<HardCase> cases = makeHardCases();
  return cases;
}

const HardCase& findHardCase(const std::string& name) {
  for (const auto& c : hardCases())
    if (c.name == name) return c;
  throw Error("unknown hard case '" + name + "'; valid: " + joinNames(hardCases(), &HardCase::name));
}

Scene makeHardCaseScene(const HardCase& hardCase, HardCaseSize size) {
  SceneSpec spec = hardCase.scene;
  EnvImage env = hardCase.environment(size == HardCaseSize::Full ? hardCase.envWidth : hardCase.testEnvWidth);
  if (size == HardCaseSize::Test) spec.width = spec.height = std::min(spec.width, 24);
  if (!hardCase.viaFile) return makeScene(std::move(env), spec);  // synthetic maps are valid by construction
  spec.envPath = std::filesystem::temp_directory_path() /
                 ("iblx-hardcase-" + hardCase.name + "-" + std::to_string(::getpid()) + ".exr");
  writeExr(spec.envPath, env.width, env.height, env.rgb);
  struct Remove {
    std::filesystem::path path;
    ~Remove() {
      std::error_code ignored;
      std::filesystem::remove(path, ignored);
    }
  } remove{spec.envPath};
  return loadScene(spec);
}

}  // namespace iblx
