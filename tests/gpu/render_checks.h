// Helpers shared by the end-to-end GPU tests: every method the registry offers for a BRDF, small scenes, and
// the z-test of a render's mean signed error against a reference.
#pragma once

#include "engine/render/metrics.h"
#include "engine/render/renderer.h"
#include "engine/scene/scene.h"
#include "tests/gpu/gpu_fixture.h"

#include <string>
#include <utility>
#include <vector>

namespace iblx::test {

// Every (method, technique) combination the registry offers for a BRDF: single env techniques, every
// applicable BRDF technique alone, MIS of every env technique with every applicable BRDF technique
// (two-sample, balance heuristic; the BRDF's best sampler also with the power heuristic, with MIS compensation
// for the table-based env techniques, and with env-cdf as one-sample MIS at a 0.3 split), and RIS over every
// env technique (8 candidates), and the product strategies (product-mis with the BRDF's best sampler).
std::vector<MethodSpec> allMethodSpecs(const BrdfInfo& brdf, const std::string& sequence);

// The unit view direction at polar angle theta and azimuth phi (degrees) in the local shading frame (n = +z).
glm::dvec3 viewAt(double thetaDegrees, double phiDegrees = 0.0);
// A direction of the upper hemisphere from a uniform point: cos theta = u.x, phi = 2 pi u.y (uniform over the
// hemisphere's solid angle).
glm::dvec3 hemisphere(glm::dvec2 u);

// A square scene of `object` (default the sphere) seen by `camera`; `brdf` is a built-in name or a file (e.g.
// a MERL .binary).
Scene sceneWith(EnvImage env, const std::string& brdf,
                std::vector<std::pair<std::string, std::string>> params, int size,
                const std::string& object = "sphere", const CameraSpec& camera = {});

// The engine's z-test (engine/render/metrics.h) of a renderer's current image.
MeanErrorZTest zTest(const Scene& scene, const Renderer& renderer, const std::vector<float>& reference);

// Which methods the checks below render: every combination of env and BRDF technique the registry offers for
// the scene's BRDF, under both sequences (the default); or, for a BRDF part that is new beside techniques
// tested elsewhere, every registry method once with its default techniques, under sobol.
enum class MethodSet { EveryCombination, EveryMethod };
std::vector<MethodSpec> methodSpecs(const BrdfInfo& brdf, MethodSet set);

// White furnace (constant environment 1): renders every method the registry offers for the scene's BRDF with
// both sequences (or `set`), `passes` x 64 spp each, and checks that every object pixel's mean is within
// `sigmas` standard errors (plus 1e-4 of float rounding) of `albedo` and that no estimate was NaN or Inf.
// Failing pixels are reported with their method.
void checkWhiteFurnace(const Scene& scene, double albedo, int passes, double sigmas,
                       MethodSet set = MethodSet::EveryCombination);

// The ground truths of two scenes of one geometry (a tabulated material against its analytic source) over the
// object pixels: the ratio of their sums, b over a, and the largest channel difference relative to a's value
// (plus 0.01).
struct ReferenceComparison {
  double sumRatio = 0.0, worstRelative = 0.0;
};
ReferenceComparison compareReferences(const Scene& a, const Scene& b);

// Chi-square of a BRDF technique's sampled directions (those with pdf > 0) against its own pdf, on cells fine
// enough for the slivers next to the horizon (the harness refines narrow lobes itself), and the pdf
// integrating to 1 over the sphere. `testCount` is the family size for the Sidak correction.
void checkChi2AgainstPdf(BrdfTechniqueProbe& probe, std::span<const glm::dvec3> directions, int testCount,
                         const std::string& label);

// Renders every method the registry offers for the scene's BRDF (both sequences, one pass of 32 spp) and
// checks that no estimate was NaN or Inf and that every pixel's mean is finite and non-negative.
void checkFiniteForEveryMethod(const Scene& scene, const std::string& name, uint32_t seed);

// Computes the scene's reference and checks every method the registry offers for its BRDF (both sequences,
// 8 x 64 spp) against it: |z| < zBound per channel (see zTest) and no NaN/Inf estimate. `name` labels
// failures.
void checkConvergesToReference(const Scene& scene, const std::string& name, double zBound,
                               MethodSet set = MethodSet::EveryCombination);

}  // namespace iblx::test
