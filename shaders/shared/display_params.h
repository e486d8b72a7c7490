// The viewer's display kernel's push constants (shaders/display.comp, tools/viewer/display_kernel.h),
// compiled by both C++ and glslang: scalars only, so std430 and C++ layouts agree.
#ifndef IBLX_SHARED_DISPLAY_PARAMS_H
#define IBLX_SHARED_DISPLAY_PARAMS_H

#ifdef __cplusplus
#include <cstdint>
namespace iblx::gpu {
using uint = std::uint32_t;
#endif

// Bits of DisplayParams::flags.
#define DISPLAY_HAS_A 1u
#define DISPLAY_HAS_B 2u
#define DISPLAY_ERROR_ROW 4u   // side by side: the error of A and B against the reference below them
#define DISPLAY_BACKGROUND 8u  // the environment around the object, else the window's grey
#define DISPLAY_FLIP_SHOWS_B 16u

struct DisplayParams {
  uint width, height;                   // of one image
  uint canvasWidth, canvasHeight;       // of the composed canvas
  uint view;                            // 0 split, 1 side by side, 2 flip (tools/viewer/compare_view.h)
  uint splitColumn;                     // split: A left of it, B from it on, the divider drawn on it
  uint flags;                           // DISPLAY_* bits
  uint tonemap;                         // 0 clamp, 1 Reinhard, 2 ACES (engine/io/image_write.h, Tonemap)
  float exposureScale;                  // 2^exposureEV
  float gamma;                          // 0: the exact sRGB OETF; otherwise x^(1/gamma)
  float errorLog10Low, errorLog10High;  // the error row's log10 colour scale
};

#ifdef __cplusplus
static_assert(sizeof(DisplayParams) == 48);
}  // namespace iblx::gpu
#endif
#endif
