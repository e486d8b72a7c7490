// Settings read from environment variables (IBLX_MEMORY_BUDGET_GIB, IBLX_GPU_TIMEOUT_S,
// IBLX_COMPILE_TIMEOUT_S): one parser, so that each is read the same way.
#pragma once

namespace iblx {

// The value of environment variable `name` when it is a number in (0, upper); otherwise (unset, empty, not a
// number, out of range) `fallback`.
double environmentNumber(const char* name, double fallback, double upper);

}  // namespace iblx
