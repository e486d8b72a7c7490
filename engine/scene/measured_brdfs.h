// Measured files beyond MERL as iblx BRDFs: a UTIA .bin (engine/io/utia.h; shaders/brdf/utia.glsl) with the
// file's colour convention as parameters (prescale, srgb, scale), and an MIT CSAIL .dat
// (engine/io/mit_brdf.h; shaders/brdf/mit.glsl) with a scale, so `--param` and the viewer's sliders change
// how the stored values are read. Both are sampled by brdf-tab (its half-vector tables follow an anisotropic
// lobe's azimuth). An RGL-EPFL .bsdf (engine/sampling/rgl_sampling.h; shaders/brdf/rgl.glsl) is sampled by
// its own luminance and VNDF warps, technique rgl-vndf.
#pragma once

#include "engine/io/mit_brdf.h"
#include "engine/io/utia.h"
#include "engine/sampling/rgl_sampling.h"
#include "engine/scene/methods.h"

#include <filesystem>
#include <memory>

namespace iblx {

// The BRDFs named after their files.
std::shared_ptr<const BrdfInfo> makeUtiaBrdf(UtiaBrdf brdf, const std::filesystem::path& file);
std::shared_ptr<const BrdfInfo> makeMitBrdf(MitBrdf brdf, const std::filesystem::path& file);
std::shared_ptr<const BrdfInfo> makeRglBrdf(const RglTables& tables, const std::filesystem::path& file);

// Whether a BRDF is an RGL-EPFL material (what technique rgl-vndf samples).
bool isRglBrdf(const BrdfInfo& brdf);

// The convention of the parameter values (BrdfInfo::params of makeUtiaBrdf, as resolveParams returns them).
UtiaConvention utiaConvention(const ParamValues& values);

}  // namespace iblx
