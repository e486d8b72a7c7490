// Strategy "mis": one-sample multiple importance sampling of the env and BRDF techniques (Veach 1997, §9.2.4).
// The technique is chosen by u.x < c (c = frame.strategy.x, the env fraction) and u.x is rescaled, so each
// sample uses one 2D point. Estimate = w_i f L cos / (c_i p_i) with the balance or power (beta = 2) heuristic.
float misWeightTimesInvPdf(float chosen, float other, bool power) {
  // chosen = c_i p_i > 0, other = c_j p_j >= 0; returns w_i / (c_i p_i).
  if (!power) return 1.0 / (chosen + other);
  float r = other / chosen;
  return 1.0 / (chosen * (1.0 + r * r));
}

vec3 estimateRadiance(vec2 u, Shading s) {
  float c = frame.strategy.x;
  bool power = frame.strategy.y > 0.5;
  vec3 wi, wiLocal;
  float pEnv, pBrdf;
  bool envChosen = u.x < c;
  if (envChosen) {
    u.x = clamp(u.x / c, 0.0, kOneMinusEpsilon);
    wi = envSample(u, s.n, pEnv);
    wiLocal = toLocal(s, wi);
    if (!(pEnv > 0.0) || wiLocal.z <= 0.0) return vec3(0.0);
    pBrdf = brdfPdf(wiLocal, s.woLocal);
  } else {
    u.x = clamp((u.x - c) / (1.0 - c), 0.0, kOneMinusEpsilon);
    wiLocal = brdfSample(u, s.woLocal, pBrdf);
    if (!(pBrdf > 0.0) || wiLocal.z <= 0.0) return vec3(0.0);
    wi = normalize(toWorld(s, wiLocal));
    pEnv = envPdf(wi, s.n);
  }
  float chosen = envChosen ? c * pEnv : (1.0 - c) * pBrdf;
  float other = envChosen ? (1.0 - c) * pBrdf : c * pEnv;
  return envRadiance(wi) * brdfEval(wiLocal, s.woLocal) * (wiLocal.z * misWeightTimesInvPdf(chosen, other, power));
}
