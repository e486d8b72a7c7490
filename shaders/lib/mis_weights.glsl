// Multiple importance sampling weights (Veach 1997, "Robust Monte Carlo Methods for Light Transport
// Simulation", §9.2): the balance and power (beta = 2) heuristics, shared by the MIS strategies.
#ifndef IBLX_LIB_MIS_WEIGHTS
#define IBLX_LIB_MIS_WEIGHTS
#include "lib/shading.glsl"

// w_i / (n_i p_i) for chosen = n_i p_i and other = n_j p_j >= 0 (n: the technique's share of samples); 0 when
// chosen is 0.
float misWeightTimesInvPdf(float chosen, float other, bool power) {
  if (!(chosen > 0.0)) return 0.0;
  float r = other / chosen;
  return power ? 1.0 / (chosen * (1.0 + r * r)) : 1.0 / (chosen + other);
}

// Whether a direction drawn with chosen = n_i p_i contributes: a positive density, above the horizon.
bool misContributes(vec3 wiLocal, float chosen) { return chosen > 0.0 && wiLocal.z > 0.0; }

// f cos w / (n p) of a contributing direction wiLocal drawn with chosen = n_i p_i: the weight its radiance is
// multiplied by; 0 for one that does not contribute.
vec3 misWeight(vec3 wiLocal, Shading s, float chosen, float other, bool power, out float weightOverPdf) {
  weightOverPdf = misWeightTimesInvPdf(chosen, other, power);
  if (!misContributes(wiLocal, chosen)) return vec3(0.0);
  return brdfEval(wiLocal, s.woLocal) * (wiLocal.z * weightOverPdf);
}
#endif
