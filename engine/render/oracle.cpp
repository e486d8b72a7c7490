// The oracle's variance: two sweeps of shaders/reference.comp over every texel (oracle.h).
#include "engine/render/oracle.h"

#include "engine/render/reference_sweep.h"
#include "engine/render/metrics.h"

#include <chrono>

namespace iblx {

OracleVariance computeOracleVariance(const VulkanContext& context, ShaderCompiler& compiler,
                                     const Scene& scene, ReferenceOptions options) {
  const auto start = std::chrono::steady_clock::now();
  options.allowMidpoint = false;
  SceneGpu gpu = uploadScene(context, scene);
  const auto fraction = [&](double from, double to) {
    return std::function<void(double)>([&options, from, to](double f) {
      if (options.progress) options.progress(from + (to - from) * f);
    });
  };
  for (int pass = 1; pass <= 2; ++pass) {
    KernelParts parts = referenceParts(scene, gpu.brdfDataLayout, gpu.chunking());
    parts.defines.emplace_back("REFERENCE_ORACLE_PASS", std::to_string(pass));
    // The second pass runs the sub-cell loop twice per texel: once for the integral, once for the variance.
    const ReferenceSweep sweep = planReferenceSweep(context, compiler, scene, options, pass == 1 ? 1.0 : 2.0);
    runReferenceSweep(context, compiler, scene, gpu, std::move(parts), "oracle pass " + std::to_string(pass),
                      sweep, pass == 1 ? fraction(0.0, 1.0 / 3.0) : fraction(1.0 / 3.0, 1.0));
  }
  OracleVariance oracle;
  oracle.width = scene.gbuffer.width;
  oracle.height = scene.gbuffer.height;
  const auto accum = gpu.accum.readAll<gpu::AccumPixel>();
  oracle.variance.resize(accum.size() * 3);
  oracle.mean.resize(accum.size() * 3);
  double mse = 0.0, relMse = 0.0;
  std::size_t objectPixels = 0;
  for (std::size_t i = 0; i < accum.size(); ++i) {
    const float mean[3] = {accum[i].mean.x, accum[i].mean.y, accum[i].mean.z};
    const float variance[3] = {accum[i].meanSquare.x, accum[i].meanSquare.y, accum[i].meanSquare.z};
    const bool object = scene.gbuffer.pixels[i].normal.w != 0.0f;
    for (int c = 0; c < 3; ++c) {
      oracle.mean[3 * i + std::size_t(c)] = mean[c];
      oracle.variance[3 * i + std::size_t(c)] = object ? variance[c] : 0.0f;
      if (!object) continue;
      // One sample's expected (x - r)^2 is its variance, weighed as relMSE weighs it.
      mse += double(variance[c]) / 3.0;
      relMse += double(variance[c]) * relativeErrorWeight(double(mean[c])) / 3.0;
    }
    objectPixels += object ? 1 : 0;
  }
  if (objectPixels > 0) {
    oracle.mseTimesSpp = mse / double(objectPixels);
    oracle.relMseTimesSpp = relMse / double(objectPixels);
  }
  oracle.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return oracle;
}

}  // namespace iblx
