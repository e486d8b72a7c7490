// Strategy "single technique, environment": Lo ~ L(wi) f(wi, wo) cos(theta_i) / p_env(wi).
#include "lib/sample_record.glsl"

void prepareStrategy(Shading s) {}

vec3 estimateRadiance(SamplePoint p, Shading s) {
  vec2 u = samplePair(p, 0u);
  float pdf;
  vec3 radiance;
  vec3 wi = envSample(u, s.n, pdf, radiance);
  RECORD_DRAW(0u, kSampleTechniqueEnv, u, wi, pdf);
  vec3 wiLocal = toLocal(s, wi);
  // An early exit pays on SIMD hardware here: whether an env sample is below the horizon is coherent between
  // neighbouring pixels (the map's bright regions dominate), so whole groups of lanes skip brdfEval.
  if (!(pdf > 0.0) || wiLocal.z <= 0.0) return vec3(0.0);
  vec3 weight = brdfEval(wiLocal, s.woLocal) * (wiLocal.z / pdf);
  RECORD_WEIGHT(0u, 1.0, weight, radiance);
  return radiance * weight;
}
