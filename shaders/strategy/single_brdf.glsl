// Strategy "single technique, BRDF": Lo ~ L(wi) f(wi, wo) cos(theta_i) / p_brdf(wi).
vec3 estimateRadiance(vec2 u, vec2 uPadding, Shading s) {
  float pdf;
  vec3 wiLocal = brdfSample(u, s.woLocal, pdf);
  if (!(pdf > 0.0) || wiLocal.z <= 0.0) return vec3(0.0);
  vec3 wi = normalize(toWorld(s, wiLocal));
  return envRadiance(wi) * brdfEval(wiLocal, s.woLocal) * (wiLocal.z / pdf);
}
