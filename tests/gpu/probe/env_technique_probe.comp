// Probe kernel for env techniques (Falcor-style GPU test pairing): the host supplies u (mode 0) or directions
// (mode 1, in frame.probeMode); the probe writes envSample's direction and pdf plus envPdf of that direction, or
// envPdf of the given directions. frame.quadrature.xyz is the shading normal handed to the technique.
#include "lib/frame_resources.glsl"
#include "lib/latlong.glsl"

layout(local_size_x = 64) in;
layout(std430, set = 1, binding = 0) readonly buffer ProbeInput { vec4 probeIn[]; };
layout(std430, set = 1, binding = 1) writeonly buffer ProbeOutput { vec4 probeOut[]; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= frame.samplesPerPass) return;
  vec3 n = frame.quadrature.xyz;
  if (frame.probeMode == 0u) {
    float pdf;
    vec3 radiance;
    vec3 w = envSample(probeIn[i].xy, n, pdf, radiance);
    probeOut[2u * i] = vec4(w, pdf);
    probeOut[2u * i + 1u] = vec4(envPdf(w, n), 0.0, 0.0, 0.0);
  } else {
    probeOut[2u * i] = vec4(envPdf(normalize(probeIn[i].xyz), n), 0.0, 0.0, 0.0);
  }
}
