// Strategy "mis": one-sample multiple importance sampling of the env and BRDF techniques (Veach 1997, §9.2.4).
// The technique is chosen by u.x < c (c = frame.strategy.x, the env fraction) and u.x is rescaled, so each
// sample uses one 2D point. Estimate = w_i f L cos / (c_i p_i) with the balance or power (beta = 2) heuristic.
#include "lib/sample_record.glsl"

float misWeightTimesInvPdf(float chosen, float other, bool power) {
  // chosen = c_i p_i, other = c_j p_j >= 0; returns w_i / (c_i p_i), 0 when chosen is 0.
  if (!(chosen > 0.0)) return 0.0;
  float r = other / chosen;
  return power ? 1.0 / (chosen * (1.0 + r * r)) : 1.0 / (chosen + other);
}

vec3 estimateRadiance(vec2 u, vec2 uPadding, Shading s) {
  float c = frame.strategy.x;
  bool power = frame.strategy.y > 0.5;
  bool envChosen = u.x < c;
  // Both techniques are evaluated and one result is kept: on SIMD hardware (GPU warps, lavapipe lanes) a
  // per-lane branch executes both sides anyway, and straight-line code avoids the masking overhead.
  vec2 uEnv = vec2(c > 0.0 ? clamp(u.x / c, 0.0, kOneMinusEpsilon) : 0.0, u.y);
  vec2 uBrdf = vec2(c < 1.0 ? clamp((u.x - c) / (1.0 - c), 0.0, kOneMinusEpsilon) : 0.0, u.y);
  float pEnvE, pBrdfB;
  vec3 radianceE;
  vec3 wiE = envSample(uEnv, s.n, pEnvE, radianceE);
  vec3 wiLocalB = brdfSample(uBrdf, s.woLocal, pBrdfB);
  vec3 wiB = normalize(toWorld(s, wiLocalB));
  vec3 wiLocalE = toLocal(s, wiE);
  float pBrdfE = brdfPdf(wiLocalE, s.woLocal);  // the other technique's density at each sample
  float pEnvB = envPdf(wiB, s.n);
  vec3 radianceB = envRadiance(wiB);
  vec3 wiLocal = envChosen ? wiLocalE : wiLocalB;
  float pEnv = envChosen ? pEnvE : pEnvB;
  float pBrdf = envChosen ? pBrdfE : pBrdfB;
  vec3 radiance = envChosen ? radianceE : radianceB;
  float chosen = envChosen ? c * pEnv : (1.0 - c) * pBrdf;
  float other = envChosen ? (1.0 - c) * pBrdf : c * pEnv;
  RECORD_DRAW(envChosen ? kSampleTechniqueEnv : kSampleTechniqueBrdf, envChosen ? wiE : wiB,
              envChosen ? pEnv : pBrdf);
  if (!(chosen > 0.0) || wiLocal.z <= 0.0) return vec3(0.0);
  float weightOverPdf = misWeightTimesInvPdf(chosen, other, power);
  vec3 weight = brdfEval(wiLocal, s.woLocal) * (wiLocal.z * weightOverPdf);
  RECORD_WEIGHT(weightOverPdf * chosen, weight, radiance);
  return radiance * weight;
}
