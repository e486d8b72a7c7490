// The fuzz targets of the GLSL compiler path (tests/fuzz/glsl_targets.cpp): only in builds with glslang.
#pragma once

#include "tests/fuzz/fuzz_target.h"

#include <vector>

namespace iblx::fuzz {

std::vector<FuzzTarget> glslFuzzTargets();

}  // namespace iblx::fuzz
