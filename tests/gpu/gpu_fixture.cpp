// GPU test fixture implementation: context, compiler with probe sources, probe runners.
#include "tests/gpu/gpu_fixture.h"

#include "engine/render/brdf_tabulation.h"
#include "engine/render/kernel_assembly.h"
#include "engine/io/latlong_texel.h"
#include "engine/scene/brdf_params.h"
#include "engine/vk/compute_kernel.h"

#include <doctest/doctest.h>

#include <fstream>
#include <sstream>

namespace iblx::test {
namespace {

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  REQUIRE_MESSAGE(in, "cannot read " << path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

uint32_t gSeenValidationErrors = 0;

// Shared machinery of the two probes: scene buffers (set 0, set 3), probe I/O (set 1), a technique's set 2.
struct ProbeRunner {
  Scene scene;
  SceneGpu gpu;
  std::vector<Buffer> envBuffers, brdfBuffers;
  std::unique_ptr<ComputeKernel> kernel;
  glm::dvec3 vector;  // the normal (env probe) or wo (BRDF probe)

  // envData goes to set 2 (an env technique), brdfData to set 3 after the BRDF's own buffers.
  ProbeRunner(Scene s, const std::string& kernelFile, std::vector<std::string> parts,
              const TechniqueData& envData, const TechniqueData& brdfData, glm::dvec3 v)
      : scene(std::move(s)),
        gpu(uploadScene(gpuContext(), scene)),
        envBuffers(uploadTables(gpuContext(), envData, "probe env technique")),
        brdfBuffers(uploadTables(gpuContext(), brdfData, "probe BRDF technique")),
        vector(v) {
    KernelParts k = brdfKernelParts(kernelFile, *scene.brdf, gpu.brdfDataLayout, std::move(parts));
    k.bindTables(kEnvTechniqueSet, 0, envData, "probe env technique");
    k.bindTables(kBrdfSet, kBrdfDataBinding + uint32_t(gpu.brdfData.size()), brdfData,
                 "probe BRDF technique");
    for (auto& d : gpu.chunking().defines()) k.defines.push_back(d);
    const auto spirv = compileKernel(gpuCompiler(), k, kernelFile);
    const auto set3 = gpu.brdfSet(brdfBuffers);
    KernelLayout layout = sceneKernelLayout(uint32_t(envBuffers.size()), uint32_t(set3.size() - 1));
    layout.buffersPerSet[1] = 2;
    kernel = std::make_unique<ComputeKernel>(gpuContext(), spirv, layout, kernelFile);
    kernel->bindBuffers(0, gpu.frameSet());
    std::vector<const Buffer*> set2;
    for (const auto& b : envBuffers) set2.push_back(&b);
    kernel->bindBuffers(2, set2);
    kernel->bindBuffers(3, set3);
  }

  // Runs the probe over `input` in chunks that respect maxComputeWorkGroupCount and maxStorageBufferRange.
  std::vector<gpu::vec4> run(const std::vector<gpu::vec4>& input, uint32_t mode) {
    const auto& limits = gpuContext().limits();
    const std::size_t maxItems =
        std::min<std::size_t>({std::size_t(limits.maxComputeWorkGroupCount[0]) * 64,
                               limits.maxStorageBufferRange / (2 * sizeof(gpu::vec4)), std::size_t(1) << 20});
    std::vector<gpu::vec4> output;
    output.reserve(2 * input.size());
    for (std::size_t begin = 0; begin < input.size(); begin += maxItems) {
      const std::size_t count = std::min(maxItems, input.size() - begin);
      const auto chunk = runChunk(std::span(input).subspan(begin, count), mode);
      output.insert(output.end(), chunk.begin(), chunk.begin() + std::ptrdiff_t(2 * count));
    }
    return output;
  }

  std::vector<gpu::vec4> runChunk(std::span<const gpu::vec4> input, uint32_t mode) {
    Buffer in = Buffer::fromData(gpuContext(), input, "probe input");
    Buffer out(gpuContext(), input.size() * 2 * sizeof(gpu::vec4), "probe output");
    kernel->bindBuffers(1, {&in, &out});
    gpu::FrameParams params{};
    params.width = params.height = 1;
    params.envWidth = uint32_t(scene.env.width);
    params.envHeight = uint32_t(scene.env.height);
    params.samplesPerPass = uint32_t(input.size());
    params.probeMode = mode;
    params.envRotation = {1, 0, 0, 0};
    params.quadrature = {float(vector.x), float(vector.y), float(vector.z), 0};
    gpuContext().submitAndWait([&](vk::CommandBuffer cmd) {
      kernel->record(cmd, uint32_t((input.size() + 63) / 64), 1, &params, sizeof params);
      recordShaderWriteBarrier(cmd, true);
    });
    return out.readAll<gpu::vec4>();
  }

  std::vector<ProbeSample> sample(std::span<const glm::dvec2> u) {
    std::vector<gpu::vec4> input(u.size());
    for (size_t i = 0; i < u.size(); ++i) input[i] = {toGpuU(u[i].x), toGpuU(u[i].y), 0, 0};
    const auto out = run(input, 0);
    std::vector<ProbeSample> samples(u.size());
    for (size_t i = 0; i < u.size(); ++i)
      samples[i] = {{out[2 * i].x, out[2 * i].y, out[2 * i].z}, out[2 * i].w, out[2 * i + 1].x};
    return samples;
  }

  std::vector<gpu::vec4> directionsMode(std::span<const glm::dvec3> d, uint32_t mode) {
    std::vector<gpu::vec4> input(d.size());
    for (size_t i = 0; i < d.size(); ++i) input[i] = {float(d[i].x), float(d[i].y), float(d[i].z), 0};
    return run(input, mode);
  }

  std::vector<double> pdf(std::span<const glm::dvec3> d) {
    const auto out = directionsMode(d, 1);
    std::vector<double> pdfs(d.size());
    for (size_t i = 0; i < d.size(); ++i) pdfs[i] = out[2 * i].x;
    return pdfs;
  }
};

Scene probeScene(EnvImage env, const std::string& brdf,
                 const std::vector<std::pair<std::string, std::string>>& params) {
  SceneSpec spec;
  spec.brdf = brdf;
  spec.params = params;
  spec.width = spec.height = 1;
  return makeScene(std::move(env), spec);
}

}  // namespace

const VulkanContext& gpuContext() {
  static VulkanContext context({"", Validation::Auto});
  return context;
}

ShaderCompiler& gpuCompiler() {
  static ShaderCompiler compiler = [] {
    ShaderCompiler c;
    for (const char* probe : {"env_technique_probe.comp", "brdf_technique_probe.comp",
                              "analytic_brdf_probe.comp", "env_ot_inverse_probe.comp"})
      c.addSource(std::string("probe/") + probe,
                  readFile(std::string(IBLX_TEST_SOURCE_DIR) + "/gpu/probe/" + probe));
    return c;
  }();
  return compiler;
}

void checkNoNewValidationErrors() {
  const uint32_t now = gpuContext().validationErrorCount();
  CHECK_MESSAGE(now == gSeenValidationErrors, "Vulkan validation errors were reported (see stderr)");
  gSeenValidationErrors = now;
}

struct EnvTechniqueProbe::Impl : ProbeRunner {
  using ProbeRunner::ProbeRunner;
};

EnvTechniqueProbe::EnvTechniqueProbe(const std::string& technique, const EnvImage& env, glm::dvec3 normal) {
  const auto& info = findEnvTechnique(technique);
  impl_ =
      std::make_unique<Impl>(probeScene(env, "lambert", {}), "probe/env_technique_probe.comp",
                             std::vector<std::string>{info.part}, info.build(env), TechniqueData{}, normal);
}
EnvTechniqueProbe::~EnvTechniqueProbe() = default;
std::vector<ProbeSample> EnvTechniqueProbe::sample(std::span<const glm::dvec2> u) {
  return impl_->sample(u);
}
std::vector<double> EnvTechniqueProbe::pdf(std::span<const glm::dvec3> d) {
  return impl_->pdf(d);
}

struct EnvPartProbe::Impl : ProbeRunner {
  using ProbeRunner::ProbeRunner;
};

EnvPartProbe::EnvPartProbe(const std::string& kernelFile, std::vector<std::string> parts,
                           const TechniqueData& data, const EnvImage& env) {
  impl_ = std::make_unique<Impl>(probeScene(env, "lambert", {}), kernelFile, std::move(parts), data,
                                 TechniqueData{}, glm::dvec3(0, 1, 0));
}
EnvPartProbe::~EnvPartProbe() = default;
std::vector<std::pair<glm::dvec4, glm::dvec4>> EnvPartProbe::directions(std::span<const glm::dvec3> d) {
  const auto out = impl_->directionsMode(d, 1);
  std::vector<std::pair<glm::dvec4, glm::dvec4>> values(d.size());
  const auto widen = [](const gpu::vec4& v) { return glm::dvec4(v.x, v.y, v.z, v.w); };
  for (size_t i = 0; i < d.size(); ++i) values[i] = {widen(out[2 * i]), widen(out[2 * i + 1])};
  return values;
}

struct BrdfTechniqueProbe::Impl : ProbeRunner {
  using ProbeRunner::ProbeRunner;
};

BrdfTechniqueProbe::BrdfTechniqueProbe(const std::string& technique, const std::string& brdf,
                                       const std::vector<std::pair<std::string, std::string>>& params,
                                       glm::dvec3 wo) {
  const auto& info = findBrdfTechnique(technique);
  Scene scene = probeScene(EnvImage{2, 1, std::vector<float>(6, 1.0f)}, brdf, params);
  const std::string evalPart = scene.brdf->evalPart;
  const TechniqueData data =
      info.build ? info.build(scene, VulkanServices(gpuContext(), gpuCompiler())) : TechniqueData{};
  impl_ = std::make_unique<Impl>(std::move(scene), "probe/brdf_technique_probe.comp",
                                 std::vector<std::string>{evalPart, info.part}, TechniqueData{}, data, wo);
}
BrdfTechniqueProbe::~BrdfTechniqueProbe() = default;
std::vector<ProbeSample> BrdfTechniqueProbe::sample(std::span<const glm::dvec2> u) {
  return impl_->sample(u);
}
std::vector<double> BrdfTechniqueProbe::pdf(std::span<const glm::dvec3> d) {
  return impl_->pdf(d);
}
std::vector<glm::dvec3> BrdfTechniqueProbe::evalCos(std::span<const glm::dvec3> d) {
  const auto out = impl_->directionsMode(d, 2);
  std::vector<glm::dvec3> values(d.size());
  for (size_t i = 0; i < d.size(); ++i) values[i] = {out[2 * i].x, out[2 * i].y, out[2 * i].z};
  return values;
}

}  // namespace iblx::test

namespace iblx::test {

struct AnalyticBrdfProbe::Impl : ProbeRunner {
  using ProbeRunner::ProbeRunner;
  bool hasSampler = false;
};

AnalyticBrdfProbe::AnalyticBrdfProbe(const std::string& file,
                                     const std::vector<std::pair<std::string, std::string>>& params,
                                     glm::dvec3 wo) {
  Scene scene = probeScene(EnvImage{2, 1, std::vector<float>(6, 1.0f)}, file, params);
  const bool sampler = scene.brdf->hasSampleHook;
  const std::string evalPart = scene.brdf->evalPart;
  TechniqueData defines;
  if (sampler) defines.defines.emplace_back("PROBE_HAS_ISFUNC", "1");
  impl_ = std::make_unique<Impl>(std::move(scene), "probe/analytic_brdf_probe.comp",
                                 std::vector<std::string>{evalPart}, defines, TechniqueData{}, wo);
  impl_->hasSampler = sampler;
}
AnalyticBrdfProbe::~AnalyticBrdfProbe() = default;
bool AnalyticBrdfProbe::hasSampler() const {
  return impl_->hasSampler;
}

std::vector<IsFuncSample> AnalyticBrdfProbe::sample(std::span<const glm::dvec2> u) {
  std::vector<gpu::vec4> input(u.size());
  for (size_t i = 0; i < u.size(); ++i) input[i] = {toGpuU(u[i].x), toGpuU(u[i].y), 0, 0};
  const auto out = impl_->run(input, 0);
  std::vector<IsFuncSample> samples(u.size());
  for (size_t i = 0; i < u.size(); ++i)
    samples[i] = {{out[2 * i].x, out[2 * i].y, out[2 * i].z},
                  out[2 * i].w,
                  {out[2 * i + 1].x, out[2 * i + 1].y, out[2 * i + 1].z}};
  return samples;
}

std::vector<glm::dvec3> AnalyticBrdfProbe::brdf(std::span<const glm::dvec3> wi) {
  const auto out = impl_->directionsMode(wi, 1);
  std::vector<glm::dvec3> f(wi.size());
  for (size_t i = 0; i < wi.size(); ++i) f[i] = {out[2 * i].x, out[2 * i].y, out[2 * i].z};
  return f;
}

std::vector<double> AnalyticBrdfProbe::pdf(std::span<const glm::dvec3> wi) {
  const auto out = impl_->directionsMode(wi, 2);
  std::vector<double> p(wi.size());
  for (size_t i = 0; i < wi.size(); ++i) p[i] = out[2 * i].x;
  return p;
}

}  // namespace iblx::test
