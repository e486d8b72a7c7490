// Settings from environment variables (engine/core/environment.h).
#include "engine/core/environment.h"

#include <cmath>
#include <cstdlib>

namespace iblx {

double environmentNumber(const char* name, double fallback, double upper) {
  const char* text = std::getenv(name);
  if (!text || !*text) return fallback;
  char* end = nullptr;
  const double value = std::strtod(text, &end);
  return end && *end == '\0' && std::isfinite(value) && value > 0.0 && value < upper ? value : fallback;
}

}  // namespace iblx
