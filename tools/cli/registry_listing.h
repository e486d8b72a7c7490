// The registry as text, for --list-methods: every method, technique, sequence and BRDF with its parameters.
#pragma once

#include "engine/scene/methods.h"

#include <string>

namespace iblx {

std::string describeRegistry();
// One BRDF with its parameters (types, ranges, defaults).
std::string describeBrdf(const BrdfInfo& brdf);

}  // namespace iblx
