// Strategy "single technique, environment": Lo ~ L(wi) f(wi, wo) cos(theta_i) / p_env(wi).
vec3 estimateRadiance(vec2 u, Shading s) {
  float pdf;
  vec3 wi = envSample(u, s.n, pdf);
  vec3 wiLocal = toLocal(s, wi);
  if (!(pdf > 0.0) || wiLocal.z <= 0.0) return vec3(0.0);
  return envRadiance(wi) * brdfEval(wiLocal, s.woLocal) * (wiLocal.z / pdf);
}
