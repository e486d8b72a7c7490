// An ALTA function file (engine/io/alta_func.h) as an iblx BRDF: one generated GLSL part implementing
// interfaces/brdf.glsl with the sum of the file's lobes, and, when every lobe has a closed-form sampling
// routine (diffuse, Blinn, Beckmann, Ward), the `isfunc` hook (sampleBRDF / pdfBRDF, the contract of
// analytic_brdf.h).
// - brdfEval(wi, wo): the lobes' sum at wi = light, wo = view (n = +z, t = +x), 0 below the horizon; a
// negative
//   or non-finite sum counts as 0, as for .brdf files.
// - Parameters: every lobe coefficient per colour channel (diffuse_kd, blinn_ks, blinn_N, ward_ax,
//   ...; a kind used twice is numbered: ward1_ks, ward2_ks) and a colour scale per rational function
//   (rational_scale), with the file's values as defaults, so --param and the viewer's sliders edit them.
// - Sampling: a mixture with one component per lobe and channel, weighted by the channel's approximate albedo
//   at normal incidence (diffuse kd pi, Blinn Ks pi min(1, 8 / (N + 2)), Beckmann and Ward Ks); the pdf is
//   the same mixture of the components' exact densities (cosine; Blinn's cos^N theta_h; Beckmann and Ward by
//   the anisotropic Beckmann distribution of half vectors, Walter 2005, "Notes on the Ward BRDF"), so it is
//   exact for any parameter values. A half vector is read with both orientations (a sampled h with wo.h < 0
//   reflects wo to the same wi as -h), so every sample keeps a positive density and the pdf integrates to 1
//   over the sphere at grazing views too. A file with a rational function is sampled by brdf-tab.
#pragma once

#include "engine/io/alta_func.h"
#include "engine/scene/methods.h"

#include <filesystem>
#include <memory>

namespace iblx {

std::shared_ptr<const BrdfInfo> makeAltaFuncBrdf(const AltaFunc& func, const std::filesystem::path& file);

// The generated GLSL (exposed for tests).
std::string altaFuncBrdfSource(const AltaFunc& func, const std::string& displayName);

}  // namespace iblx
