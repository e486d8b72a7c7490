// Reference convolution driver: quadrature choice, row chunking, progress.
#include "engine/render/reference.h"
#include "engine/render/reference_sweep.h"

#include "engine/core/cache_dir.h"
#include "engine/core/error.h"
#include "engine/core/hash.h"
#include "engine/core/log.h"
#include "engine/io/env_image.h"
#include "engine/io/reference_cache.h"

#include "engine/render/brdf_tabulation.h"
#include "engine/render/kernel_assembly.h"
#include "engine/render/scene_gpu.h"
#include "engine/io/latlong_texel.h"
#include "engine/core/sphere_mapping.h"
#include "engine/vk/compute_kernel.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>

namespace iblx {

ReferenceSweep planReferenceSweep(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                                  const ReferenceOptions& options, double subcellLoopsPerTexel) {
  ReferenceSweep sweep;
  const int W = scene.env.width, H = scene.env.height;
  const double texelAngle = std::max(kPi / H, 2.0 * kPi / W);  // largest texel side (at the equator)
  const double lobe =
      scene.brdf->lobeWidth ? scene.brdf->lobeWidth(scene, VulkanServices(context, compiler)) : 0.0;
  // Texels much smaller than every feature of f cos (the lobe, the cosine) take the midpoint rule (error
  // ~ texel^2 / 24 relative); larger ones the 2x2 Gauss rule on coarseSubdivisions^2 sub-cells.
  const double smoothScale = lobe > 0.0 ? std::min(0.05, lobe / 8.0) : 0.05;
  const int coarse =
      options.allowMidpoint && texelAngle < smoothScale ? 0 : std::max(1, options.coarseSubdivisions);
  int fine = std::max(1, coarse);
  double fineZoneCos = 2.0;                       // > 1: no fine zone
  if (lobe > 0.0 && texelAngle >= smoothScale) {  // a lobe that is narrow against the texels
    // Sub-cells about a quarter of the lobe width, within a cone of a few lobe widths plus one texel
    // diagonal.
    fine = std::clamp(int(std::ceil(4.0 * texelAngle / lobe)), 1, std::max(1, options.maxFineSubdivisions));
    fineZoneCos = std::cos(std::min(kPi, 4.0 * lobe + 1.5 * texelAngle));
  }
  sweep.fineSubdivisions = fine;
  // Texels the horizon may cross (centre within half a texel diagonal of it): the max(0, cos) kink costs the
  // Gauss rule its order, so these get 2x2 sub-cells (4x4 when the texels are large).
  const int horizonFine = std::min(coarse == 0 ? 2 : 4 * coarse, std::max(1, options.maxFineSubdivisions));
  const double horizonBand = std::sin(std::min(kPi / 2, 0.75 * texelAngle));

  const double rotation = scene.envRotationDeg * kPi / 180.0;
  gpu::FrameParams& params = sweep.params;
  params = {};
  params.width = uint32_t(scene.gbuffer.width);
  params.height = uint32_t(scene.gbuffer.height);
  params.envWidth = uint32_t(W);
  params.envHeight = uint32_t(H);
  params.envRotation = {float(std::cos(rotation)), float(std::sin(rotation)), 0, 0};
  // The brightest texels: at most kBrightTexels (each sub-cell is a loop iteration under lavapipe's cap),
  // each with at least 32 times the mean texel energy.
  constexpr std::size_t kBrightTexels = 16;
  std::vector<double> energies;
  double totalEnergy = 0.0;
  const std::vector<float> solidAngles = rowSolidAngles(W, H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const std::size_t i = 3 * scene.env.index(x, y);
      const double e = (double(scene.env.rgb[i]) + scene.env.rgb[i + 1] + scene.env.rgb[i + 2]) / 3.0 *
                       solidAngles[std::size_t(y)];
      energies.push_back(e);
      totalEnergy += e;
    }
  double brightEnergy = 32.0 * totalEnergy / double(energies.size());
  if (energies.size() > kBrightTexels) {  // strictly above the (kBrightTexels + 1)-th brightest
    std::vector<double> sorted = energies;
    std::nth_element(sorted.begin(), sorted.begin() + kBrightTexels, sorted.end(), std::greater<>());
    brightEnergy = std::max(brightEnergy, std::nextafter(sorted[kBrightTexels], HUGE_VAL) * (1.0 + 1e-6));
  }
  if (!(brightEnergy > 0.0)) brightEnergy = std::numeric_limits<double>::max();
  const int brightFine = std::min(16, std::max(1, options.maxFineSubdivisions));
  params.strategy = {float(std::min(brightEnergy, double(std::numeric_limits<float>::max()))),
                     float(brightFine), float(horizonBand), float(horizonFine)};
  params.quadrature = {float(coarse), float(fine), float(fineZoneCos), 0.0f};

  // Dispatches over runs of texels (row-major). lavapipe caps the loop iterations one invocation may run
  // (about 65535 back-edges in all; beyond it loops end early and the sum silently misses texels), so each
  // run's worst-case iteration count stays under kIterationBudget: a texel costs one texel-loop iteration
  // plus its sub-cell loops, k^2 each for the largest k any pixel may give it (any texel may lie in some
  // pixel's fine zone or horizon band; only the bright ones get brightFine), and each row 3 for its own
  // loops. Runs also bound the work per dispatch (watchdogs, progress).
  constexpr double kIterationBudget = 50000;
  const double workPerIteration = double(scene.gbuffer.objectPixelCount());
  const double kCommon = std::max({double(coarse), double(fine), double(horizonFine)});
  uint32_t begin = 0;
  double iterations = 0;
  const std::size_t texels = std::size_t(W) * std::size_t(H);
  for (std::size_t i = 0; i < texels; ++i) {
    const double k = energies[i] >= brightEnergy ? std::max(kCommon, double(brightFine)) : kCommon;
    // A row started in the run adds its own loop iterations (the row loop and its two column ranges).
    const double cost = 1.0 + subcellLoopsPerTexel * k * k + (i % std::size_t(W) == 0 ? 3.0 : 0.0);
    if (i > begin && (iterations + cost > kIterationBudget ||
                      (iterations + cost) * workPerIteration > options.maxWorkPerDispatch)) {
      sweep.runs.emplace_back(begin, uint32_t(i));
      begin = uint32_t(i);
      iterations = 0;
    }
    iterations += cost;
  }
  sweep.runs.emplace_back(begin, uint32_t(texels));
  return sweep;
}

void runReferenceSweep(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                       SceneGpu& gpu, KernelParts parts, const std::string& name, ReferenceSweep sweep,
                       const std::function<void(double)>& progress) {
  const auto spirv = compileKernel(compiler, parts, name + " " + scene.brdf->name);
  const auto brdfSet = gpu.brdfSet();
  ComputeKernel kernel(context, spirv, sceneKernelLayout(0, uint32_t(brdfSet.size() - 1)), name);
  kernel.bindBuffers(0, gpu.frameSet());
  kernel.bindBuffers(2, std::span<const Buffer* const>());
  kernel.bindBuffers(3, brdfSet);
  gpu::FrameParams& params = sweep.params;
  for (std::size_t r = 0; r < sweep.runs.size(); ++r) {
    params.sampleOffset = sweep.runs[r].first;
    params.samplesPerPass = sweep.runs[r].second;
    context.submitAndWait([&](vk::CommandBuffer cmd) {
      kernel.record(cmd, (params.width + 7) / 8, (params.height + 7) / 8, &params, sizeof params);
      recordShaderWriteBarrier(cmd, true);  // -> the next run and the host
    });
    // After every run: the viewer cancels a ground truth by throwing from here, so this is also how soon it
    // stops.
    if (progress) progress(double(sweep.runs[r].second) / double(sweep.runs.back().second));
  }
}

ReferenceImage computeReference(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                                const ReferenceOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  SceneGpu gpu = uploadScene(context, scene);
  KernelParts parts = referenceParts(scene, gpu.brdfDataLayout, gpu.chunking());
  if (options.visitEveryTexel) parts.defines.emplace_back("REFERENCE_VISIT_EVERY_TEXEL", "1");
  const ReferenceSweep sweep = planReferenceSweep(context, compiler, scene, options, 1.0);
  runReferenceSweep(context, compiler, scene, gpu, std::move(parts), "reference", sweep, options.progress);

  ReferenceImage image{scene.gbuffer.width, scene.gbuffer.height, {}, 0.0, sweep.fineSubdivisions};
  const auto accum = gpu.accum.readAll<gpu::AccumPixel>();
  image.rgb.resize(accum.size() * 3);
  for (size_t i = 0; i < accum.size(); ++i) {
    image.rgb[3 * i] = accum[i].mean.x;
    image.rgb[3 * i + 1] = accum[i].mean.y;
    image.rgb[3 * i + 2] = accum[i].mean.z;
  }
  image.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return image;
}

std::uint64_t referenceKey(const Scene& scene, const ReferenceOptions& options) {
  // Bump when the reference's algorithm changes, so stale cached images are not reused.
  constexpr std::string_view kAlgorithmVersion = "iblx-reference-1";
  // Bump when the cache file's layout changes (2: the EXR is sealed with a checksum,
  // engine/io/reference_cache.h), so entries of the old layout are not found rather than reported as damaged.
  constexpr std::string_view kCacheLayout = "cache-layout-2";
  ContentHash hash;
  hash.add(kAlgorithmVersion).add(kCacheLayout);
  const int sizes[] = {scene.env.width,           scene.env.height,           scene.gbuffer.width,
                       scene.gbuffer.height,      options.coarseSubdivisions, options.maxFineSubdivisions,
                       int(options.allowMidpoint)};
  hash.add(std::span<const int>(sizes));
  hash.add(std::span<const float>(scene.env.rgb));
  hash.addBytes(&scene.envRotationDeg, sizeof scene.envRotationDeg);
  hash.add(scene.brdf->name).add(scene.brdf->evalPart).add(scene.brdf->evalSource);
  for (const auto& [name, value] : scene.params) hash.add(name).add(std::span<const double>(value));
  if (scene.measured) hash.add(std::span<const float>(scene.measured->brdf.rgb));
  hash.add(std::span<const gpu::GPixel>(scene.gbuffer.pixels));
  return hash.value();
}

ReferenceImage cachedReference(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                               const std::filesystem::path& cacheDir, const ReferenceOptions& options,
                               bool* fromCache) {
  if (fromCache) *fromCache = false;
  if (cacheDir.empty()) return computeReference(context, compiler, scene, options);
  const auto path = cacheDir / "references" / (hexKey(referenceKey(scene, options)) + ".exr");
  ReferenceImage reference{scene.gbuffer.width, scene.gbuffer.height, {}, 0.0, 0};
  bool cached = false;
  reference.rgb = readOrComputeCached(
      path, reference.width, reference.height,
      [&] {
        ReferenceImage computed = computeReference(context, compiler, scene, options);
        reference.seconds = computed.seconds;
        reference.fineSubdivisions = computed.fineSubdivisions;
        return std::move(computed.rgb);
      },
      &cached);
  if (fromCache) *fromCache = cached;
  return reference;
}

}  // namespace iblx
