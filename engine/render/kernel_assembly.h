// Compiles an assembled kernel (engine/scene/kernel_prelude.h) and lays out its descriptor sets.
#pragma once

#include "engine/scene/kernel_prelude.h"
#include "engine/vk/compute_kernel.h"

#include <cstdint>
#include <string>
#include <vector>

namespace iblx {

class ShaderCompiler;

// Registers parts.sources with the compiler and compiles the assembled prelude. A part that reads a table
// the kernel does not bind (or binds at another width) is reported as such (explainMissingTable), not as
// glslang's undeclared identifier.
std::vector<uint32_t> compileKernel(ShaderCompiler& compiler, const KernelParts& parts,
                                    const std::string& name);

// Buffer counts of sets 0..3 for the scene's kernels, and which bindings are tables (compute_kernel.h).
KernelLayout sceneKernelLayout(uint32_t envBuffers, uint32_t brdfBuffers);

}  // namespace iblx
