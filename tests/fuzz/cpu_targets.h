// The fuzz targets every build has (tests/fuzz/cpu_targets.cpp).
#pragma once

#include "tests/fuzz/fuzz_target.h"

#include <vector>

namespace iblx::fuzz {

std::vector<FuzzTarget> cpuFuzzTargets();

}  // namespace iblx::fuzz
