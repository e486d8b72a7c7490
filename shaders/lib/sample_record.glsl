// Sample recording (`iblx samples`, the viewer's sample overlay): with IBLX_RECORD_SAMPLES defined,
// strategies describe each sample they draw and integrate.comp stores that for the one pixel it integrates.
// Without the define every macro below is empty, so the integrator that renders images is unchanged.
//
// A strategy calls, on the path of every sample:
//   RECORD_DRAW(technique, wi, pdf)            which technique drew wi (environment frame) and its pdf;
//                                              resets the contribution to 0 (a sample that exits early
//                                              contributes nothing)
//   RECORD_WEIGHT(misWeight, weight, radiance) the contribution: the strategy returns radiance * weight
//   RECORD_SCALE_WEIGHT(factor)                weight *= factor, for a factor known only later (ris)
#ifndef IBLX_LIB_SAMPLE_RECORD
#define IBLX_LIB_SAMPLE_RECORD
#include "lib/frame_resources.glsl"

#ifdef IBLX_RECORD_SAMPLES
// After set 0's frame buffers (engine/render/kernel_assembly.h kSampleRecordBinding).
layout(std430, set = 0, binding = SAMPLE_RECORD_BINDING) writeonly buffer SampleRecordData {
  SampleRecord sampleRecords[];
};

SampleRecord gSampleRecord;

void recordBegin() {
  gSampleRecord =
      SampleRecord(vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0), 0.0, 0.0, 0u, kSampleTechniqueNone);
}

void recordDraw(uint technique, vec3 wi, float pdf) {
  gSampleRecord.technique = technique;
  gSampleRecord.direction = vec4(wi, pdf);
  gSampleRecord.weight = vec4(0.0);
  gSampleRecord.radiance = vec4(0.0);
}

void recordWeight(float misWeight, vec3 weight, vec3 radiance) {
  gSampleRecord.weight = vec4(weight, misWeight);
  gSampleRecord.radiance = vec4(radiance, 0.0);
}

// Stores the record of sample `sampleIndex` (u: its sequence point, x: the estimate accumulated) at its place
// in the pass.
void recordStore(uint sampleIndex, vec2 u, vec3 x) {
  uint slot = sampleIndex - frame.recordFirstSample;
  if (slot >= frame.recordCapacity) return;  // the host sizes the buffer for the pass; guard all the same
  gSampleRecord.estimate = vec4(x, 0.0);
  gSampleRecord.pointX = u.x;
  gSampleRecord.pointY = u.y;
  gSampleRecord.sampleIndex = sampleIndex;
  sampleRecords[slot] = gSampleRecord;
}

#define RECORD_BEGIN() recordBegin()
#define RECORD_DRAW(technique, wi, pdf) recordDraw(technique, wi, pdf)
#define RECORD_WEIGHT(misWeight, weight, radiance) recordWeight(misWeight, weight, radiance)
#define RECORD_SCALE_WEIGHT(factor) gSampleRecord.weight.rgb *= (factor)
#define RECORD_STORE(sampleIndex, u, x) recordStore(sampleIndex, u, x)
#else
#define RECORD_BEGIN()
#define RECORD_DRAW(technique, wi, pdf)
#define RECORD_WEIGHT(misWeight, weight, radiance)
#define RECORD_SCALE_WEIGHT(factor)
#define RECORD_STORE(sampleIndex, u, x)
#endif
#endif
