// Set 0, the frame: G-buffer, accumulation, environment radiance and row solid angles, kernel counters,
// and the push constants. Every kernel that renders the scene includes this.
#ifndef IBLX_LIB_FRAME_RESOURCES
#define IBLX_LIB_FRAME_RESOURCES
#include "lib/table.glsl"
#include "shared/frame_params.h"

layout(std430, set = 0, binding = 0) readonly buffer GBufferData { GPixel gbuffer[]; };
layout(std430, set = 0, binding = 1) buffer AccumData { AccumPixel accum[]; };
// Linear RGB of every texel, top row first, 3 floats per texel (nearest-texel reconstruction, docs/DESIGN.md §3).
// A map larger than one buffer may be (maxStorageBufferRange, maxTexelBufferElements) is split into
// ENV_RADIANCE_CHUNKS runs of ENV_TEXELS_PER_CHUNK texels at bindings 2, 5, 6, 7 (engine/render/scene_gpu.cpp
// uploadScene); read it through envTexelRadiance (lib/latlong.glsl).
#ifndef ENV_RADIANCE_CHUNKS
#define ENV_RADIANCE_CHUNKS 1
#endif
IBLX_TABLE(envRgb, 1);
#if ENV_RADIANCE_CHUNKS > 1
IBLX_TABLE(envRgb1, 1);
#endif
#if ENV_RADIANCE_CHUNKS > 2
IBLX_TABLE(envRgb2, 1);
#endif
#if ENV_RADIANCE_CHUNKS > 3
IBLX_TABLE(envRgb3, 1);
#endif
// Per row (engine/io/latlong_texel.h envRowTable, computed in double): x = exact texel solid angle,
// y, z = the squared half-angle terms at the row's edges, w = 1 for rows in the lower half.
IBLX_TABLE(envRows, 4);
layout(std430, set = 0, binding = 4) buffer KernelStatsData { KernelStats stats; };

layout(push_constant) uniform FrameBlock { FrameParams frame; };
#endif
