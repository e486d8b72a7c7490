// Offline diagnostics of where an environment sampler's pdf departs from the texel pdf that env-cdf samples
// (docs/BENCHMARKS.md "Optimal-transport sampling", docs/studies/ot_decompose.toml, `iblx otmap --diagnose`):
// - chi^2(p_texel || p_sampler) = sum over texels of p_texel^2 / p_sampler - 1: the relative variance per
//   sample of the estimate p_texel / p_sampler, i.e. what the pdf alone costs on an integrand proportional
//   to the environment;
// - the share of non-convex quads in the map an OT sampler evaluates (pieces split into two affine
//   triangles instead of one bilinear patch);
// - the round trip |F(G(u)) - u| of env-ot-inv's tabulated inverse G through the forward map F.
// The OT samplers have no CPU twin that samples; envOtFwdPdf and envOtInvPdf are CPU twins of their envPdf
// (shaders/env_technique/env_ot_fwd.glsl, env_ot_inv.glsl, shaders/lib/quad_grid_map.glsl, ot_sun.glsl), in
// double.
#pragma once

#include "engine/io/env_image.h"
#include "engine/ot/map.h"
#include "engine/sampling/env/env_ot_sun.h"

#include <glm/glm.hpp>

#include <cstddef>
#include <functional>
#include <span>
#include <vector>

namespace iblx {

// The texel pdf env-cdf samples: texelSamplingWeights (mean RGB times the texel's exact solid angle),
// normalised to sum 1, row-major.
std::vector<double> texelProbabilities(const EnvImage& image);

// A sampler's probability of every texel of a width x height lat-long map, row-major: the texel's solid angle
// times the mean of `pdf` (per unit solid angle) over subgrid x subgrid points of the texel spread uniformly
// in solid angle (the midpoints of a regular grid in phi and in cos(theta)). Exact for a pdf that is
// constant per texel (env-cdf, env-hier); the midpoint rule's error for one that varies inside texels.
std::vector<double> integrateTexelProbabilities(const std::function<double(glm::dvec3)>& pdf, int width,
                                                int height, int subgrid);

struct TexelChi2 {
  // sum p^2 / q - 1 over the texels with q > 0, with q normalised by qMass (so that an integration error
  // common to every texel does not read as a divergence).
  double chi2 = 0.0;
  double unreachableMass = 0.0;  // sum of p over the texels with q = 0 (the divergence is infinite if > 0)
  double qMass = 0.0;            // sum of q before normalisation: 1 up to the integration's error
};
// chi^2(p || q) of two per-texel probability tables of the same size. Throws iblx::Error when the sizes
// differ or a value is negative or not finite.
TexelChi2 texelChi2(std::span<const double> p, std::span<const double> q);

// The OT maps' parameter square (quad_grid_map.glsl): u = phi / 2pi; row r of densityGrid covers theta in
// [pi r / N, pi (r+1) / N], with cos(theta) linear inside the row. jacobian = dOmega / (du dv) in the row.
glm::dvec3 otParameterToDirection(glm::dvec2 x, int densityGrid, double& jacobian);
glm::dvec2 otDirectionToParameter(glm::dvec3 w, int densityGrid, double& jacobian);

// The maps the OT samplers evaluate, built as envOtFwdTechniqueData and envOtInvTechniqueData build their
// tables.
struct EnvOtSamplerMaps {
  OtSunSplit sun;       // the suns sampled apart (sunShare 0: none)
  int densityGrid = 0;  // OT_DENSITY_GRID: rows of the parameter square
  QuadGridMap forward;  // env-ot-fwd's map F: parameter square -> uniform square (untangled)
  QuadGridMap inverse;  // env-ot-inv's map G: uniform square -> parameter square, tabulated from F
};
// From the samplers' own split and map (solveEnvOtMaps: the cache, or a solve). Throws as they do.
EnvOtSamplerMaps envOtSamplerMaps(const EnvImage& image);
// From a given split and solved map (tests).
EnvOtSamplerMaps envOtSamplerMaps(OtSunSplit sun, const OtMap& map);

// The samplers' pdfs per unit solid angle at direction w: sunShare * pSun + (1 - sunShare) * pOt, with pOt
// |det DF| at w's parameter point (env-ot-fwd), or 1 / |det DG| at its preimage under G (env-ot-inv; the
// preimage looked for around F's image first, as the shader does), divided by dOmega / (du dv).
double envOtFwdPdf(const EnvOtSamplerMaps& maps, glm::dvec3 w);
double envOtInvPdf(const EnvOtSamplerMaps& maps, glm::dvec3 w);

// The share of a map's cells whose piece is not a bilinear patch (a non-convex quad split into triangles).
double nonConvexShare(const QuadGridMap& map);

struct MapRoundTrip {
  double max = 0.0, mean = 0.0;  // of |T(S(u)) - u| in the unit square, over the points that S maps
  std::size_t missed = 0;        // points S does not map (no piece contains them)
};
// |F(G(u)) - u| over points x points cell centres u of the unit square: env-ot-inv's tabulated inverse G
// against the forward map F.
MapRoundTrip inverseRoundTrip(const QuadGridMap& forward, const QuadGridMap& inverse, int points);
// |F(F^-1(u)) - u|, F^-1 by point location (QuadGridMap::invert), as env-ot-fwd samples: rounding only.
MapRoundTrip forwardRoundTrip(const QuadGridMap& forward, int points);

}  // namespace iblx
