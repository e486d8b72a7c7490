// G-buffers of the analytic sphere and of the named objects (engine/geometry/gbuffer.h).
#include "engine/geometry/gbuffer.h"

#include "engine/core/assets.h"
#include "engine/core/error.h"
#include "engine/core/setting.h"
#include "engine/core/file_names.h"
#include "engine/core/join.h"
#include "engine/geometry/obj_file.h"
#include "engine/geometry/rasterizer.h"
#include "engine/core/sphere_mapping.h"

#include <algorithm>
#include <cctype>

namespace iblx {

std::size_t GBuffer::objectPixelCount() const {
  std::size_t n = 0;
  for (const auto& p : pixels) n += p.normal.w != 0.0f;
  return n;
}

std::vector<std::uint8_t> GBuffer::objectMask() const {
  std::vector<std::uint8_t> mask(pixels.size());
  for (std::size_t p = 0; p < pixels.size(); ++p) mask[p] = pixels[p].normal.w != 0.0f;
  return mask;
}

GBuffer makeBackgroundGBuffer(const CameraFrame& frame, int width, int height) {
  GBuffer g{width, height, std::vector<gpu::GPixel>(std::size_t(width) * height)};
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i) {
      auto& px = g.pixels[std::size_t(j) * width + i];
      const glm::dvec3 d = frame.backgroundDirection(pixelToImagePlane(i, j, width, height));
      px.normal = {0.0f, 0.0f, 1.0f, 0.0f};
      px.tangent = {1.0f, 0.0f, 0.0f, 0.0f};
      px.view = {float(d.x), float(d.y), float(d.z), 0.0f};
    }
  return g;
}

void setObjectPixel(gpu::GPixel& px, glm::dvec3 n, glm::dvec3 view) {
  const glm::dvec3 t = tangentFromNormal(n);
  px.normal = {float(n.x), float(n.y), float(n.z), 1.0f};
  px.tangent = {float(t.x), float(t.y), float(t.z), 0.0f};
  px.view = {float(view.x), float(view.y), float(view.z), 0.0f};
}

GBuffer makeSphereGBuffer(int width, int height, const CameraSpec& camera) {
  checkCamera(camera);
  const CameraFrame frame = cameraFrame(camera);
  GBuffer g = makeBackgroundGBuffer(frame, width, height);
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i)
      // The normal in camera space, then in the world (the identity for the default camera).
      if (auto n = sphereNormalAt(frame.onPlane(pixelToImagePlane(i, j, width, height))))
        setObjectPixel(g.pixels[std::size_t(j) * width + i], frame.toWorld(*n), frame.back);
  return g;
}

std::filesystem::path teapotObjPath() {
  return assetPath("teapot.obj");
}

std::string objectNameList() {
  return joinNames(kObjectNames);
}

TriMesh loadObjectMesh(const std::string& object) {
  if (object == "plane") return makePlaneMesh();
  if (object == "teapot") {
    const auto path = teapotObjPath();
    if (!std::filesystem::exists(path))
      throw SettingError(Setting::Object, "",
                         " teapot: " + path.string() + ": no such file (iblx make-teapot writes it)");
    return loadObjMesh(path);
  }
  if (lowerExtension(object) == ".obj") return loadObjMesh(object);
  throw SettingError(Setting::Object, "unknown ",
                     " '" + object + "'; valid: " + objectNameList() + ", or a file ending in .obj");
}

GBuffer makeGBuffer(const std::string& object, const CameraSpec& camera, int width, int height) {
  checkCamera(camera);
  if (object == "sphere") return makeSphereGBuffer(width, height, camera);
  return rasterizeMesh(loadObjectMesh(object), camera, width, height);
}

}  // namespace iblx
