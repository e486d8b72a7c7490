// Set 0, the frame: G-buffer, accumulation, environment radiance and row solid angles, kernel counters,
// and the push constants. Every kernel that renders the scene includes this.
#ifndef IBLX_LIB_FRAME_RESOURCES
#define IBLX_LIB_FRAME_RESOURCES
#include "shared/frame_params.h"

layout(std430, set = 0, binding = 0) readonly buffer GBufferData { GPixel gbuffer[]; };
layout(std430, set = 0, binding = 1) buffer AccumData { AccumPixel accum[]; };
// Linear RGB of every texel, top row first, 3 floats per texel (nearest-texel reconstruction, DESIGN §3).
layout(std430, set = 0, binding = 2) readonly buffer EnvRadianceData { float envRgb[]; };
// Per row (engine/sampling/latlong_texel.h envRowTable, computed in double): x = exact texel solid angle,
// y, z = the squared half-angle terms at the row's edges, w = 1 for rows in the lower half.
layout(std430, set = 0, binding = 3) readonly buffer EnvRowData { vec4 envRows[]; };
layout(std430, set = 0, binding = 4) buffer KernelStatsData { KernelStats stats; };

layout(push_constant) uniform FrameBlock { FrameParams frame; };
#endif
