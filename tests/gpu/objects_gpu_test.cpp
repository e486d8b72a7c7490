// End-to-end tests of the rasterized objects on lavapipe: the teapot converges to its convolution reference
// for every method, and the plane at grazing orbits renders without NaN or Inf. The G-buffer is all the
// kernels see, so these check that mesh G-buffers (bent normals, two-sided back faces, tangents from the
// normal field) are valid shading frames for every technique.
#include "engine/render/renderer.h"
#include "tests/gpu/gpu_fixture.h"
#include "tests/gpu/render_checks.h"
#include "tests/support/hard_envs.h"

#include <doctest/doctest.h>

#include <cmath>

using namespace iblx;
using namespace iblx::test;

TEST_CASE("teapot: every method converges to the convolution reference (z-test)") {
  // 32 px from orbits that show the lid, the inside of the handle (back faces) and silhouettes with bent
  // normals; GGX with a diffuse lobe so both BRDF techniques matter, and Lambert under a 1e6 sun next to an
  // exactly-zero half. The plane at 80° tests grazing frames. |z| < 5.5 as for the sphere
  // (render_gpu_test.cpp). Every registry method once: the objects change the shading frames, which every
  // technique meets alike; the sphere's tests render every combination.
  struct Case {
    std::string name, object;
    CameraSpec camera;
    EnvImage env;
    std::string brdf;
    std::vector<std::pair<std::string, std::string>> params;
  };
  const Case cases[] = {
      {"teapot ggx a=0.3/smooth",
       "teapot",
       {30, 25, 1},
       smoothSky(32, 16),
       "ggx",
       {{"roughness", "0.3"}, {"metallic", "0.5"}}},
      {"teapot lambert/sun+zero", "teapot", {-40, 10, 1.2}, sunAndZeroHalf(32, 16), "lambert", {}},
      {"plane at 80 deg ggx a=0.15/smooth",
       "plane",
       {20, 80, 2},
       smoothSky(32, 16),
       "ggx",
       {{"roughness", "0.15"}}},
  };
  for (const auto& c : cases) {
    const Scene scene = sceneWith(c.env, c.brdf, c.params, 32, c.object, c.camera);
    INFO(c.name << ": " << scene.gbuffer.objectPixelCount() << " object pixels");
    REQUIRE(scene.gbuffer.objectPixelCount() > 150);
    checkConvergesToReference(scene, c.name, 5.5, MethodSet::EveryMethod);
  }
}

TEST_CASE("objects: no NaN or Inf for any method on the plane at grazing orbits and the teapot under a sun") {
  struct Case {
    std::string name, object;
    CameraSpec camera;
    std::string brdf;
    std::vector<std::pair<std::string, std::string>> params;
  };
  // Zoom 3 at elevation 85 keeps about 8 rows of the plane in 32 px, all at n . wo = cos 85° = 0.087;
  // at 89.5° (n . wo = 0.0087) one or two rows remain.
  const Case cases[] = {
      {"plane at 85 deg, ggx a=1e-3", "plane", {30, 85, 3}, "ggx", {{"roughness", "0.001"}}},
      {"plane at 89.5 deg, lambert", "plane", {-60, 89.5, 8}, "lambert", {}},
      {"teapot, ggx a=0.05 dielectric",
       "teapot",
       {-120, -30, 1},
       "ggx",
       {{"roughness", "0.05"}, {"metallic", "0"}}},
  };
  for (const auto& c : cases) {
    const Scene scene = sceneWith(sunAndZeroHalf(64, 32), c.brdf, c.params, 32, c.object, c.camera);
    INFO(c.name << ": " << scene.gbuffer.objectPixelCount() << " object pixels");
    CHECK(scene.gbuffer.objectPixelCount() >= 32);
    checkFiniteForEveryMethod(scene, c.name, 29);
  }
  checkNoNewValidationErrors();
}
