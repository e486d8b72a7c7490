// Structs that cross the host/GPU line, compiled by both C++ and glslang (docs/DESIGN.md §2).
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

// One accumulation entry per pixel (set 0, binding 1): running means over all samples so far (docs/DESIGN.md §6).
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
  // Sample recording (integrate.comp compiled with IBLX_RECORD_SAMPLES): the one pixel integrated, the first
  // sample index of the pass (record i holds sample recordFirstSample + i) and the record buffer's length.
  uint recordPixelX;
  uint recordPixelY;
  uint recordFirstSample;
  uint recordCapacity;
};

// SampleRecord::technique: the role of the technique that drew the sample. The host maps roles to the
// method's technique names, so no technique needs a number of its own.
const uint kSampleTechniqueNone = 0u;  // no sample drawn (ris: no candidate kept); the record is all zero
const uint kSampleTechniqueEnv = 1u;
const uint kSampleTechniqueBrdf = 2u;
const uint kSampleTechniqueProduct = 3u;  // the product strategies' own technique (over the env technique)

// One sample of the recorded pixel (set 0, binding 8 of the recording integrator; lib/sample_record.glsl).
struct SampleRecord {
  vec4 direction;  // xyz: the sampled direction (environment frame); w: pdf of the technique that drew it,
                   // solid angle
  vec4 weight;     // rgb: contribution weight, estimate = radiance * weight (f cos / pdf times the MIS
                   // weight, over the technique's share of samples); a: MIS weight (1: single technique, ris)
  vec4 radiance;   // rgb: the environment radiance the estimate used (0 when the sample contributes nothing)
  vec4 estimate;   // rgb: the estimate the integrator accumulated (after its NaN/Inf guard); a: unused
  float pointX;    // the sequence's 2D point u
  float pointY;
  uint sampleIndex;  // in the pixel's sequence
  uint technique;    // kSampleTechnique*
  // Product draws (kSampleTechniqueProduct): the node the per-pixel table chose, row-major in a table of
  // productColumns x productRows nodes, and its probability P(node); productColumns is 0 for other draws.
  uint productNode;
  uint productColumns;
  uint productRows;
  float productNodeProbability;
  // The chosen node on the lat-long map (u0, v0, u1, v1) when nodes are blocks of texels (`product`,
  // `product-mis`); all 0 when they are cells of a warp's unit square, whose images are not rectangles.
  vec4 productNodeUv;
};

#ifdef __cplusplus
}  // namespace iblx::gpu
#endif

#endif
