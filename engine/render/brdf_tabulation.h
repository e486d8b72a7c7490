// Evaluation of a scene's BRDF (its compiled GLSL part, so every BRDF iblx can render) at direction pairs on
// the GPU. `iblx merl-synth` tabulates built-in BRDFs into MERL files with it; the tests compare GPU
// evaluations with CPU ones.
#pragma once

#include "engine/io/mit_brdf.h"
#include "engine/scene/scene.h"
#include "engine/vk/context.h"
#include "engine/sampling/brdf/merl_sampling.h"
#include "engine/sampling/brdf/alta_grid.h"
#include "engine/sampling/brdf/rgl_sampling.h"
#include "engine/vk/shader_compiler.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace iblx {

// The GPU services the registry's builders get (engine/scene/methods.h): through this device and compiler.
class VulkanServices final : public GpuServices {
 public:
  VulkanServices(const VulkanContext& vulkanContext, ShaderCompiler& shaderCompiler)
      : context(vulkanContext), compiler(shaderCompiler) {}
  std::shared_ptr<const MerlTableData> tabulateBrdf(const Scene& scene) const override;
  double measureLobeWidth(const Scene& scene) const override;

  const VulkanContext& context;
  ShaderCompiler& compiler;
};

// f(wi, wo) in 1/sr for each pair (local frame: normal +z), evaluated as the integrator would. Runs in chunks
// within the device's dispatch and buffer limits. Compiles and uploads once; call evaluate() many times.
class BrdfEvaluator {
 public:
  // `unguarded`: a .brdf file's values as written, without the generated part's clamp of negative and
  // non-finite values to 0 (to test the file itself).
  BrdfEvaluator(const VulkanServices& gpu, const Scene& scene, bool unguarded = false);
  ~BrdfEvaluator();
  std::vector<glm::dvec3> evaluate(std::span<const glm::dvec3> wi, std::span<const glm::dvec3> wo) const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};
std::vector<glm::dvec3> evaluateBrdf(const VulkanContext& context, ShaderCompiler& compiler,
                                     const Scene& scene, std::span<const glm::dvec3> wi,
                                     std::span<const glm::dvec3> wo);

// Angular width (radians) of the narrowest lobe of the scene's BRDF, measured on the GPU: the full width at
// half maximum of f cos along great circles through the mirror direction (in and across the plane of
// incidence, for views at 0 and 60 degrees), at 0.05 degree steps. 0 when f cos has no peak (a maximum below
// 4 times its mean along the circle). The reference refines its quadrature around lobes narrower than its
// texels.
double estimateLobeWidth(const VulkanServices& gpu, const Scene& scene);

// brdf-tab's tables: the half-vector tables of merl-table (engine/sampling/brdf/merl_sampling.h) with the
// sampling weight mean(f) of the scene's compiled BRDF, evaluated on the GPU. Kept in memory per BRDF source
// and parameter values, so the renderers of one scene (bench, converge) build them once.
std::shared_ptr<const MerlTableData> tabulateBrdfTable(const VulkanServices& gpu, const Scene& scene);

// A built-in BRDF tabulated in MERL's layout: the values of writeMerl (3 * kMerlBins, planar, 1/sr), each the
// BRDF at its bin's centre (merlBinCenter). A centre direction at or below the horizon is evaluated at the
// nearest direction 1e-3 above it, so every bin that valid pairs fall into holds the BRDF's value (a Lambert
// table is exactly constant) — unless `invalidBelowHorizon`, which writes -1 there as measured files do.
// `invalidFraction` of the bins, chosen by `seed`, are also written as -1.
struct MerlSynthOptions {
  bool invalidBelowHorizon = false;
  double invalidFraction = 0.0;
  uint32_t seed = 1;
};
struct MerlSynthResult {
  std::vector<double> values;
  std::size_t invalidBins = 0;
};
MerlSynthResult tabulateMerl(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                             const MerlSynthOptions& options = {});

// A BRDF tabulated in UTIA's .bin layout (engine/io/utia.h): its values at every grid pair of (theta_i,
// phi_i) x (theta_v, phi_v), planar, as writeUtia stores them.
std::vector<double> tabulateUtia(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene);

// A BRDF tabulated in MIT CSAIL's .dat layout (engine/io/mit_brdf.h) at every bin centre of `dims`, planar,
// as writeMitBrdf stores them.
std::vector<float> tabulateMit(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                               const MitDims& dims);

// A BRDF tabulated in the RGL-EPFL .bsdf layout (engine/sampling/brdf/rgl_sampling.h, planRglSynth). A layout
// whose alpha is 0 takes the warps' GGX width from the BRDF's measured lobe (0.6 for a lobe-less BRDF, where
// a Lambert fixture is then within 1 % on average, 8 % at worst).
RglTables tabulateRgl(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                      RglSynthLayout layout);

// A BRDF sampled for an ALTA data file (engine/sampling/brdf/alta_grid.h, planAltaSynth): on a regular grid
// of `param`, or at `scattered` random direction pairs when that is > 0 (always for CARTESIAN).
AltaData tabulateAltaData(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                          AltaParam param, AltaOutput output, std::size_t scattered);

}  // namespace iblx
