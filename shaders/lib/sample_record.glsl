// Sample recording (`iblx samples`, the viewer's sample overlay): with IBLX_RECORD_SAMPLES defined,
// strategies describe each direction they draw and integrate.comp stores that for the one pixel it integrates.
// Without the define every macro below is empty, so the integrator that renders images is unchanged.
//
// A sample draws SAMPLE_RECORD_DRAWS directions (the host's ResolvedMethod::drawsPerSample: 2 for two-sample
// MIS, else 1), each recorded in its own slot d. A strategy calls, on the path of every sample:
//   RECORD_DRAW(d, technique, u, wi, pdf)         which technique drew wi (environment frame) from the 2D
//                                                 point u, and its pdf; resets slot d's contribution to 0 (a
//                                                 draw that exits early contributes nothing); a later call
//                                                 for the same slot replaces it (ris keeps the last taken)
//   RECORD_WEIGHT(d, misWeight, weight, radiance) slot d's contribution is radiance * weight
//   RECORD_SCALE_WEIGHT(d, factor)                slot d's weight *= factor, for a factor known only later (ris)
//   RECORD_PRODUCT_NODE(d)                        the node the product table chose for slot d's draw
//                                                 (lib/product_sampling.glsl's productSample sets it)
#ifndef IBLX_LIB_SAMPLE_RECORD
#define IBLX_LIB_SAMPLE_RECORD
#include "lib/frame_resources.glsl"

#ifdef IBLX_RECORD_SAMPLES
// After set 0's frame buffers (engine/scene/kernel_prelude.h kSampleRecordBinding).
layout(std430, set = 0, binding = SAMPLE_RECORD_BINDING) writeonly buffer SampleRecordData {
  SampleRecord sampleRecords[];
};

SampleRecord gSampleRecords[SAMPLE_RECORD_DRAWS];

void recordBegin() {
  for (uint d = 0u; d < SAMPLE_RECORD_DRAWS; ++d)
    gSampleRecords[d] =
        SampleRecord(vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0), 0.0, 0.0, 0u, kSampleTechniqueNone, 0u, 0u, 0u,
                     0.0, vec4(0.0));
}

void recordDraw(uint d, uint technique, vec2 u, vec3 wi, float pdf) {
  gSampleRecords[d].technique = technique;
  gSampleRecords[d].direction = vec4(wi, pdf);
  gSampleRecords[d].weight = vec4(0.0);
  gSampleRecords[d].radiance = vec4(0.0);
  gSampleRecords[d].pointX = u.x;
  gSampleRecords[d].pointY = u.y;
  gSampleRecords[d].productColumns = 0u;
}

// The product table's choice for the draw in slot d (after its RECORD_DRAW): node `node` of a columns x rows
// table, its probability, and its rectangle on the map (all 0 when the node is no block of texels).
void recordProductNode(uint d, uint node, uint columns, uint rows, float probability, vec4 nodeUv) {
  gSampleRecords[d].productNode = node;
  gSampleRecords[d].productColumns = columns;
  gSampleRecords[d].productRows = rows;
  gSampleRecords[d].productNodeProbability = probability;
  gSampleRecords[d].productNodeUv = nodeUv;
}

void recordWeight(uint d, float misWeight, vec3 weight, vec3 radiance) {
  gSampleRecords[d].weight = vec4(weight, misWeight);
  gSampleRecords[d].radiance = vec4(radiance, 0.0);
}

// Stores the records of sample `sampleIndex` at their place in the pass. x is the estimate the integrator
// accumulates (0 when it was non-finite: finite is false). With one draw per sample the record holds x itself;
// with several, each holds its own contribution, so the records of a sample sum to x.
void recordStore(uint sampleIndex, vec3 x, bool finite) {
  uint slot = sampleIndex - frame.recordFirstSample;
  if (slot >= frame.recordCapacity) return;  // the host sizes the buffer for the pass; guard all the same
  for (uint d = 0u; d < SAMPLE_RECORD_DRAWS; ++d) {
    vec3 contribution = gSampleRecords[d].radiance.rgb * gSampleRecords[d].weight.rgb;
    gSampleRecords[d].estimate = vec4(SAMPLE_RECORD_DRAWS == 1u ? x : (finite ? contribution : vec3(0.0)), 0.0);
    gSampleRecords[d].sampleIndex = sampleIndex;
    sampleRecords[slot * SAMPLE_RECORD_DRAWS + d] = gSampleRecords[d];
  }
}

#define RECORD_BEGIN() recordBegin()
#define RECORD_DRAW(d, technique, u, wi, pdf) recordDraw(d, technique, u, wi, pdf)
#define RECORD_WEIGHT(d, misWeight, weight, radiance) recordWeight(d, misWeight, weight, radiance)
#define RECORD_SCALE_WEIGHT(d, factor) gSampleRecords[d].weight.rgb *= (factor)
#define RECORD_STORE(sampleIndex, x, finite) recordStore(sampleIndex, x, finite)
#define RECORD_PRODUCT_NODE(d)                                                                           \
  if (gProductChosen.columns > 0u)                                                                       \
  recordProductNode(d, gProductChosen.node, gProductChosen.columns, gProductChosen.rows,                 \
                    gProductChosen.probability, gProductChosen.nodeUv)
#else
#define RECORD_BEGIN()
#define RECORD_DRAW(d, technique, u, wi, pdf)
#define RECORD_WEIGHT(d, misWeight, weight, radiance)
#define RECORD_SCALE_WEIGHT(d, factor)
#define RECORD_STORE(sampleIndex, x, finite)
#define RECORD_PRODUCT_NODE(d)
#endif
#endif
