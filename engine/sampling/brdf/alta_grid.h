// The table iblx renders an ALTA data file (engine/io/alta_data.h) with: the samples' values on a regular
// grid of the file's parametrisation, interpolated multilinearly (the axes may be spaced unevenly, as
// measurements often are). Samples that lie on a regular grid are the table; scattered samples (and every
// CARTESIAN file, whose unit vectors cannot form a grid) are resampled onto an even grid of the
// parametrisation (CARTESIAN: SPHERICAL_TL_PL_TV_PV) spanning the samples: each node takes the
// inverse-distance-weighted mean (power 2) of its 8 nearest samples, distances measured with every axis
// scaled to [0, 1] (Shepard 1968), with a warning that says so and gives the resampling's leave-one-out
// error (each sample predicted from its 8 nearest others). Samples at the same coordinates are one sample
// with their mean value; the nearest samples are found in a k-d tree, so clustered samples cost no more than
// spread ones. The CPU lookup here is the twin of
// shaders/brdf/alta_data.glsl.
//
// Azimuths outside an axis's range are brought into it by the symmetries of the parametrisation: a whole turn
// always; for isotropic parametrisations an axis over [0, pi] also uses reciprocity (phi_d and phi_d + pi,
// for Rusinkiewicz's phi_d) or the mirror symmetry of the plane of incidence (phi_L - phi_V and its
// negative), and one over [0, pi / 2] both. Every coordinate is then clamped to its axis.
#pragma once

#include "engine/io/alta_data.h"
#include "engine/sampling/technique_data.h"

#include <glm/glm.hpp>

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace iblx {

// How a coordinate is brought into its axis's range before clamping.
enum class AltaFold { Clamp = 0, Turn = 1, Reciprocity = 2, Mirror = 3, ReciprocityMirror = 4 };

struct AltaGrid {
  AltaParam param = AltaParam::RusinThTdPd;  // never Cartesian
  bool cosineFactor = false;                 // the values are f cos(theta_L)
  std::vector<std::vector<double>> axes;     // node coordinates per dimension, increasing
  std::vector<AltaFold> folds;               // per dimension
  std::vector<float> rgb;                    // planar: channel * nodes + node, the last axis fastest
  std::size_t resampledFrom = 0;             // > 0: this many scattered samples were resampled
  std::size_t distinctSamples = 0;           // of them, at distinct coordinates (repeats are averaged)
  // Resampled: the relative RMS error of predicting each distinct sample from its 8 nearest others (the
  // resampling's leave-one-out error); nullopt for a regular grid or 8 samples or fewer.
  std::optional<double> leaveOneOutError;
  std::size_t nodes() const { return rgb.size() / 3; }
};

// Throws iblx::Error naming `name` when the grid would exceed the memory budget.
// " (leave-one-out error E % over N distinct samples)" for a resampled grid, else empty.
std::string leaveOneOutText(const AltaGrid& grid);
AltaGrid makeAltaGrid(const AltaData& data, const std::string& name);

// f(wi, wo) in 1/sr: 0 when either direction is at or below the horizon.
glm::dvec3 evalAltaGrid(const AltaGrid& grid, glm::dvec3 wi, glm::dvec3 wo);

// The grid's table ("altaData": the axes, then the values) and the ALTA_* defines of its GLSL part.
TechniqueData altaGridTechniqueData(const AltaGrid& grid);

// `iblx measured-synth --format alta`: the sample positions of a regular grid of `param` (RUSIN_TH_TD_PD,
// RUSIN_TH_TD, ISOTROPIC_TV_TL_DPHI or SPHERICAL_TL_PL_TV_PV), theta_h spaced as MERL's (sqrt-warped) for
// Rusinkiewicz's coordinates, or of `scattered` random direction pairs (any param; 20,000 when 0 for the
// others), and the direction pairs to evaluate there.
struct AltaSynthPlan {
  AltaData data;  // x filled, rgb to fill
  std::vector<glm::dvec3> wi, wo;
};
AltaSynthPlan planAltaSynth(AltaParam param, AltaOutput output, std::size_t scattered);
// f at plan.wi, plan.wo (1/sr): fills the values (times cos theta_L for INV_STERADIAN_COSINE_FACTOR).
AltaData finishAltaSynth(AltaSynthPlan plan, const std::vector<glm::dvec3>& f);

}  // namespace iblx
