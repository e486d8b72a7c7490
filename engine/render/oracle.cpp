// The oracle's variance: two sweeps of shaders/reference.comp over every texel (oracle.h).
#include "engine/render/oracle.h"

#include "engine/render/reference_sweep.h"
#include "engine/render/metrics.h"

#include "engine/core/error.h"

#include <algorithm>
#include <chrono>

namespace iblx {

namespace {
// The image pixel that pixel (i, j) of the strided grid stands for: its block's centre, inside the image.
std::size_t stridePixel(const GBuffer& image, int pixelStride, int i, int j) {
  const int x = std::min(i * pixelStride + pixelStride / 2, image.width - 1);
  const int y = std::min(j * pixelStride + pixelStride / 2, image.height - 1);
  return std::size_t(y) * std::size_t(image.width) + std::size_t(x);
}
}  // namespace

GBuffer oracleStridePixels(const GBuffer& image, int pixelStride) {
  if (pixelStride < 1) throw Error("oracle: the pixel stride must be at least 1");
  if (pixelStride == 1) return image;
  GBuffer picked;
  picked.width = (image.width + pixelStride - 1) / pixelStride;
  picked.height = (image.height + pixelStride - 1) / pixelStride;
  for (int j = 0; j < picked.height; ++j)
    for (int i = 0; i < picked.width; ++i)
      picked.pixels.push_back(image.pixels[stridePixel(image, pixelStride, i, j)]);
  return picked;
}

namespace {
// Calls visit(at, source) for each object pixel of the oracle: `at` its index among the oracle's pixels,
// `source` the image pixel it stands for. Throws when the image or the oracle does not fit.
template <typename Visit>
void forEachOraclePixel(const OracleVariance& oracle, const GBuffer& image, std::span<const float> rgb,
                        Visit&& visit) {
  if (rgb.size() != image.pixels.size() * 3)
    throw Error("oracle: the image is not the oracle's image's size");
  const int stride = oracle.pixelStride;
  if (oracle.width != (image.width + stride - 1) / stride ||
      oracle.height != (image.height + stride - 1) / stride ||
      oracle.mean.size() != std::size_t(oracle.width) * std::size_t(oracle.height) * 3 ||
      oracle.variance.size() != oracle.mean.size())
    throw Error("oracle: computed for another image");
  for (int j = 0; j < oracle.height; ++j)
    for (int i = 0; i < oracle.width; ++i) {
      const std::size_t source = stridePixel(image, stride, i, j);
      if (image.pixels[source].normal.w != 0.0f)
        visit(std::size_t(j) * std::size_t(oracle.width) + std::size_t(i), source);
    }
}
}  // namespace

std::vector<OraclePixelError> oraclePixelErrors(const OracleVariance& oracle, const GBuffer& image,
                                                std::span<const float> rgb, std::uint64_t spp) {
  std::vector<OraclePixelError> pixels;
  forEachOraclePixel(oracle, image, rgb, [&](std::size_t at, std::size_t source) {
    OraclePixelError p;
    p.x = int(source % std::size_t(image.width));
    p.y = int(source / std::size_t(image.width));
    for (std::size_t c = 0; c < 3; ++c) {
      const double exact = oracle.mean[3 * at + c], error = double(rgb[3 * source + c]) - exact;
      p.mean += exact / 3.0;
      p.variance += double(oracle.variance[3 * at + c]) / 3.0;
      p.squaredErrorTimesSpp += error * error / 3.0 * double(spp);
    }
    pixels.push_back(p);
  });
  return pixels;
}

OraclePixelsError errorOnOraclePixels(const OracleVariance& oracle, const GBuffer& image,
                                      std::span<const float> rgb, std::uint64_t spp) {
  double mse = 0.0, relMse = 0.0;
  std::size_t objectPixels = 0;
  forEachOraclePixel(oracle, image, rgb, [&](std::size_t at, std::size_t source) {
    for (std::size_t c = 0; c < 3; ++c) {
      const double exact = oracle.mean[3 * at + c], error = double(rgb[3 * source + c]) - exact;
      mse += error * error / 3.0;
      relMse += error * error * relativeErrorWeight(exact) / 3.0;
    }
    ++objectPixels;
  });
  if (objectPixels == 0) return {};
  return {mse / double(objectPixels) * double(spp), relMse / double(objectPixels) * double(spp)};
}

OracleVariance computeOracleVariance(const VulkanContext& context, ShaderCompiler& compiler,
                                     const Scene& image, ReferenceOptions options, int pixelStride) {
  const auto start = std::chrono::steady_clock::now();
  options.allowMidpoint = false;
  Scene strided;
  if (pixelStride != 1) {
    strided = image;
    strided.gbuffer = oracleStridePixels(image.gbuffer, pixelStride);
    if (strided.gbuffer.objectPixelCount() == 0)
      throw Error("oracle: every " + std::to_string(pixelStride) +
                  "th pixel misses the object; use a smaller --oracle-stride");
  }
  const Scene& scene = pixelStride != 1 ? strided : image;
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
  oracle.pixelStride = pixelStride;
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
