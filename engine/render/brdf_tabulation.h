// Evaluation of a scene's BRDF (its compiled GLSL part, so every BRDF iblx can render) at direction pairs on
// the GPU. `iblx merl-synth` tabulates built-in BRDFs into MERL files with it; the tests compare GPU
// evaluations with CPU ones.
#pragma once

#include "engine/render/scene.h"
#include "engine/vk/shader_compiler.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace iblx {

// f(wi, wo) in 1/sr for each pair (local frame: normal +z), evaluated as the integrator would. Runs in chunks
// within the device's dispatch and buffer limits.
std::vector<glm::dvec3> evaluateBrdf(const VulkanContext& context, ShaderCompiler& compiler,
                                     const Scene& scene, std::span<const glm::dvec3> wi,
                                     std::span<const glm::dvec3> wo);

// A built-in BRDF tabulated in MERL's layout: the values of writeMerl (3 * kMerlBins, planar, 1/sr), each the
// BRDF at its bin's centre (merlBinCenter). A centre direction at or below the horizon is evaluated at the
// nearest direction 1e-3 above it, so every bin that valid pairs fall into holds the BRDF's value (a Lambert
// table is exactly constant) — unless `invalidBelowHorizon`, which writes -1 there as measured files do.
// `invalidFraction` of the bins, chosen by `seed`, are also written as -1.
struct MerlSynthOptions {
  bool invalidBelowHorizon = false;
  double invalidFraction = 0.0;
  uint32_t seed = 1;
};
struct MerlSynthResult {
  std::vector<double> values;
  std::size_t invalidBins = 0;
};
MerlSynthResult tabulateMerl(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                             const MerlSynthOptions& options = {});

}  // namespace iblx
