// The sweep over every environment texel that the ground truth (engine/render/reference.h) and the oracle's
// variance (engine/render/oracle.h) share: the quadrature per texel and the runs of texels per dispatch that
// keep each invocation under lavapipe's loop cap (shaders/reference.comp).
#pragma once

#include "engine/render/kernel_assembly.h"
#include "engine/render/reference.h"
#include "engine/render/scene_gpu.h"

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace iblx {

struct ReferenceSweep {
  gpu::FrameParams params{};  // the quadrature; sampleOffset/samplesPerPass per run
  std::vector<std::pair<std::uint32_t, std::uint32_t>> runs;  // [first, end) texels, row-major
  int fineSubdivisions = 0;
};

// subcellLoopsPerTexel: how many loops over a texel's k x k sub-cells the kernel runs (1 for the ground
// truth, 2 for the oracle's second pass).
ReferenceSweep planReferenceSweep(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                                  const ReferenceOptions& options, double subcellLoopsPerTexel);

// Compiles `parts` (referenceParts and the kernel's own defines) and dispatches every run on `gpu`'s frame
// buffers, accumulating in gpu.accum; `progress` after each run (it may throw to abandon the sweep).
void runReferenceSweep(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                       SceneGpu& gpu, KernelParts parts, const std::string& name, ReferenceSweep sweep,
                       const std::function<void(double)>& progress);

}  // namespace iblx
