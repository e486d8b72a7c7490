// GPU evaluation of a BRDF part at direction pairs (shaders/brdf_eval.comp).
#include "engine/render/brdf_tabulation.h"

#include "engine/core/error.h"
#include "engine/render/kernel_assembly.h"
#include "engine/vk/compute_kernel.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace iblx {

std::vector<glm::dvec3> evaluateBrdf(const VulkanContext& context, ShaderCompiler& compiler,
                                     const Scene& scene, std::span<const glm::dvec3> wi,
                                     std::span<const glm::dvec3> wo) {
  if (wi.size() != wo.size()) throw Error("evaluateBrdf: as many wi as wo are needed");
  const SceneGpu gpu = uploadScene(context, scene);
  KernelParts parts{"brdf_eval.comp",
                    {scene.brdf->evalPart},
                    paramBlockGlsl(*scene.brdf),
                    brdfBindingDefines(gpu.brdfData.size())};
  const auto spirv = compiler.compile(assemblePrelude(parts), "brdf eval " + scene.brdf->name);
  const auto set3 = gpu.brdfSet();
  KernelLayout layout{{0, 2, 0, uint32_t(set3.size())}, sizeof(uint32_t)};
  ComputeKernel kernel(context, spirv, layout, "brdf eval");
  kernel.bindBuffers(3, set3);

  const auto& limits = context.limits();
  const std::size_t maxPairs =
      std::min<std::size_t>({std::size_t(limits.maxComputeWorkGroupCount[0]) * 64,
                             limits.maxStorageBufferRange / (2 * sizeof(glm::vec4)), std::size_t(1) << 20});
  std::vector<glm::dvec3> values;
  values.reserve(wi.size());
  for (std::size_t begin = 0; begin < wi.size(); begin += maxPairs) {
    const std::size_t count = std::min(maxPairs, wi.size() - begin);
    std::vector<glm::vec4> pairs(2 * count);
    for (std::size_t i = 0; i < count; ++i) {
      pairs[2 * i] = glm::vec4(glm::vec3(wi[begin + i]), 0.0f);
      pairs[2 * i + 1] = glm::vec4(glm::vec3(wo[begin + i]), 0.0f);
    }
    Buffer in = Buffer::fromData(context, pairs, "brdf eval pairs");
    Buffer out(context, count * sizeof(glm::vec4), "brdf eval values");
    kernel.bindBuffers(1, {&in, &out});
    const uint32_t pairCount = uint32_t(count);
    context.submitAndWait([&](vk::CommandBuffer cmd) {
      kernel.record(cmd, uint32_t((count + 63) / 64), 1, &pairCount, sizeof pairCount);
      recordShaderWriteBarrier(cmd, true);
    });
    for (const glm::vec4& v : out.readAll<glm::vec4>()) values.emplace_back(v.x, v.y, v.z);
  }
  return values;
}

namespace {
constexpr double kLiftZ = 1e-3;

glm::dvec3 liftAboveHorizon(glm::dvec3 w) {
  if (w.z >= kLiftZ) return w;
  const double planar = std::hypot(w.x, w.y);
  if (!(planar > 0.0)) return {0.0, 0.0, 1.0};
  const double scale = std::sqrt(1.0 - kLiftZ * kLiftZ) / planar;
  return {w.x * scale, w.y * scale, kLiftZ};
}
}  // namespace

MerlSynthResult tabulateMerl(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                             const MerlSynthOptions& options) {
  std::vector<glm::dvec3> wi(kMerlBins), wo(kMerlBins);
  std::vector<bool> belowHorizon(kMerlBins, false);
  for (int h = 0; h < kMerlThetaHBins; ++h)
    for (int d = 0; d < kMerlThetaDBins; ++d)
      for (int p = 0; p < kMerlPhiDBins; ++p) {
        const std::size_t bin = merlBinIndex(h, d, p);
        const DirectionPair pair = merlBinCenter(h, d, p);
        belowHorizon[bin] = pair.wi.z <= 0.0 || pair.wo.z <= 0.0;
        wi[bin] = liftAboveHorizon(pair.wi);
        wo[bin] = liftAboveHorizon(pair.wo);
      }
  const std::vector<glm::dvec3> f = evaluateBrdf(context, compiler, scene, wi, wo);
  MerlSynthResult result;
  result.values.resize(3 * kMerlBins);
  std::mt19937_64 rng(options.seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (std::size_t bin = 0; bin < kMerlBins; ++bin) {
    const bool invalid = (options.invalidBelowHorizon && belowHorizon[bin]) ||
                         (options.invalidFraction > 0.0 && uniform(rng) < options.invalidFraction);
    result.invalidBins += invalid ? 1 : 0;
    for (int c = 0; c < 3; ++c) result.values[std::size_t(c) * kMerlBins + bin] = invalid ? -1.0 : f[bin][c];
  }
  return result;
}

}  // namespace iblx
