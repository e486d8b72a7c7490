// A BRDF Explorer .brdf file as an iblx BRDF: its parameters become the BRDF parameter block, its shader and
// isFunc sections become one generated GLSL part that implements interfaces/brdf.glsl (and, with an isFunc,
// what the `isfunc` BRDF technique calls). What the generated part guarantees:
// - brdfEval(wi, wo) = BRDF(L = wi, V = wo, N = +z, X = +x, Y = +y) when both are above the horizon, else 0;
//   a negative or non-finite value counts as 0 (like MERL's invalid bins), so one bad evaluation cannot turn
//   an image into NaN.
// - user functions named after GLSL built-ins (BRDF Explorer's phong.brdf redefines `reflect`) are renamed
//   with their calls to iblxUser_NAME, which glslang otherwise rejects;
// - compile errors name the .brdf file and its own line numbers (#line directives).
// The isFunc contract (an iblx decision; BRDF Explorer never called the hook): `vec3 sampleBRDF(float u,
// float v, vec3 N, vec3 X, vec3 Y, out vec3 wi, out float pdf)` draws wi towards the light with its exact
// solid-angle density pdf (0: no sample) and returns the weight f(wi, V) (N.wi) / pdf, which iblx does not
// use (it recomputes f cos / pdf, so a wrong return value cannot bias an image; the library's tests check
// it). The view direction, missing from the signature, is the global `vec3 iblxV`. For MIS the section must
// also define `float pdfBRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)`, the density of any L; iblx uses the
// hook only when both exist.
#pragma once

#include "engine/io/brdf_file.h"
#include "engine/scene/methods.h"

#include <memory>

namespace iblx {

// Throws iblx::Error "FILE:LINE: problem" for a parameter name GLSL reserves or iblx uses.
std::shared_ptr<const BrdfInfo> makeAnalyticBrdf(const BrdfFile& file);

// The generated GLSL (exposed for tests).
std::string analyticBrdfSource(const BrdfFile& file, const std::string& partPath);

// Renames user definitions of GLSL built-in functions and their calls (exposed for tests).
std::string renameBuiltinRedefinitions(const std::string& glsl, std::vector<std::string>* renamed = nullptr);

}  // namespace iblx
