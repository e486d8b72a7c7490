// Strategy "single technique, environment": Lo ~ L(wi) f(wi, wo) cos(theta_i) / p_env(wi).
vec3 estimateRadiance(vec2 u, vec2 uPadding, Shading s) {
  float pdf;
  vec3 radiance;
  vec3 wi = envSample(u, s.n, pdf, radiance);
  vec3 wiLocal = toLocal(s, wi);
  // An early exit pays on SIMD hardware here: whether an env sample is below the horizon is coherent between
  // neighbouring pixels (the map's bright regions dominate), so whole groups of lanes skip brdfEval.
  if (!(pdf > 0.0) || wiLocal.z <= 0.0) return vec3(0.0);
  return radiance * brdfEval(wiLocal, s.woLocal) * (wiLocal.z / pdf);
}
