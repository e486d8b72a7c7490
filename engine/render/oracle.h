// The limit of importance sampling with a luminance pdf: the variance of the oracle, an estimator that picks,
// per pixel, texel t of the environment with probability w_t / W, w_t = Y(L_t * integral over t of f cos)
// (Rec. 709 luminance of the texel's exact contribution, as the ground truth's quadrature gives it), and a
// direction uniformly in solid angle inside the texel; its pdf is exact (w_t / W / solidAngle_t). Every pdf
// that is a function of luminance over the map's texels does no better, so a method's variance per sample
// stated against the oracle's says how much importance sampling could still gain on that scene. Computed,
// not sampled: one sweep like the ground truth's sums I and W, a second sums the variance of one sample
// (shaders/reference.comp), so the figure carries no sampling noise. It costs about three ground truths.
#pragma once

#include "engine/render/reference.h"

#include <cstdint>
#include <span>
#include <vector>

namespace iblx {

struct OracleVariance {
  int pixelStride = 1;          // the pixels computed: the centre of every stride x stride block of the image
  int width = 0, height = 0;    // of the pixels computed: the image's size over the stride, rounded up
  std::vector<float> variance;  // width*height*3: the variance of one sample per pixel and channel
  std::vector<float> mean;      // width*height*3: the integral the oracle estimates (the ground truth)
  // Over the object pixels, in the units of ErrorMetrics (engine/render/metrics.h) times the samples per
  // pixel: the expected MSE and relMSE of an image of N samples per pixel are these / N.
  double mseTimesSpp = 0.0;
  double relMseTimesSpp = 0.0;
  double seconds = 0.0;
};

// Both sweeps use the Gauss rule in every texel (options.allowMidpoint is ignored: one point per texel would
// hide the variation of f cos inside it, and with it the oracle's variance). With pixelStride s > 1 only the
// centre pixel of every s x s block is computed (s^2 times cheaper; a stratified sample of the image, so the
// MSE·spp and relMSE·spp over its object pixels estimate the image's). Throws iblx::Error for s < 1 or a
// stride that leaves no object pixel.
OracleVariance computeOracleVariance(const VulkanContext& context, ShaderCompiler& compiler,
                                     const Scene& scene, ReferenceOptions options = {}, int pixelStride = 1);
// The pixels computeOracleVariance computes with that stride, as a G-buffer of their own.
GBuffer oracleStridePixels(const GBuffer& image, int pixelStride);

// An image's MSE and relMSE times its spp on the oracle's pixels, against the oracle's integral there (the
// exact answer at those pixels): with a pixel stride, a method's variance per sample on the pixels the
// oracle's was computed on. A sun's highlight holds most of an image's MSE, so the oracle's MSE over a
// sample of pixels is only comparable with a method's over the same pixels. Throws iblx::Error when `rgb` is
// not the image's size.
struct OraclePixelsError {
  double mseTimesSpp = 0.0, relMseTimesSpp = 0.0;
};
OraclePixelsError errorOnOraclePixels(const OracleVariance& oracle, const GBuffer& image,
                                      std::span<const float> rgb, std::uint64_t spp);

// Per object pixel of the oracle: where the image's MSE·spp against the oracle's lies. Its place in the
// image, the oracle's integral and variance per sample there, and the image's squared error times spp, each a
// mean over the channels (the units of errorOnOraclePixels' MSE, which is their mean over the pixels). A few
// pixels can hold most of an image's MSE (a highlight the sampler misses); this says which. Throws
// iblx::Error as errorOnOraclePixels.
struct OraclePixelError {
  int x = 0, y = 0;
  double mean = 0.0, variance = 0.0, squaredErrorTimesSpp = 0.0;
};
std::vector<OraclePixelError> oraclePixelErrors(const OracleVariance& oracle, const GBuffer& image,
                                                std::span<const float> rgb, std::uint64_t spp);

}  // namespace iblx
