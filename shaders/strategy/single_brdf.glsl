// Strategy "single technique, BRDF": Lo ~ L(wi) f(wi, wo) cos(theta_i) / p_brdf(wi).
#include "lib/sample_record.glsl"

void prepareStrategy(Shading s) {}

vec3 estimateRadiance(SamplePoint p, Shading s) {
  vec2 u = samplePair(p, 0u);
  float pdf;
  vec3 wiLocal = brdfSample(u, s.woLocal, pdf);
  RECORD_DRAW(0u, kSampleTechniqueBrdf, u, normalize(toWorld(s, wiLocal)), pdf);
  if (!(pdf > 0.0) || wiLocal.z <= 0.0) return vec3(0.0);
  vec3 wi = normalize(toWorld(s, wiLocal));
  vec3 radiance = envRadiance(wi);
  vec3 weight = brdfEval(wiLocal, s.woLocal) * (wiLocal.z / pdf);
  RECORD_WEIGHT(0u, 1.0, weight, radiance);
  return radiance * weight;
}
