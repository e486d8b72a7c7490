// BRDF "lambert": f = albedo / pi. Parameter: albedo (color).
#include "lib/constants.glsl"

vec3 brdfEval(vec3 wi, vec3 wo) {
  return (wi.z > 0.0 && wo.z > 0.0) ? albedo * kInvPi : vec3(0.0);
}
