// glslang's info log turned into the one-line messages iblx reports: "FILE:LINE: problem", naming the file
// (a .brdf, or the kernel part) the error is in.
#pragma once

#include <string>

namespace iblx {

// The first error of a glslang info log as "FILE:LINE: problem (GLSL compile error in CONTEXT)", with the
// number of further errors; the whole log, trimmed, when it holds no line in glslang's "ERROR: FILE:LINE:"
// shape.
std::string formatGlslLog(const std::string& infoLog, const std::string& context);

}  // namespace iblx
