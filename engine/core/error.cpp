// Excerpts of file text for messages, and assertion failure reporting (debug builds only call it).
#include "engine/core/error.h"

#include <cstdio>
#include <cstdlib>

namespace iblx {

std::string printableExcerpt(std::string_view text, std::size_t maxLength) {
  std::string out;
  for (std::size_t i = 0; i < text.size() && i < maxLength; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += char(c);
    } else {
      char escaped[5];
      std::snprintf(escaped, sizeof escaped, "\\x%02x", c);
      out += escaped;
    }
  }
  if (text.size() > maxLength) out += "...";
  return out;
}

void assertionFailed(const char* expression, const char* file, int line) {
  std::fprintf(stderr, "iblx: internal assertion failed: %s (%s:%d)\n", expression, file, line);
  std::abort();
}

}  // namespace iblx
