// The integrator: one invocation per pixel adds frame.samplesPerPass estimates to the running mean and the
// running mean of squares (docs/DESIGN.md §6: means, not float32 sums, so precision does not decay with the count).
// Non-finite estimates are replaced by 0 and counted in stats.nonFiniteSamples, which must stay 0.
// Assembled with one part per role by engine/scene/kernel_prelude.cpp. With IBLX_RECORD_SAMPLES it
// integrates one pixel (frame.recordPixelX/Y) through this same code and stores every sample's record
// (lib/sample_record.glsl, engine/render/sample_recorder.h). With PRODUCT_TABLE_BUILD it only builds and
// stores the product strategy's per-pixel tables (engine/scene/kernel_prelude.h, IntegratorMode).
#include "lib/frame_resources.glsl"
#include "lib/latlong.glsl"
#include "lib/pixel_shading.glsl"
#include "lib/sample_record.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

void main() {
#ifdef IBLX_RECORD_SAMPLES
  if (gl_GlobalInvocationID.xy != uvec2(0u)) return;  // the host dispatches one group for the one pixel
  uvec2 pixel = uvec2(frame.recordPixelX, frame.recordPixelY);
#else
  uvec2 pixel = gl_GlobalInvocationID.xy;
#endif
  if (pixel.x >= frame.width || pixel.y >= frame.height) return;
  uint index = pixel.y * frame.width + pixel.x;
  GPixel g = gbuffer[index];
#ifdef PRODUCT_TABLE_BUILD
  // The product-table kernel (IntegratorMode::ProductTables): the object's pixels' tables, no sample. A
  // kernel of its own, since lavapipe runs a branch's body in every dispatch, taken or not.
  if (g.normal.w != 0.0) prepareStrategy(pixelShading(g));
#else
  if (g.normal.w == 0.0) {  // background: the environment seen in that direction, exact from the first pass
    vec3 radiance = envRadiance(normalize(worldToEnv(g.view.xyz)));
    accum[index].mean = vec4(radiance, 1.0);
    accum[index].meanSquare = vec4(radiance * radiance, 1.0);
    return;
  }
  Shading s = pixelShading(g);
  prepareStrategy(s);
  vec3 sum = vec3(0.0), sumSquares = vec3(0.0);
  uint nonFinite = 0u;
  for (uint k = 0u; k < frame.samplesPerPass; ++k) {
    RECORD_BEGIN();
    vec3 x = estimateRadiance(SamplePoint(pixel, frame.sampleOffset + k, frame.seed), s);
    bool finite = !(any(isnan(x)) || any(isinf(x)));
    if (!finite) {
      x = vec3(0.0);
      ++nonFinite;
    }
    RECORD_STORE(frame.sampleOffset + k, x, finite);
    sum += x;
    sumSquares += x * x;
  }
  if (nonFinite > 0u) atomicAdd(stats.nonFiniteSamples, nonFinite);
  float total = float(frame.sampleOffset + frame.samplesPerPass);
  // Member-wise: glslang 12 emits invalid SPIR-V for a ?: between a constructed and a buffer-loaded struct.
  vec3 mean = vec3(0.0), meanSquare = vec3(0.0);
  if (frame.sampleOffset != 0u) {
    mean = accum[index].mean.rgb;
    meanSquare = accum[index].meanSquare.rgb;
  }
  // mean_new = mean + (sum - S mean) / (n + S)
  mean += (sum - float(frame.samplesPerPass) * mean) / total;
  meanSquare += (sumSquares - float(frame.samplesPerPass) * meanSquare) / total;
  accum[index].mean = vec4(mean, 1.0);
  accum[index].meanSquare = vec4(meanSquare, 1.0);
#endif
}
