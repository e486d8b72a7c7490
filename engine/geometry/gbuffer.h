// G-buffers (docs/DESIGN.md §2): per pixel the shading frame and view direction of the object, or the direction the
// background shows. The object is the analytic unit sphere, or a triangle mesh (the plane, the teapot, an OBJ
// file) rasterized on the CPU (engine/geometry/rasterizer.h); the camera is engine/geometry/camera.h's.
// Every vector is in world space. There is no visibility term (docs/DESIGN.md §1): a G-buffer is all the kernels see.
#pragma once

#include "engine/geometry/camera.h"
#include "engine/geometry/mesh.h"
#include "shaders/shared/frame_params.h"

#include <filesystem>
#include <string>
#include <vector>

namespace iblx {

static_assert(sizeof(gpu::GPixel) == 48);
static_assert(sizeof(gpu::AccumPixel) == 32);
static_assert(sizeof(gpu::FrameParams) == 96);

struct GBuffer {
  int width = 0, height = 0;
  std::vector<gpu::GPixel> pixels;
  std::size_t objectPixelCount() const;
  // 1 for object pixels, 0 for background, per pixel (the display transform's automatic exposure reads it).
  std::vector<std::uint8_t> objectMask() const;
};

// Every pixel background: normal.w = 0 and view = what the camera's pinhole sees there
// (CameraFrame::backgroundDirection; display only, never part of an error metric).
GBuffer makeBackgroundGBuffer(const CameraFrame& frame, int width, int height);

// An object pixel: normal.w = 1, tangentFromNormal(n), view = wo.
void setObjectPixel(gpu::GPixel& pixel, glm::dvec3 normal, glm::dvec3 view);

// The analytic unit sphere. With the default camera this is docs/DESIGN.md §3: pixel (x, y) inside the unit circle
// has n = (x, y, sqrt(1-x²-y²)) and wo = +Z; the tangent follows the latitude about +Y. With an orbit the
// same camera-space normal is turned into the world by the camera's frame, so a pixel sees what the rotated
// camera sees; the zoom scales the image-plane point.
GBuffer makeSphereGBuffer(int width, int height, const CameraSpec& camera = {});

// The path `--object teapot` loads: teapot.obj in $IBLX_ASSET_DIR, else in the source tree's assets/.
std::filesystem::path teapotObjPath();

// The built-in objects, in the order the CLI's help, its errors and the viewer's list show them.
inline constexpr const char* kObjectNames[] = {"sphere", "plane", "teapot"};
// "sphere, plane, teapot".
std::string objectNameList();

// The mesh of a non-sphere --object: "plane" (makePlaneMesh), "teapot" (teapotObjPath(), fitted into the unit
// sphere) or a path ending in .obj (loadObjMesh). Throws iblx::Error for an unknown name or a bad file.
TriMesh loadObjectMesh(const std::string& object);

// The G-buffer of --object NAME|FILE seen by `camera`. Throws a SettingError listing the valid names otherwise.
GBuffer makeGBuffer(const std::string& object, const CameraSpec& camera, int width, int height);

}  // namespace iblx
