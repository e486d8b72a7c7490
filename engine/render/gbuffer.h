// G-buffers (DESIGN §2): per pixel the shading frame and view direction of the object, or the direction the
// background shows. Only the analytic unit sphere under the default orthographic camera for now.
#pragma once

#include "shaders/shared/frame_params.h"

#include <string>
#include <vector>

namespace iblx {

static_assert(sizeof(gpu::GPixel) == 48);
static_assert(sizeof(gpu::AccumPixel) == 32);
static_assert(sizeof(gpu::FrameParams) == 80);

struct GBuffer {
  int width = 0, height = 0;
  std::vector<gpu::GPixel> pixels;
  std::size_t objectPixelCount() const;
};

// DESIGN §3: orthographic camera looking down -Z at the unit sphere. Object pixels: n = (x, y,
// sqrt(1-x²-y²)), wo = +Z, tangent along the sphere's latitude (n.z, 0, -n.x). Background pixels show the
// environment through a pinhole looking down -Z with a 90° vertical field of view (display only; never part
// of an error metric).
GBuffer makeSphereGBuffer(int width, int height);

// Builds the G-buffer of a named object ("sphere"); throws listing the valid names otherwise.
GBuffer makeGBuffer(const std::string& object, int width, int height);

}  // namespace iblx
