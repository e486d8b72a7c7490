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

#include <vector>

namespace iblx {

struct OracleVariance {
  int width = 0, height = 0;
  std::vector<float> variance;  // width*height*3: the variance of one sample per pixel and channel
  std::vector<float> mean;      // width*height*3: the integral the oracle estimates (the ground truth)
  // Over the object pixels, in the units of ErrorMetrics (engine/render/metrics.h) times the samples per
  // pixel: the expected MSE and relMSE of an image of N samples per pixel are these / N.
  double mseTimesSpp = 0.0;
  double relMseTimesSpp = 0.0;
  double seconds = 0.0;
};

// Both sweeps use the Gauss rule in every texel (options.allowMidpoint is ignored: one point per texel would
// hide the variation of f cos inside it, and with it the oracle's variance).
OracleVariance computeOracleVariance(const VulkanContext& context, ShaderCompiler& compiler,
                                     const Scene& scene, ReferenceOptions options = {});

}  // namespace iblx
