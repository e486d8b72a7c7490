// Assertion failure reporting (debug builds only call it).
#include "engine/core/error.h"

#include <cstdio>
#include <cstdlib>

namespace iblx {

void assertionFailed(const char* expression, const char* file, int line) {
  std::fprintf(stderr, "iblx: internal assertion failed: %s (%s:%d)\n", expression, file, line);
  std::abort();
}

}  // namespace iblx
