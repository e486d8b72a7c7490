// Probe kernel for BRDF techniques: as env_sampler_probe.comp, with frame.quadrature.xyz = wo (local frame).
// Mode 2 evaluates brdfEval(wi, wo) * cos for the given directions (for white-furnace albedo checks).
#include "lib/frame_resources.glsl"

layout(local_size_x = 64) in;
layout(std430, set = 1, binding = 0) readonly buffer ProbeInput { vec4 probeIn[]; };
layout(std430, set = 1, binding = 1) writeonly buffer ProbeOutput { vec4 probeOut[]; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= frame.samplesPerPass) return;
  vec3 wo = normalize(frame.quadrature.xyz);
  if (frame.probeMode == 0u) {
    float pdf;
    vec3 wi = brdfSample(probeIn[i].xy, wo, pdf);
    probeOut[2u * i] = vec4(wi, pdf);
    probeOut[2u * i + 1u] = vec4(brdfPdf(wi, wo), 0.0, 0.0, 0.0);
  } else if (frame.probeMode == 1u) {
    probeOut[2u * i] = vec4(brdfPdf(normalize(probeIn[i].xyz), wo), 0.0, 0.0, 0.0);
  } else {
    vec3 wi = normalize(probeIn[i].xyz);
    probeOut[2u * i] = vec4(brdfEval(wi, wo) * max(wi.z, 0.0), 0.0);
  }
}
