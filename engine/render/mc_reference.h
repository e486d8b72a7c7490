// A Monte Carlo ground truth, for scenes where the exact convolution (engine/render/reference.h) would take
// minutes: two independent runs of one method, with different seeds and half the budget each. The image is
// their mean M = (A + B)/2, and its own error is estimated from the halves: for independent A and B of one
// variance s^2, E[(A - B)^2] / 4 = s^2 / 2 = Var(M). An error measured against M exceeds the true one by
// Var(M) on average, which the measurements subtract (ReferenceNoise).
#pragma once

#include "engine/render/reference.h"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>

namespace iblx {

struct McReferenceOptions {
  MethodSpec method = [] {
    MethodSpec m;  // two-sample MIS under Owen-scrambled Sobol': applies to every BRDF, robust under suns
    m.sequence = "sobol";
    return m;
  }();
  double seconds = 20.0;  // both runs together, wall time of rendering
  std::uint32_t seedA = 0x6d630001u, seedB = 0x6d630002u;
  std::function<void(double fraction)> progress;  // may throw to abandon (Ctrl-C)
};

// The expected error of M = (A + B)/2 over the object pixels: mean of (A - B)^2 / 4, and of that over
// (M^2 + 0.01) for relMSE, as compareToReference averages them.
ReferenceNoise referenceNoise(const GBuffer& gbuffer, std::span<const float> a, std::span<const float> b);

ReferenceImage computeMcReference(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                                  const McReferenceOptions& options);

// The same through the on-disk cache: each half is an entry of its own (a sealed EXR keyed by the scene, the
// method, the budget and the seed), so a damaged half is reported and rendered again alone.
ReferenceImage cachedMcReference(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                                 const std::filesystem::path& cacheDir, const McReferenceOptions& options,
                                 bool* fromCache = nullptr);

}  // namespace iblx
