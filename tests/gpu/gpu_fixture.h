// Shared GPU test fixture: one Vulkan context (validation layers on when installed) and one shader compiler
// that also sees the probe kernels under tests/gpu/probe, plus the probe runners for env and BRDF techniques.
#pragma once

#include "engine/render/scene_gpu.h"
#include "engine/vk/context.h"
#include "engine/vk/shader_compiler.h"
#include "tests/support/chi2.h"

#include <glm/glm.hpp>

#include <span>
#include <vector>

namespace iblx::test {

const VulkanContext& gpuContext();
ShaderCompiler& gpuCompiler();
// Validation errors reported since the previous call (fails the calling test case when non-zero).
void checkNoNewValidationErrors();

struct ProbeSample {
  glm::dvec3 direction;
  double pdf = 0.0;        // from the technique's sample()
  double pdfLookup = 0.0;  // the technique's pdf() of that direction
};

// Runs an env technique from the registry on `env` through the probe kernel.
class EnvTechniqueProbe {
 public:
  EnvTechniqueProbe(const std::string& technique, const EnvImage& env, glm::dvec3 normal = {0, 1, 0});
  ~EnvTechniqueProbe();
  std::vector<ProbeSample> sample(std::span<const glm::dvec2> u);
  std::vector<double> pdf(std::span<const glm::dvec3> directions);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Runs a probe kernel of tests/gpu/probe over env parts with the given tables (set 2) on `env`: per input
// direction, the kernel's two vec4 outputs (for GLSL libraries that are not an env technique's interface).
class EnvPartProbe {
 public:
  EnvPartProbe(const std::string& kernelFile, std::vector<std::string> parts, const TechniqueData& data,
               const EnvImage& env);
  ~EnvPartProbe();
  std::vector<std::pair<glm::dvec4, glm::dvec4>> directions(std::span<const glm::dvec3> directions);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Runs a BRDF technique (and the BRDF) through the probe kernel, local frame, fixed wo.
class BrdfTechniqueProbe {
 public:
  BrdfTechniqueProbe(const std::string& technique, const std::string& brdf,
                     const std::vector<std::pair<std::string, std::string>>& params, glm::dvec3 wo);
  ~BrdfTechniqueProbe();
  std::vector<ProbeSample> sample(std::span<const glm::dvec2> u);
  std::vector<double> pdf(std::span<const glm::dvec3> directions);
  std::vector<glm::dvec3> evalCos(std::span<const glm::dvec3> directions);  // f(wi, wo) * max(cos, 0)

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// A .brdf file's own functions as written, without iblx's guards (tests/gpu/probe/analytic_brdf_probe.comp).
struct IsFuncSample {
  glm::dvec3 wi;
  double pdf = 0.0;
  glm::dvec3 weight;  // sampleBRDF's return value
};
class AnalyticBrdfProbe {
 public:
  AnalyticBrdfProbe(const std::string& file, const std::vector<std::pair<std::string, std::string>>& params,
                    glm::dvec3 wo);
  ~AnalyticBrdfProbe();
  bool hasSampler() const;
  std::vector<IsFuncSample> sample(std::span<const glm::dvec2> u);  // sampleBRDF
  std::vector<glm::dvec3> brdf(std::span<const glm::dvec3> wi);     // BRDF(wi, wo)
  std::vector<double> pdf(std::span<const glm::dvec3> wi);          // pdfBRDF(wi, wo)

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace iblx::test
