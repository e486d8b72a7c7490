// Analytic sphere G-buffer.
#include "engine/render/gbuffer.h"

#include "engine/core/error.h"
#include "engine/sampling/sphere_mapping.h"

namespace iblx {

std::size_t GBuffer::objectPixelCount() const {
  std::size_t n = 0;
  for (const auto& p : pixels) n += p.normal.w != 0.0f;
  return n;
}

GBuffer makeSphereGBuffer(int width, int height) {
  GBuffer g{width, height, std::vector<gpu::GPixel>(std::size_t(width) * height)};
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i) {
      auto& px = g.pixels[std::size_t(j) * width + i];
      const CameraRay ray = pixelToImagePlane(i, j, width, height);
      if (auto n = sphereNormalAt(ray)) {
        const glm::dvec3 t = glm::normalize(glm::dvec3(n->z, 0.0, -n->x));  // n.z > 0 on visible pixels
        px.normal = {float(n->x), float(n->y), float(n->z), 1.0f};
        px.tangent = {float(t.x), float(t.y), float(t.z), 0.0f};
        px.view = {0.0f, 0.0f, 1.0f, 0.0f};
      } else {
        const glm::dvec3 d = glm::normalize(glm::dvec3(ray.x, ray.y, -1.0));
        px.normal = {0.0f, 0.0f, 1.0f, 0.0f};
        px.tangent = {1.0f, 0.0f, 0.0f, 0.0f};
        px.view = {float(d.x), float(d.y), float(d.z), 0.0f};
      }
    }
  return g;
}

GBuffer makeGBuffer(const std::string& object, int width, int height) {
  if (object == "sphere") return makeSphereGBuffer(width, height);
  throw Error("unknown --object '" + object + "'; valid: sphere");
}

}  // namespace iblx
