// The file name of a GLSL #line directive, for the parts iblx generates from a user's file (a .brdf, an ALTA
// function): compile messages then name the user's file rather than the generated part.
#pragma once

#include <string>

namespace iblx {

// `file` as a #line string. glslang's preprocessor has no escapes in strings, so a quote, a backslash or a
// control character (a newline in a path) cannot be written at all: each becomes '?', which only changes how
// compile messages spell the path.
inline std::string glslLineFileName(const std::string& file) {
  std::string out = "\"";
  for (char c : file) out += c == '"' || c == '\\' || static_cast<unsigned char>(c) < 0x20 ? '?' : c;
  return out + "\"";
}

}  // namespace iblx
