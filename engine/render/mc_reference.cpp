// The Monte Carlo ground truth (engine/render/mc_reference.h).
#include "engine/render/mc_reference.h"

#include "engine/core/cache_dir.h"
#include "engine/core/error.h"
#include "engine/core/hash.h"
#include "engine/core/log.h"
#include "engine/io/reference_cache.h"
#include "engine/render/renderer.h"

#include <algorithm>
#include <chrono>

namespace iblx {
namespace {

// One half: the method rendered with `seed` until `seconds` of rendering have passed.
std::vector<float> renderHalf(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                              const ResolvedMethod& method, std::uint32_t seed, double seconds,
                              const std::function<void(double)>& progress) {
  Renderer renderer(context, compiler, scene, method, seed);
  double elapsed = 0.0;
  // 64-sample passes keep each dispatch short (a responsive Ctrl-C) and the sample index far from wrapping.
  while (elapsed < seconds && renderer.samplesPerPixel() + 64 < 0xffffffffull) {
    elapsed += renderer.runPass(64).wallSeconds;
    if (progress) progress(std::min(1.0, elapsed / seconds));
  }
  return renderer.meanRgb();
}

std::uint64_t halfKey(const Scene& scene, const ResolvedMethod& method, double seconds, std::uint32_t seed) {
  ContentHash hash;
  hash.add("iblx-mc-reference-1").add(std::to_string(referenceKey(scene))).add(method.label());
  hash.addBytes(&seconds, sizeof seconds).addBytes(&seed, sizeof seed);
  return hash.value();
}

ReferenceImage combine(const Scene& scene, const std::vector<float>& a, const std::vector<float>& b,
                       double seconds) {
  ReferenceImage image{
      scene.gbuffer.width, scene.gbuffer.height, std::vector<float>(a.size()), seconds, 0, {}};
  for (std::size_t i = 0; i < a.size(); ++i) image.rgb[i] = 0.5f * (a[i] + b[i]);
  image.noise = referenceNoise(scene.gbuffer, a, b);
  return image;
}

}  // namespace

ReferenceNoise referenceNoise(const GBuffer& gbuffer, std::span<const float> a, std::span<const float> b) {
  IBLX_ASSERT(a.size() == b.size() && a.size() == 3 * gbuffer.pixels.size());
  ReferenceNoise noise;
  std::size_t count = 0;
  for (std::size_t p = 0; p < gbuffer.pixels.size(); ++p) {
    if (gbuffer.pixels[p].normal.w == 0.0f) continue;
    for (std::size_t c = 0; c < 3; ++c) {
      const double x = a[3 * p + c], y = b[3 * p + c], mean = 0.5 * (x + y);
      const double variance = 0.25 * (x - y) * (x - y);
      noise.mse += variance;
      noise.relMse += variance / (mean * mean + 0.01);
      ++count;
    }
  }
  if (count > 0) noise.mse /= double(count), noise.relMse /= double(count);
  return noise;
}

ReferenceImage computeMcReference(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                                  const McReferenceOptions& options) {
  return cachedMcReference(context, compiler, scene, {}, options);
}

ReferenceImage cachedMcReference(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                                 const std::filesystem::path& cacheDir, const McReferenceOptions& options,
                                 bool* fromCache) {
  const auto start = std::chrono::steady_clock::now();
  const ResolvedMethod method = resolveMethod(options.method, *scene.brdf);
  const int width = scene.gbuffer.width, height = scene.gbuffer.height;
  bool allCached = !cacheDir.empty();
  std::vector<float> halves[2];
  const std::uint32_t seeds[2] = {options.seedA, options.seedB};
  for (int h = 0; h < 2; ++h) {
    const auto path =
        cacheDir.empty()
            ? std::filesystem::path()
            : cacheDir / "references" / (hexKey(halfKey(scene, method, options.seconds, seeds[h])) + ".exr");
    std::function<void(double)> progress;
    if (options.progress) progress = [&options, h](double f) { options.progress(0.5 * h + 0.5 * f); };
    const auto render = [&] {
      return renderHalf(context, compiler, scene, method, seeds[h], 0.5 * options.seconds, progress);
    };
    if (path.empty()) {
      halves[h] = render();
      continue;
    }
    bool cached = false;
    halves[h] = readOrComputeCached(path, width, height, render, &cached);
    allCached = allCached && cached;
  }
  if (fromCache) *fromCache = allCached;
  return combine(
      scene, halves[0], halves[1],
      allCached ? 0.0 : std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

}  // namespace iblx
