// Strategy "mis": multiple importance sampling of the env and BRDF techniques (Veach 1997, "Robust Monte Carlo
// Methods for Light Transport Simulation", ch. 9), with the balance or the power (beta = 2) heuristic.
//   Two-sample (default, §9.2.2 with n_env = n_brdf = 1): each sample draws one direction from each
//   technique, from its own 2D point (dimension pairs 0 and 1), and adds both weighted estimates:
//     Lo ~ sum_i w_i(x_i) f L cos(x_i) / p_i(x_i).
//   One-sample (MIS_ONE_SAMPLE, §9.2.4): the technique is chosen by u.x < c (c = frame.strategy.x, the env
//   fraction) and u.x is rescaled, so each sample uses one 2D point; Lo ~ w_i f L cos / (c_i p_i).
// Both directions are drawn and both pdfs evaluated in either mode; the one-sample estimator keeps one result.
#include "lib/mis_weights.glsl"
#include "lib/sample_record.glsl"

void prepareStrategy(Shading s) {}

vec3 estimateRadiance(SamplePoint p, Shading s) {
  bool power = frame.strategy.y > 0.5;
#ifdef MIS_ONE_SAMPLE
  float c = frame.strategy.x;
  vec2 u = samplePair(p, 0u);
  bool envChosen = u.x < c;
  // Straight-line code: on SIMD hardware (GPU warps, lavapipe lanes) a per-lane branch executes both sides
  // anyway, and this avoids the masking overhead.
  vec2 uEnv = vec2(c > 0.0 ? clamp(u.x / c, 0.0, kOneMinusEpsilon) : 0.0, u.y);
  vec2 uBrdf = vec2(c < 1.0 ? clamp((u.x - c) / (1.0 - c), 0.0, kOneMinusEpsilon) : 0.0, u.y);
  float shareEnv = c, shareBrdf = 1.0 - c;
#else
  vec2 uEnv = samplePair(p, 0u), uBrdf = samplePair(p, 1u);
  float shareEnv = 1.0, shareBrdf = 1.0;
#endif
  float pEnvE, pBrdfB;
  vec3 radianceE;
  vec3 wiE = envSample(uEnv, s.n, pEnvE, radianceE);
  vec3 wiLocalB = brdfSample(uBrdf, s.woLocal, pBrdfB);
  vec3 wiB = normalize(toWorld(s, wiLocalB));
  vec3 wiLocalE = toLocal(s, wiE);
  float pBrdfE = brdfPdf(wiLocalE, s.woLocal);  // the other technique's density at each direction
  float pEnvB = envPdf(wiB, s.n);
  vec3 radianceB = envRadiance(wiB);
#ifdef MIS_ONE_SAMPLE
  vec3 wiLocal = envChosen ? wiLocalE : wiLocalB;
  float pEnv = envChosen ? pEnvE : pEnvB;
  float pBrdf = envChosen ? pBrdfE : pBrdfB;
  vec3 radiance = envChosen ? radianceE : radianceB;
  float chosen = envChosen ? shareEnv * pEnv : shareBrdf * pBrdf;
  float other = envChosen ? shareBrdf * pBrdf : shareEnv * pEnv;
  RECORD_DRAW(0u, envChosen ? kSampleTechniqueEnv : kSampleTechniqueBrdf, envChosen ? uEnv : uBrdf,
              envChosen ? wiE : wiB, envChosen ? pEnv : pBrdf);
  float weightOverPdf;
  vec3 weight = misWeight(wiLocal, s, chosen, other, power, weightOverPdf);
  if (!misContributes(wiLocal, chosen)) return vec3(0.0);
  RECORD_WEIGHT(0u, weightOverPdf * chosen, weight, radiance);
  return radiance * weight;
#else
  float weightOverPdfE, weightOverPdfB;
  vec3 weightE = misWeight(wiLocalE, s, shareEnv * pEnvE, shareBrdf * pBrdfE, power, weightOverPdfE);
  vec3 weightB = misWeight(wiLocalB, s, shareBrdf * pBrdfB, shareEnv * pEnvB, power, weightOverPdfB);
  RECORD_DRAW(0u, kSampleTechniqueEnv, uEnv, wiE, pEnvE);
  if (misContributes(wiLocalE, shareEnv * pEnvE)) RECORD_WEIGHT(0u, weightOverPdfE * pEnvE, weightE, radianceE);
  RECORD_DRAW(1u, kSampleTechniqueBrdf, uBrdf, wiB, pBrdfB);
  if (misContributes(wiLocalB, shareBrdf * pBrdfB)) RECORD_WEIGHT(1u, weightOverPdfB * pBrdfB, weightB, radianceB);
  return radianceE * weightE + radianceB * weightB;
#endif
}
