// Structs that cross the host/GPU line, compiled by both C++ and glslang (STYLE "For iblx" 6).
// Only scalars and vec4 are used so std430 and C++ layouts agree; the C++ side static_asserts the sizes.
#ifndef IBLX_SHARED_FRAME_PARAMS_H
#define IBLX_SHARED_FRAME_PARAMS_H

#ifdef __cplusplus
#include <cstdint>
namespace iblx::gpu {
using uint = std::uint32_t;
struct vec4 {
  float x = 0, y = 0, z = 0, w = 0;
};
#endif

// One G-buffer entry per pixel (set 0, binding 0).
struct GPixel {
  vec4 normal;   // xyz: shading normal (world); w: 1 = object pixel, 0 = background
  vec4 tangent;  // xyz: tangent t (world); the bitangent is cross(n, t)
  vec4 view;     // xyz: direction to the viewer wo (world); for background pixels the direction seen
};

// One accumulation entry per pixel (set 0, binding 1): running means over all samples so far (DESIGN §6).
struct AccumPixel {
  vec4 mean;        // rgb: mean estimate; a: unused
  vec4 meanSquare;  // rgb: mean of the squared estimates (per-pixel variance = meanSquare - mean^2)
};

// Counters written by kernels (set 0, binding 4).
struct KernelStats {
  uint nonFiniteSamples;  // estimates that were NaN or Inf and were replaced by 0 (must stay 0)
  uint pad0, pad1, pad2;
};

// Push constants of the integrator and reference kernels.
struct FrameParams {
  uint width;
  uint height;
  uint envWidth;
  uint envHeight;
  uint sampleOffset;  // samples already accumulated per pixel (reference kernel: first texel of the dispatch)
  uint samplesPerPass;  // samples added by this dispatch (reference kernel: end texel of the dispatch)
  uint seed;
  uint probeMode;    // test probes (tests/gpu/probe): which query to answer
  vec4 envRotation;  // x: cos, y: sin of the rotation about +Y (world -> env), zw unused
  vec4 strategy;     // x: MIS fraction of env samples, y: heuristic (0 balance, 1 power);
                     // reference: z sin of the horizon band, w subdivisions per axis inside it
  vec4 quadrature;   // reference: x coarse, y fine subdivisions per texel axis, z cos of the fine-zone angle,
                     // w unused
};

#ifdef __cplusplus
}  // namespace iblx::gpu
#endif

#endif
