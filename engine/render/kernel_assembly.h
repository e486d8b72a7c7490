// Writes the prelude that assembles a kernel from one part per role (DESIGN §2, STYLE "For iblx" 3):
// #version, the interfaces, the BRDF parameter block, the kernel and one #include per chosen part.
#pragma once

#include "engine/render/scene.h"
#include "engine/vk/compute_kernel.h"

#include <string>
#include <vector>

namespace iblx {

struct KernelParts {
  std::string kernel;                                        // entry point, e.g. "integrate.comp"
  std::vector<std::string> parts;                            // one per role in use
  std::string brdfParamBlock;                                // paramBlockGlsl() of the scene's BRDF
  std::vector<std::pair<std::string, std::string>> defines;  // from the techniques' data
  // Generated parts (path, text) the compiler must know, e.g. a .brdf file's (BrdfInfo::evalSource).
  std::vector<std::pair<std::string, std::string>> sources;
};

std::string assemblePrelude(const KernelParts& parts);
// The parts of every kernel that evaluates `brdf`: its part and, for a generated BRDF, that part's source.
KernelParts brdfKernelParts(std::string kernel, const BrdfInfo& brdf);
// Registers parts.sources with the compiler and compiles the assembled prelude.
std::vector<uint32_t> compileKernel(ShaderCompiler& compiler, const KernelParts& parts,
                                    const std::string& name);

// What the integrator kernel does: add samples to every pixel, or integrate one pixel through the same code
// and store every sample's record (IBLX_RECORD_SAMPLES, shaders/lib/sample_record.glsl) in an extra set-0
// buffer at binding kSampleRecordBinding.
enum class IntegratorMode { Image, RecordPixel };
inline constexpr uint32_t kSampleRecordBinding = 8;

// The integrator for a scene and method, and the reference kernel for a scene, as uploaded in `gpu`. Set 3
// holds the parameter block (binding 0), the BRDF's buffers (gpu.brdfData, from BRDF_DATA_BINDING = 1) and the
// BRDF technique's (from BRDF_SAMPLER_BINDING); both bindings, and the environment's chunking
// (SceneGpu::envDefines), are defined for the parts.
KernelParts integratorParts(const Scene& scene, const SceneGpu& gpu, const ResolvedMethod& method,
                            const TechniqueData& envData, const TechniqueData& brdfTechniqueData,
                            IntegratorMode mode = IntegratorMode::Image);
KernelParts referenceParts(const Scene& scene, const SceneGpu& gpu);
// The two set-3 binding definitions alone (for kernels assembled elsewhere, e.g. the test probes).
std::vector<std::pair<std::string, std::string>> brdfBindingDefines(std::size_t brdfDataBuffers);

// Buffer counts of sets 0..3 for these kernels, and which bindings are tables (compute_kernel.h).
KernelLayout sceneKernelLayout(uint32_t envBuffers, uint32_t brdfBuffers);

}  // namespace iblx
