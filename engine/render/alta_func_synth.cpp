// ALTA function files from iblx BRDFs (alta_func_synth.h).
#include "engine/render/alta_func_synth.h"

#include "engine/io/alta_func_fit.h"
#include "engine/core/error.h"
#include "engine/render/brdf_tabulation.h"

#include <numbers>

namespace iblx {

AltaSynthResult synthesizeAltaFunc(const VulkanContext& context, ShaderCompiler& compiler, const Scene& scene,
                                   const AltaSynthOptions& options) {
  if (options.degreeP < 0 || options.degreeQ < 0 || options.degreeP > 10 || options.degreeQ > 10)
    throw Error("the rational fit's degrees must be in [0, 10]");
  AltaSynthResult result;
  AltaFunc& f = result.func;
  f.dimX = 3;
  f.dimY = 3;
  f.paramIn = AltaParam::RusinThTdPd;
  if (scene.brdf->name == "lambert" && scene.brdf->evalSource.empty()) {
    // f = albedo / pi exactly: ALTA's nonlinear_function_diffuse holds the value in 1/sr.
    f.command = "iblx measured-synth --func nonlinear_function_diffuse";
    AltaLobe lobe;
    lobe.kind = AltaLobeKind::Diffuse;
    const auto albedo = scene.params.at("albedo");
    for (int c = 0; c < 3; ++c) lobe.values.push_back({albedo[std::size_t(c)] / std::numbers::pi});
    f.lobes.push_back(std::move(lobe));
    result.exact = true;
    return result;
  }
  f.command = "iblx measured-synth --func rational_function_chebychev";
  f.basis = AltaBasis::Chebyshev;
  const double half = std::numbers::pi / 2.0;
  std::vector<double> x;
  std::vector<glm::dvec3> wis, wos;
  for (int h = 0; h < options.thetaSteps; ++h)
    for (int d = 0; d < options.thetaSteps; ++d)
      for (int p = 0; p < options.phiSteps; ++p) {
        // Square-root spacing in theta_h puts more points where specular lobes peak (as MERL's table does).
        const double uh = (h + 0.5) / options.thetaSteps;
        const double thetaH = uh * uh * half, thetaD = (d + 0.5) / options.thetaSteps * half;
        const double phiD = (p + 0.5) / options.phiSteps * std::numbers::pi;
        glm::dvec3 wi, wo;
        altaRusinDirections(thetaH, thetaD, phiD, wi, wo);
        if (wi.z <= 1e-3 || wo.z <= 1e-3) continue;
        x.insert(x.end(), {thetaH, thetaD, phiD});
        wis.push_back(wi);
        wos.push_back(wo);
      }
  const auto values = evaluateBrdf(context, compiler, scene, wis, wos);
  std::vector<std::vector<double>> y(3, std::vector<double>(values.size()));
  for (std::size_t i = 0; i < values.size(); ++i)
    for (int c = 0; c < 3; ++c) y[std::size_t(c)][i] = values[i][c];
  const std::vector<double> min{0.0, 0.0, 0.0}, max{half, half, std::numbers::pi};
  AltaFitResult fit = fitAltaRational(3, x, y, min, max, options.degreeP, options.degreeQ);
  AltaLobe lobe;
  lobe.kind = AltaLobeKind::Rational;
  lobe.rational = std::move(fit.rational);
  f.lobes.push_back(std::move(lobe));
  result.rmsRelative = fit.rmsRelative;
  result.samples = values.size();
  return result;
}

}  // namespace iblx
