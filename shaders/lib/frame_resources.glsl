// Set 0, the frame: G-buffer, accumulation, environment radiance and row solid angles, kernel counters,
// and the push constants. Every kernel that renders the scene includes this.
#ifndef IBLX_LIB_FRAME_RESOURCES
#define IBLX_LIB_FRAME_RESOURCES
#include "shared/frame_params.h"

layout(std430, set = 0, binding = 0) readonly buffer GBufferData { GPixel gbuffer[]; };
layout(std430, set = 0, binding = 1) buffer AccumData { AccumPixel accum[]; };
// Linear RGB of every texel, top row first, 3 floats per texel (nearest-texel reconstruction, DESIGN §3).
layout(std430, set = 0, binding = 2) readonly buffer EnvRadianceData { float envRgb[]; };
// Exact solid angle of one texel of each row, computed in double on the host.
layout(std430, set = 0, binding = 3) readonly buffer EnvRowSolidAngleData { float envRowSolidAngle[]; };
layout(std430, set = 0, binding = 4) buffer KernelStatsData { KernelStats stats; };

layout(push_constant) uniform FrameBlock { FrameParams frame; };
#endif
