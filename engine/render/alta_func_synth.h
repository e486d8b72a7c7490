// An ALTA function file made from any BRDF iblx can render (`iblx measured-synth --format alta-func`):
// Lambert becomes an exact diffuse lobe; any other BRDF is tabulated on the GPU (its compiled part,
// BrdfEvaluator) over a grid of Rusinkiewicz's (theta_h, theta_d, phi_d) and fitted by a rational function in
// the Chebyshev basis (fitAltaRational, engine/io/alta_func_fit.h), as ALTA's rational fitters do.
#pragma once

#include "engine/io/alta_func.h"
#include "engine/scene/scene.h"
#include "engine/vk/context.h"
#include "engine/vk/shader_compiler.h"

namespace iblx {

struct AltaSynthOptions {
  int degreeP = 5, degreeQ = 5;        // total degrees of the numerator and the denominator
  int thetaSteps = 24, phiSteps = 12;  // the grid: theta_h (square-root spaced), theta_d, phi_d in [0, pi]
};
struct AltaSynthResult {
  AltaFunc func;
  bool exact = false;        // a diffuse lobe written from Lambert's albedo
  double rmsRelative = 0.0;  // of the fit over the grid (fitAltaRational); 0 when exact
  std::size_t samples = 0;   // grid points above the horizon
};
AltaSynthResult synthesizeAltaFunc(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                                   const AltaSynthOptions& options = {});

}  // namespace iblx
