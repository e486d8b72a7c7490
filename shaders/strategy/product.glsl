// Strategy "product": environment x BRDF product sampling over env-hier's pyramid (lib/product_sampling.glsl):
// Lo ~ L(wi) f(wi, wo) cos(theta_i) / p_product(wi).
#include "lib/product_sampling.glsl"
#include "lib/sample_record.glsl"

void prepareStrategy(Shading s) { productPrepare(s); }

vec3 estimateRadiance(SamplePoint p, Shading s) {
  vec2 u = samplePair(p, 0u);
  float pdf;
  vec3 radiance;
  vec3 wi = productSample(u, s, pdf, radiance);
  RECORD_DRAW(0u, kSampleTechniqueProduct, u, wi, pdf);
  RECORD_PRODUCT_NODE(0u);
  vec3 wiLocal = toLocal(s, wi);
  if (!(pdf > 0.0) || wiLocal.z <= 0.0) return vec3(0.0);
  vec3 weight = brdfEval(wiLocal, s.woLocal) * (wiLocal.z / pdf);
  RECORD_WEIGHT(0u, 1.0, weight, radiance);
  return radiance * weight;
}
