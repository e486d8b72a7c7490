// The GLSL sources under shaders/, embedded at build time (third_party/embed_shaders.cmake).
#pragma once

#include <string_view>
#include <vector>

namespace iblx {

struct EmbeddedShader {
  std::string_view path;  // relative to shaders/, e.g. "env_technique/env_cdf.glsl"
  std::string_view text;
};

const std::vector<EmbeddedShader>& embeddedShaders();

}  // namespace iblx
