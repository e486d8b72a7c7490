// The ground truth of a scene (docs/DESIGN.md §4): a deterministic convolution over every environment texel on the
// GPU, integrating the same nearest-texel reconstruction the estimators see, with finer quadrature inside
// texels that the BRDF's narrow lobe or the horizon cuts through.
#pragma once

#include "engine/scene/scene.h"
#include "engine/vk/context.h"
#include "engine/vk/shader_compiler.h"

#include <cstdint>
#include <filesystem>
#include <functional>

namespace iblx {

struct ReferenceOptions {
  int coarseSubdivisions =
      1;  // per texel axis, each with 2x2 Gauss-Legendre points (unless the midpoint suffices)
  int maxFineSubdivisions = 512;
  bool allowMidpoint = true;  // false: the Gauss rule everywhere (for checking the midpoint rule)
  // Upper bound on a dispatch's work (loop iterations x object pixels). Smaller keeps a shared queue responsive
  // (the viewer's frames wait behind each dispatch on a CPU device) at a little more overhead. It only changes
  // the order of float additions, so it is not part of the cache key.
  double maxWorkPerDispatch = 4e8;
  // Visit every texel of every row instead of only the interval of each row that can be above a pixel's
  // horizon. The result is the same bit for bit (the exact per-texel test decides either way); the option
  // exists to check that, and is not part of the cache key.
  bool visitEveryTexel = false;
  // Called after each dispatch (a run of texels); an exception thrown from it abandons the computation.
  std::function<void(double fraction)> progress;
};

// A ground truth's own expected error over the object pixels, in the units of ErrorMetrics (engine/render/
// metrics.h): 0 for the convolution, estimated for a Monte Carlo reference (engine/render/mc_reference.h).
// An error measured against a noisy reference exceeds the true one by this much on average.
struct ReferenceNoise {
  double mse = 0.0;
  double relMse = 0.0;
};

struct ReferenceImage {
  int width = 0, height = 0;
  std::vector<float> rgb;  // width*height*3; background pixels hold the environment seen
  double seconds = 0.0;
  int fineSubdivisions = 0;
  ReferenceNoise noise;
};

ReferenceImage computeReference(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                                const ReferenceOptions& options = {});

// The cache key of a scene's reference: a hash of everything the image depends on (the environment's texels
// and rotation, the BRDF's code, parameters and measured data, the G-buffer, which covers object, camera and
// size, the quadrature options) and of the reference algorithm's version.
std::uint64_t referenceKey(const Scene& scene, const ReferenceOptions& options = {});

// computeReference through an on-disk cache: `cacheDir`/references/<key>.exr (a sealed EXR,
// engine/io/reference_cache.h) is read when present and valid (seconds = 0, fromCache set); an entry that is
// torn, damaged, of another size or holds NaN/Inf is reported in a one-line warning naming it and replaced.
// Otherwise the reference is computed and stored there atomically (a cache that cannot be written only
// warns). An empty cacheDir computes without caching.
ReferenceImage cachedReference(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                               const std::filesystem::path& cacheDir, const ReferenceOptions& options = {},
                               bool* fromCache = nullptr);

}  // namespace iblx
