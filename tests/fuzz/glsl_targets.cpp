// The fuzz target of the GLSL compiler path: a compute shader's text through ShaderCompiler (glslang's
// preprocessor, parser and SPIR-V back end, with #include resolved against the embedded shaders/ tree), as
// every user .brdf file's code takes it. The cache is off, so each input is compiled.
#include "tests/fuzz/glsl_targets.h"

#include "engine/vk/shader_compiler.h"

#include <string>

namespace iblx::fuzz {

namespace {

void runGlsl(std::span<const std::uint8_t> input) {
  // One compiler for the process: glslang's set-up and the embedded sources are built once.
  static ShaderCompiler compiler("-");
  compiler.compile(std::string(input.begin(), input.end()), "fuzz");
}

Bytes textBytes(std::string_view text) {
  return Bytes(text.begin(), text.end());
}

std::vector<Bytes> glslSeeds() {
  return {
      textBytes("#version 460\nlayout(local_size_x = 8, local_size_y = 8) in;\n"
                "layout(std430, binding = 0) buffer Out { vec4 values[]; };\n"
                "void main() {\n  uint i = gl_GlobalInvocationID.x;\n  values[i] = vec4(float(i) * 0.5, 1.0, "
                "sqrt(2.0), 0.0);\n}\n"),
      textBytes(
          "#version 460\n#extension GL_GOOGLE_include_directive : require\n#include \"lib/hash.glsl\"\n"
          "#include \"lib/warps.glsl\"\nlayout(local_size_x = 64) in;\n"
          "layout(std430, binding = 0) buffer Out { float values[]; };\n"
          "#define SCALE(x) ((x) * 2.0)\n"
          "void main() {\n  uvec4 h = pcg4d(uvec4(gl_GlobalInvocationID, 7u));\n"
          "  for (int k = 0; k < 4; ++k) values[gl_GlobalInvocationID.x] += SCALE(uintToUnitFloat(h[k]));\n"
          "}\n"),
  };
}

}  // namespace

std::vector<FuzzTarget> glslFuzzTargets() {
  // A compilation costs about as much as twenty file reads.
  return {{"glsl", "GLSL compute shader through glslang (ShaderCompiler::compile)", runGlsl, glslSeeds, 4.0}};
}

}  // namespace iblx::fuzz
