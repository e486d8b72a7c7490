// Names joined for messages: "valid: sphere, plane, teapot".
#pragma once

#include <functional>
#include <string>
#include <string_view>

namespace iblx {

// The names of `items` (each item itself, or `name` of it: a member pointer or a function) joined by ", ".
template <typename Range, typename Name = std::identity>
std::string joinNames(Range&& items, Name name = {}) {
  std::string joined;
  for (auto&& item : items) {
    if (!joined.empty()) joined.append(", ");
    joined.append(std::string_view(std::invoke(name, item)));
  }
  return joined;
}

}  // namespace iblx
