// JSON lines through nlohmann-json (engine/core/json_output.h).
#include "engine/core/json_output.h"

#include "engine/core/log.h"

#include <cmath>
#include <cstdio>

namespace iblx {
namespace {

// A path need not be UTF-8 on Linux: its invalid bytes become U+FFFD instead of failing the whole output.
constexpr auto kReplaceInvalidUtf8 = nlohmann::json::error_handler_t::replace;

}  // namespace

std::string formatJson(const JsonObject& value, std::size_t* nonFinite) {
  if (value.is_object()) {
    std::string text = "{";
    for (auto it = value.begin(); it != value.end(); ++it) {
      if (it != value.begin()) text += ", ";
      text += JsonObject(it.key()).dump(-1, ' ', false, kReplaceInvalidUtf8) + ": " + formatJson(it.value(), nonFinite);
    }
    return text + "}";
  }
  if (value.is_array()) {
    std::string text = "[";
    for (std::size_t i = 0; i < value.size(); ++i) text += (i ? ", " : "") + formatJson(value[i], nonFinite);
    return text + "]";
  }
  if (value.is_number_float() && !std::isfinite(value.get<double>())) {
    if (nonFinite) ++*nonFinite;
    return "null";
  }
  return value.dump(-1, ' ', false, kReplaceInvalidUtf8);
}

void printJsonLine(const JsonObject& value) {
  std::size_t nonFinite = 0;
  std::printf("%s\n", formatJson(value, &nonFinite).c_str());
  if (nonFinite > 0)
    warn(std::to_string(nonFinite) + " figure" + (nonFinite == 1 ? " was" : "s were") +
         " NaN or infinite and " + (nonFinite == 1 ? "is" : "are") + " written as null");
}

}  // namespace iblx
