// An RGL-EPFL material (engine/io/rgl_bsdf.h) as warps: evaluation and sampling with the file's own
// luminance and VNDF warps (Dupuy & Jakob 2018, §5-6), in double. It is the CPU twin of shaders/brdf/rgl.glsl
// (evaluation) and shaders/brdf_technique/rgl_vndf.glsl (technique rgl-vndf), which read the table this
// packs.
//
// In iblx's convention wo is the view and wi the light (interfaces/brdf.glsl); the file's tables are
// conditioned on the view (the "incident" direction of the paper, whose azimuth the isotropic tables are
// relative to). Directions of a unit square: theta = u_theta^2 pi / 2, phi = (2 u_phi - 1) pi.
#pragma once

#include "engine/io/rgl_bsdf.h"
#include "engine/sampling/bilinear_warp.h"
#include "engine/sampling/technique_data.h"

#include <glm/glm.hpp>

namespace iblx {

class RglBsdf {
 public:
  explicit RglBsdf(const RglTables& tables);

  // f(wi, wo) in 1/sr (the file stores f cos(theta_wi)); 0 when either direction is at or below the horizon.
  glm::dvec3 eval(glm::dvec3 wi, glm::dvec3 wo) const;
  struct Sample {
    glm::dvec3 wi;
    double pdf;  // solid-angle density of wi; 0: no sample
  };
  // Draws the light direction: u through the luminance warp, then the VNDF warp gives the microfacet
  // normal, and wi is wo reflected about it. wi may fall below the horizon (f = 0 there).
  Sample sample(glm::dvec2 u, glm::dvec3 wo) const;
  // The density sample() draws wi with, for any wi.
  double pdf(glm::dvec3 wi, glm::dvec3 wo) const;

  bool isotropic() const { return isotropic_; }
  int reduction() const { return reduction_; }
  const BilinearWarp2D& ndf() const { return ndf_; }
  const BilinearWarp2D& sigma() const { return sigma_; }
  const BilinearWarp2D& vndf() const { return vndf_; }
  const BilinearWarp2D& luminance() const { return luminance_; }

  // The material's one table (name "rglData") with the defines the GLSL parts read: RGL_* sizes and
  // offsets.
  TechniqueData techniqueData() const;

 private:
  // The view mirrored into the stored azimuth range, and the signs that undo it.
  struct Reduced {
    glm::dvec3 wo, wi;
    double sx, sy;
  };
  Reduced reduce(glm::dvec3 wi, glm::dvec3 wo) const;

  BilinearWarp2D ndf_, sigma_, vndf_, luminance_, rgb_;
  bool isotropic_, jacobian_;
  int reduction_;
};

// `iblx measured-synth --format rgl`: tables of any BRDF in the .bsdf layout. The warp's microfacet
// distribution is a GGX NDF of width `alpha` (ndf = D, sigma its projected area, vndf the visible normals);
// the rgb table holds f cos times the inverse Jacobian 4 sigma / ndf at the direction each node of the unit
// square maps to, so evaluation reproduces the BRDF exactly there and interpolates in between, and the
// luminance table is the rgb table's luminance, so rgl-vndf samples close to f cos. Planned in two steps
// around the GPU evaluation of the BRDF: plan the directions, then finish with the values there.
struct RglSynthLayout {
  std::uint32_t thetaViews = 10;  // theta_i every 89 / (n - 1) degrees
  std::uint32_t phiViews = 1;     // 1: isotropic; else phi_i from -pi to pi (at least 3)
  std::uint32_t vndfSize = 32;    // the ndf, sigma and vndf grids
  std::uint32_t sampleSize = 32;  // the luminance and rgb grids
  double alpha = 0.5;             // GGX width of the warps' NDF
};
struct RglSynthPlan {
  RglTables tables;                // without rgb and luminance yet
  std::vector<glm::dvec3> wi, wo;  // light and view per rgb node (phi, theta, y, x order)
  std::vector<double> toStored;    // per node: cos(theta_wi) 4 sigma / ndf (0 below the horizon)
};
RglSynthPlan planRglSynth(const RglSynthLayout& layout);
// f: the BRDF (1/sr) at plan.wi, plan.wo. Fills rgb and luminance and returns the tables.
RglTables finishRglSynth(RglSynthPlan plan, std::span<const glm::dvec3> f);

}  // namespace iblx
