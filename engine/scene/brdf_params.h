// A BRDF's parameters (BrdfInfo::params): values given as text checked and resolved against their
// declarations, packed into the GPU parameter block, and that block's GLSL declaration.
#pragma once

#include "engine/core/params.h"
#include "engine/scene/methods.h"

#include <string>
#include <utility>
#include <vector>

namespace iblx {

// Fills defaults, parses "r,g,b" / "x" / "0|1|true|false" strings, range-checks; throws on unknown names.
ParamValues resolveParams(const BrdfInfo& brdf,
                          const std::vector<std::pair<std::string, std::string>>& given);
// Packs values into the BRDF parameter block: one 16-byte slot per parameter in declaration order.
std::vector<float> packParams(const BrdfInfo& brdf, const ParamValues& values);
// GLSL declaration of that block (set 3, binding 0) with each parameter as a plain name.
std::string paramBlockGlsl(const BrdfInfo& brdf);
// A parameter's value as text: "0.25", or "0.95,0.64,0.54" for a colour.
std::string formatParamValue(const ParamDecl& decl, const std::array<double, 3>& value);

}  // namespace iblx
