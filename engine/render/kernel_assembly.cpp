// Prelude generation for the integrator and reference kernels.
#include "engine/render/kernel_assembly.h"

#include "engine/vk/shader_compiler.h"

#include <sstream>

namespace iblx {

std::string assemblePrelude(const KernelParts& parts) {
  std::ostringstream s;
  s << "#version 460\n#extension GL_GOOGLE_include_directive : require\n";
  for (const char* interface : {"sequence", "env_sampler", "brdf", "brdf_sampler", "strategy"})
    s << "#include \"interfaces/" << interface << ".glsl\"\n";
  for (const auto& [name, value] : parts.defines) s << "#define " << name << " " << value << "\n";
  s << parts.brdfParamBlock;
  s << "#include \"" << parts.kernel << "\"\n";
  for (const auto& part : parts.parts) s << "#include \"" << part << "\"\n";
  return s.str();
}

KernelParts brdfKernelParts(std::string kernel, const BrdfInfo& brdf) {
  KernelParts k{std::move(kernel), {brdf.evalPart}, paramBlockGlsl(brdf), {}, {}};
  if (!brdf.evalSource.empty()) k.sources.emplace_back(brdf.evalPart, brdf.evalSource);
  return k;
}

std::vector<uint32_t> compileKernel(ShaderCompiler& compiler, const KernelParts& parts,
                                    const std::string& name) {
  for (const auto& [path, text] : parts.sources) compiler.addSource(path, text);
  return compiler.compile(assemblePrelude(parts), name);
}

std::vector<std::pair<std::string, std::string>> brdfBindingDefines(std::size_t brdfDataBuffers) {
  return {{"BRDF_DATA_BINDING", "1"}, {"BRDF_SAMPLER_BINDING", std::to_string(1 + brdfDataBuffers)}};
}

KernelParts integratorParts(const Scene& scene, const SceneGpu& gpu, const ResolvedMethod& method,
                            const TechniqueData& envData, const TechniqueData& brdfTechniqueData,
                            IntegratorMode mode) {
  KernelParts k{"integrate.comp", {}, paramBlockGlsl(*scene.brdf), envData.defines};
  if (mode == IntegratorMode::RecordPixel) {
    k.defines.emplace_back("IBLX_RECORD_SAMPLES", "1");
    k.defines.emplace_back("SAMPLE_RECORD_BINDING", std::to_string(kSampleRecordBinding));
    k.defines.emplace_back("SAMPLE_RECORD_DRAWS", std::to_string(method.drawsPerSample()) + "u");
  }
  k.defines.insert(k.defines.end(), brdfTechniqueData.defines.begin(), brdfTechniqueData.defines.end());
  const auto bindings = brdfBindingDefines(gpu.brdfData.size());
  k.defines.insert(k.defines.end(), bindings.begin(), bindings.end());
  const auto chunking = gpu.envDefines();
  k.defines.insert(k.defines.end(), chunking.begin(), chunking.end());
  k.parts.push_back(method.sequence->part);
  if (method.envTechnique) k.parts.push_back(method.envTechnique->part);
  k.parts.push_back(scene.brdf->evalPart);
  if (method.brdfTechnique) k.parts.push_back(method.brdfTechnique->part);
  k.parts.push_back(strategyPart(method.method->strategy));
  if (method.misOneSample) k.defines.emplace_back("MIS_ONE_SAMPLE", "1");
  if (method.method->strategy == Strategy::Ris)
    k.defines.emplace_back("RIS_CANDIDATES", std::to_string(method.risCandidates) + "u");
  if (!scene.brdf->evalSource.empty()) k.sources.emplace_back(scene.brdf->evalPart, scene.brdf->evalSource);
  return k;
}

KernelParts referenceParts(const Scene& scene, const SceneGpu& gpu) {
  // No BRDF technique in the reference: only the BRDF's own data binding.
  KernelParts k = brdfKernelParts("reference.comp", *scene.brdf);
  k.defines = gpu.envDefines();
  k.defines.emplace_back("BRDF_DATA_BINDING", "1");
  return k;
}

KernelLayout sceneKernelLayout(uint32_t envBuffers, uint32_t brdfBuffers) {
  // Set 0 (SceneGpu::frameSet): radiance (2, 5-7) and row table (3) are tables; the G-buffer, accumulation
  // and counters stay storage buffers. Set 2: every technique buffer. Set 3: all but the parameter block.
  return {
      {8, 0, envBuffers, 1 + brdfBuffers},
      sizeof(gpu::FrameParams),
      {bindingBits(2, 2) | bindingBits(5, 3), 0, bindingBits(0, envBuffers), bindingBits(1, brdfBuffers)}};
}

}  // namespace iblx
