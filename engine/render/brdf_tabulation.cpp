// GPU evaluation of a BRDF part at direction pairs (shaders/brdf_eval.comp).
#include "engine/render/brdf_tabulation.h"

#include "engine/core/error.h"
#include "engine/core/hash.h"
#include "engine/io/mit_brdf.h"
#include "engine/io/utia.h"
#include "engine/render/kernel_assembly.h"
#include "engine/render/scene_gpu.h"
#include "engine/scene/brdf_params.h"
#include "engine/core/sphere_mapping.h"
#include "engine/vk/compute_kernel.h"

#include <algorithm>
#include <map>
#include <mutex>
#include <cmath>
#include <random>

namespace iblx {

struct BrdfEvaluator::State {
  const VulkanContext& context;
  SceneGpu gpu;
  std::unique_ptr<ComputeKernel> kernel;
};

BrdfEvaluator::BrdfEvaluator(const VulkanServices& services, const Scene& scene, bool unguarded)
    : state_(
          std::make_unique<State>(State{services.context, uploadScene(services.context, scene), nullptr})) {
  KernelParts parts = brdfKernelParts("brdf_eval.comp", *scene.brdf, state_->gpu.brdfDataLayout);
  if (unguarded) parts.defines.emplace_back("IBLX_UNGUARDED_BRDF", "1");
  const auto spirv = compileKernel(services.compiler, parts, "brdf eval " + scene.brdf->name);
  const auto set3 = state_->gpu.brdfSet();
  KernelLayout layout{{0, 2, 0, uint32_t(set3.size())},
                      sizeof(uint32_t),
                      {0, 0, 0, bindingBits(kBrdfDataBinding, uint32_t(set3.size()) - 1)}};
  state_->kernel = std::make_unique<ComputeKernel>(services.context, spirv, layout, "brdf eval");
  state_->kernel->bindBuffers(3, set3);
}

BrdfEvaluator::~BrdfEvaluator() = default;

std::vector<glm::dvec3> BrdfEvaluator::evaluate(std::span<const glm::dvec3> wi,
                                                std::span<const glm::dvec3> wo) const {
  if (wi.size() != wo.size()) throw Error("evaluateBrdf: as many wi as wo are needed");
  const VulkanContext& context = state_->context;
  ComputeKernel& kernel = *state_->kernel;
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

std::vector<glm::dvec3> evaluateBrdf(const VulkanContext& context, ShaderCompiler& compiler,
                                     const Scene& scene, std::span<const glm::dvec3> wi,
                                     std::span<const glm::dvec3> wo) {
  return BrdfEvaluator(VulkanServices(context, compiler), scene).evaluate(wi, wo);
}

double estimateLobeWidth(const VulkanServices& services, const Scene& scene) {
  const BrdfEvaluator evaluator(services, scene);
  constexpr double kStep = 0.05 * kPi / 180.0;
  constexpr int kHalfSteps = 1800;  // +-90 degrees around the mirror direction
  double width = 0.0;
  for (const double viewDeg : {0.0, 60.0}) {
    const double t = viewDeg * kPi / 180.0;
    const glm::dvec3 wo(std::sin(t), 0.0, std::cos(t)), mirror(-wo.x, 0.0, wo.z);
    // Two great circles through the mirror direction: in the plane of incidence and across it.
    const glm::dvec3 axes[2] = {glm::normalize(glm::cross(mirror, glm::dvec3(0.0, 1.0, 0.0))),
                                glm::dvec3(0.0, 1.0, 0.0)};
    for (const glm::dvec3& axis : axes) {
      std::vector<glm::dvec3> wi, wos;
      for (int k = -kHalfSteps; k <= kHalfSteps; ++k) {
        const double a = k * kStep;
        wi.push_back(std::cos(a) * mirror + std::sin(a) * axis);
        wos.push_back(wo);
      }
      const std::vector<glm::dvec3> f = evaluator.evaluate(wi, wos);
      std::vector<double> g(f.size());
      double mean = 0.0, peak = 0.0;
      std::size_t at = 0;
      for (std::size_t i = 0; i < f.size(); ++i) {
        g[i] = (f[i].x + f[i].y + f[i].z) / 3.0 * std::max(wi[i].z, 0.0);
        mean += g[i] / double(f.size());
        if (g[i] > peak) peak = g[i], at = i;
      }
      if (!(peak > 4.0 * mean)) continue;  // no lobe along this circle
      std::size_t lo = at, hi = at;
      while (lo > 0 && g[lo - 1] >= 0.5 * peak) --lo;
      while (hi + 1 < g.size() && g[hi + 1] >= 0.5 * peak) ++hi;
      const double fwhm = double(hi - lo + 1) * kStep;
      width = width > 0.0 ? std::min(width, fwhm) : fwhm;
    }
  }
  return width;
}

namespace {
// View azimuths whose envelope brdf-tab takes for an anisotropic BRDF (buildHalfVectorTable).
constexpr int kAnisotropicAzimuths = 16;

bool isAnisotropic(const BrdfEvaluator& evaluator) {
  // The same random pairs, each rotated about the normal by a random angle: an isotropic BRDF gives the same
  // values up to float rounding.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const auto direction = [&] {
    const double z = 0.05 + 0.95 * u(rng), phi = 2.0 * kPi * u(rng), r = std::sqrt(1.0 - z * z);
    return glm::dvec3(r * std::cos(phi), r * std::sin(phi), z);
  };
  std::vector<glm::dvec3> wi, wo, wiRotated, woRotated;
  for (int i = 0; i < 256; ++i) {
    wi.push_back(direction());
    wo.push_back(direction());
    const double a = 2.0 * kPi * u(rng), c = std::cos(a), s = std::sin(a);
    const auto rotate = [&](glm::dvec3 v) { return glm::dvec3(c * v.x - s * v.y, s * v.x + c * v.y, v.z); };
    wiRotated.push_back(rotate(wi.back()));
    woRotated.push_back(rotate(wo.back()));
  }
  const auto f = evaluator.evaluate(wi, wo), g = evaluator.evaluate(wiRotated, woRotated);
  double scale = 0.0;
  for (const auto& v : f) scale = std::max({scale, v.x, v.y, v.z});
  for (std::size_t i = 0; i < f.size(); ++i)
    for (int c = 0; c < 3; ++c)
      if (std::abs(f[i][c] - g[i][c]) > 1e-3 * std::max(std::abs(f[i][c]), 1e-3 * scale)) return true;
  return false;
}
}  // namespace

std::shared_ptr<const MerlTableData> tabulateBrdfTable(const VulkanServices& services, const Scene& scene) {
  // One table per BRDF source and parameter values, for the life of the process.
  static std::mutex mutex;
  static std::map<std::string, std::shared_ptr<const MerlTableData>> cache;
  const std::vector<float> params = packParams(*scene.brdf, scene.params);
  std::string key = scene.brdf->evalPart + "|" + scene.brdf->evalSource + "|";
  key.append(reinterpret_cast<const char*>(params.data()), params.size() * sizeof(float));
  if (scene.brdf->data) {  // a material read from a file (MERL): its data is part of the BRDF
    ContentHash hash;
    for (const TechniqueTable& table : scene.brdf->data(scene).tables)
      hash.add(std::string_view(reinterpret_cast<const char*>(table.bytes.data()), table.bytes.size()));
    key += '|';
    key += std::to_string(hash.value());
  }
  std::lock_guard lock(mutex);
  if (auto it = cache.find(key); it != cache.end()) return it->second;
  const BrdfEvaluator evaluator(services, scene);
  std::vector<glm::dvec3> wi, wo;
  HalfVectorTableOptions options;
  if (isAnisotropic(evaluator)) options = {true, kAnisotropicAzimuths};
  auto table = std::make_shared<const MerlTableData>(buildHalfVectorTable(
      [&](std::span<const HalfVectorTablePoint> points, std::span<double> weights) {
        wi.resize(points.size());
        wo.resize(points.size());
        for (std::size_t i = 0; i < points.size(); ++i) wi[i] = points[i].wi, wo[i] = points[i].wo;
        const std::vector<glm::dvec3> f = evaluator.evaluate(wi, wo);
        for (std::size_t i = 0; i < points.size(); ++i) weights[i] = (f[i].x + f[i].y + f[i].z) / 3.0;
      },
      options));
  cache.emplace(std::move(key), table);
  return table;
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

std::vector<double> tabulateUtia(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene) {
  std::vector<glm::dvec3> wi(kUtiaEntries), wo(kUtiaEntries);
  for (int ti = 0; ti < kUtiaThetaSteps; ++ti)
    for (int pi = 0; pi < kUtiaPhiSteps; ++pi)
      for (int tv = 0; tv < kUtiaThetaSteps; ++tv)
        for (int pv = 0; pv < kUtiaPhiSteps; ++pv) {
          const std::size_t index = utiaIndex(ti, pi, tv, pv);
          wi[index] = utiaDirection(ti, pi);  // theta at most 75 deg: always above the horizon
          wo[index] = utiaDirection(tv, pv);
        }
  const std::vector<glm::dvec3> f = evaluateBrdf(context, compiler, scene, wi, wo);
  std::vector<double> values(3 * kUtiaEntries);
  for (std::size_t index = 0; index < kUtiaEntries; ++index)
    for (int c = 0; c < 3; ++c) values[std::size_t(c) * kUtiaEntries + index] = f[index][c];
  return values;
}

std::vector<float> tabulateMit(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                               const MitDims& dims) {
  const std::size_t bins = dims.bins();
  std::vector<glm::dvec3> wi(bins), wo(bins);
  for (int ti = 0; ti < dims.thetaIn; ++ti)
    for (int to = 0; to < dims.thetaOut; ++to)
      for (int pd = 0; pd < dims.phiDiff; ++pd)
        for (int pi = 0; pi < dims.phiIn; ++pi) {
          const std::size_t index = dims.index(ti, to, pd, pi);
          const MitDirectionPair pair = mitBinCenter(dims, ti, to, pd, pi);  // bin centres: above the horizon
          wi[index] = pair.wi, wo[index] = pair.wo;
        }
  const std::vector<glm::dvec3> f = evaluateBrdf(context, compiler, scene, wi, wo);
  std::vector<float> values(3 * bins);
  for (std::size_t index = 0; index < bins; ++index)
    for (int c = 0; c < 3; ++c) values[std::size_t(c) * bins + index] = float(f[index][c]);
  return values;
}

RglTables tabulateRgl(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                      RglSynthLayout layout) {
  if (!(layout.alpha > 0.0)) {
    // The lobe's full width at half maximum is about 2 atan(alpha) for GGX (estimateLobeWidth).
    const double width = estimateLobeWidth(VulkanServices(context, compiler), scene);
    layout.alpha = width > 0.0 ? std::clamp(std::tan(0.5 * width), 0.02, 1.0) : 0.6;
  }
  RglSynthPlan plan = planRglSynth(layout);
  const std::vector<glm::dvec3> f = evaluateBrdf(context, compiler, scene, plan.wi, plan.wo);
  return finishRglSynth(std::move(plan), f);
}

AltaData tabulateAltaData(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                          AltaParam param, AltaOutput output, std::size_t scattered) {
  AltaSynthPlan plan = planAltaSynth(param, output, scattered);
  const std::vector<glm::dvec3> f = evaluateBrdf(context, compiler, scene, plan.wi, plan.wo);
  return finishAltaSynth(std::move(plan), f);
}

std::shared_ptr<const MerlTableData> VulkanServices::tabulateBrdf(const Scene& scene) const {
  return tabulateBrdfTable(*this, scene);
}

double VulkanServices::measureLobeWidth(const Scene& scene) const {
  return estimateLobeWidth(*this, scene);
}

}  // namespace iblx
