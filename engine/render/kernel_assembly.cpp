// Kernel compilation and the scene kernels' descriptor layout (kernel_assembly.h).
#include "engine/render/kernel_assembly.h"

#include "engine/core/error.h"
#include "engine/render/scene_gpu.h"
#include "engine/vk/shader_compiler.h"

namespace iblx {

std::vector<uint32_t> compileKernel(ShaderCompiler& compiler, const KernelParts& parts,
                                    const std::string& name) {
  for (const auto& [path, text] : parts.sources) compiler.addSource(path, text);
  const std::string prelude = assemblePrelude(parts);
  try {
    return compiler.compile(prelude, name);
  } catch (const Error& e) {
    const std::string explained = explainMissingTable(parts, e.what());
    if (explained.empty()) throw;
    throw Error(explained);
  }
}

KernelLayout sceneKernelLayout(uint32_t envBuffers, uint32_t brdfBuffers) {
  // Set 0 (SceneGpu::frameSet): radiance (2, 5-7) and row table (3) are tables; the G-buffer, accumulation
  // and counters stay storage buffers. Set 2: every technique buffer. Set 3: all but the parameter block.
  return {{8, 0, envBuffers, 1 + brdfBuffers},
          sizeof(gpu::FrameParams),
          {bindingBits(2, 2) | bindingBits(5, 3), 0, bindingBits(0, envBuffers),
           bindingBits(kBrdfDataBinding, brdfBuffers)}};
}

}  // namespace iblx
