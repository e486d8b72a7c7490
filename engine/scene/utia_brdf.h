// A UTIA .bin file (engine/io/utia.h) as an iblx BRDF: its table, the GLSL part shaders/brdf/utia.glsl, and
// the file's colour convention as parameters (prescale, srgb, scale), so `--param` and the viewer's sliders
// change how the stored values are read.
#pragma once

#include "engine/io/utia.h"
#include "engine/scene/methods.h"

#include <filesystem>
#include <memory>

namespace iblx {

// The BRDF named after the file; sampled by brdf-tab (its half-vector tables follow the lobe's azimuth, since
// UTIA data is anisotropic).
std::shared_ptr<const BrdfInfo> makeUtiaBrdf(UtiaBrdf brdf, const std::filesystem::path& file);

// The convention of the parameter values (BrdfInfo::params of makeUtiaBrdf, as resolveParams returns them).
UtiaConvention utiaConvention(const ParamValues& values);

}  // namespace iblx
