// Probe kernel for env-ot's inverse (shaders/lib/env_ot_inverse.glsl, a part after the env-ot part: the
// prelude includes the parts after the kernel, so it declares the library's functions), with
// envOtProductTechniqueData's tables: per input direction (mode 1), its preimage through the map's pieces
// (xy, z = found) and the branch densities (w = q_map), then its preimage through the sun row (xy, z = found)
// and w = q_sun.
#include "lib/frame_resources.glsl"
#include "lib/latlong.glsl"

void envOtPreimages(vec3 wi, ivec2 texel, out vec2 uMap, out bool hasMap, out vec2 uSun, out bool hasSun);
vec2 envOtBranchPdfs(ivec2 texel);

layout(local_size_x = 64) in;
layout(std430, set = 1, binding = 0) readonly buffer ProbeInput { vec4 probeIn[]; };
layout(std430, set = 1, binding = 1) writeonly buffer ProbeOutput { vec4 probeOut[]; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= frame.samplesPerPass) return;
  vec3 w = normalize(probeIn[i].xyz);
  ivec2 texel = directionToTexel(w);
  vec2 uMap, uSun;
  bool hasMap, hasSun;
  envOtPreimages(w, texel, uMap, hasMap, uSun, hasSun);
  vec2 q = envOtBranchPdfs(texel);
  probeOut[2u * i] = vec4(uMap, hasMap ? 1.0 : 0.0, q.x);
  probeOut[2u * i + 1u] = vec4(uSun, hasSun ? 1.0 : 0.0, q.y);
}
