// Strategy "ris": resampled importance sampling (Talbot, Cline & Egbert 2005, "Importance Resampling for Global
// Illumination", eq. 2-3) as a product sampler: RIS_CANDIDATES = M candidates x_k from the env technique,
// resampled by f cos, i.e. target p^ = p_env mean(f) cos and weights w_k = p^(x_k) / p_env(x_k) = mean(f) cos.
// One candidate y is kept with probability w_y / sum(w), and
//   Lo ~ L(y) f(y) cos(y) / p^(y) * sum(w) / M = (L(y) / p_env(y)) (f(y) / mean(f(y))) sum(w) / M.
// For large M the kept y is distributed like p_env f cos (the product of the map and the lobe).
// Candidate k is drawn from its own dimension pair k, so under sobol each candidate alone is a (0,2)-sequence
// over the pixel's samples. The choice is a streaming weighted reservoir (Chao 1982): candidate k replaces the
// kept one with probability w_k / sum_{j<=k} w_j, each decision with its own uniform from pairs M, M+1, ...
// (two decisions per pair), so no per-candidate arrays are needed.
#include "lib/sample_record.glsl"

void prepareStrategy(Shading s) {}

vec3 estimateRadiance(SamplePoint p, Shading s) {
  const uint candidates = RIS_CANDIDATES;  // fixed by the method: the loop unrolls
  vec2 decisions = vec2(0.0);
  float weightSum = 0.0;
  vec3 chosen = vec3(0.0);  // L / p_env * f / mean(f) of the kept candidate
  for (uint k = 0u; k < candidates; ++k) {
    vec2 uk = samplePair(p, k);
    float pdf;
    vec3 radiance;
    vec3 wi = envSample(uk, s.n, pdf, radiance);
    vec3 wiLocal = toLocal(s, wi);
    bool valid = pdf > 0.0 && wiLocal.z > 0.0;
    vec3 f = valid ? brdfEval(wiLocal, s.woLocal) : vec3(0.0);
    float meanF = (f.r + f.g + f.b) / 3.0;
    float weight = meanF > 0.0 ? meanF * wiLocal.z : 0.0;
    weightSum += weight;
    if ((k & 1u) == 0u) decisions = samplePair(p, candidates + (k >> 1u));
    float r = (k & 1u) == 0u ? decisions.x : decisions.y;
    bool take = weight > 0.0 && r * weightSum < weight;
    chosen = take ? radiance / pdf * (f / meanF) : chosen;
#ifdef IBLX_RECORD_SAMPLES
    if (take) {  // the kept candidate is the sample; its weight gets the factor sum(w) / M below
      RECORD_DRAW(0u, kSampleTechniqueEnv, uk, wi, pdf);
      RECORD_WEIGHT(0u, 1.0, f / (meanF * pdf), radiance);
    }
#endif
  }
  RECORD_SCALE_WEIGHT(0u, weightSum / float(candidates));
  return chosen * (weightSum / float(candidates));
}
