// Probe kernel for a .brdf file's own functions, without the guards of the generated brdfEval and of the
// isfunc technique: frame.quadrature.xyz = wo (local frame, N = +z, X = +x, Y = +y).
// Mode 0: sampleBRDF at u = probeIn.xy -> (wi, pdf) and its return value (the weight f cos / pdf).
// Mode 1: BRDF(probeIn.xyz, wo) as written (may be negative or non-finite if the file is wrong).
// Mode 2: pdfBRDF(probeIn.xyz, wo).
#include "lib/frame_resources.glsl"

// Defined by the generated part, which the prelude includes after this kernel.
vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y);
void iblxSetView(vec3 v);
#ifdef PROBE_HAS_ISFUNC
vec3 sampleBRDF(float u, float v, vec3 N, vec3 X, vec3 Y, out vec3 wi, out float pdf);
float pdfBRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y);
#endif

layout(local_size_x = 64) in;
layout(std430, set = 1, binding = 0) readonly buffer ProbeInput { vec4 probeIn[]; };
layout(std430, set = 1, binding = 1) writeonly buffer ProbeOutput { vec4 probeOut[]; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= frame.samplesPerPass) return;
  vec3 wo = normalize(frame.quadrature.xyz);
  const vec3 n = vec3(0.0, 0.0, 1.0), x = vec3(1.0, 0.0, 0.0), y = vec3(0.0, 1.0, 0.0);
  iblxSetView(wo);
  if (frame.probeMode == 0u) {
#ifdef PROBE_HAS_ISFUNC
    vec3 wi = vec3(0.0);
    float pdf = 0.0;
    vec3 weight = sampleBRDF(probeIn[i].x, probeIn[i].y, n, x, y, wi, pdf);
    probeOut[2u * i] = vec4(wi, pdf);
    probeOut[2u * i + 1u] = vec4(weight, 0.0);
#endif
  } else if (frame.probeMode == 1u) {
    probeOut[2u * i] = vec4(BRDF(normalize(probeIn[i].xyz), wo, n, x, y), 0.0);
  } else {
#ifdef PROBE_HAS_ISFUNC
    probeOut[2u * i] = vec4(pdfBRDF(normalize(probeIn[i].xyz), wo, n, x, y), 0.0, 0.0, 0.0);
#endif
  }
}
