// CSV fields for the CSV files iblx writes (converge's, study merge's): RFC 4180 quoting.
#pragma once

#include <string>

namespace iblx {

// `text` as one quoted CSV field, each quote doubled (RFC 4180, section 2, rules 5 and 7): a method label
// holds commas.
inline std::string csvQuoted(const std::string& text) {
  std::string quoted = "\"";
  for (const char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

}  // namespace iblx
