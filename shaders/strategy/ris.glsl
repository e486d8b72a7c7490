// Strategy "ris": resampled importance sampling (Talbot, Cline & Egbert 2005, "Importance Resampling for Global
// Illumination", eq. 2-3) as a product sampler: RIS_CANDIDATES = M candidates x_k from the env technique,
// resampled by f cos, i.e. target p^ = p_env mean(f) cos and weights w_k = p^(x_k) / p_env(x_k) = mean(f) cos.
// One candidate y is kept with probability w_y / sum(w), and
//   Lo ~ L(y) f(y) cos(y) / p^(y) * sum(w) / M = (L(y) / p_env(y)) (f(y) / mean(f(y))) sum(w) / M.
// For large M the kept y is distributed like p_env f cos (the product of the map and the lobe).
// Unbiased whenever each candidate is marginally distributed by p_env (E = (1/M) sum_k E[L f cos / p_env]), so
// the candidates can share one sequence point: x_k comes from u_k = fract(u + k g), g the R2 lattice generator
// (Roberts 2018), which keeps them stratified against each other. The choice is a streaming weighted
// reservoir (Chao 1982): candidate k replaces the kept one with probability w_k / sum_{j<=k} w_j, each decision
// with its own uniform hashed from uPadding (independent of u), so no per-candidate arrays are needed.
#include "lib/hash.glsl"
#include "lib/sample_record.glsl"

const vec2 kRisLattice = vec2(0.7548776662466927, 0.5698402909980532);  // (1/phi2, 1/phi2^2), phi2^3 = phi2 + 1

vec3 estimateRadiance(vec2 u, vec2 uPadding, Shading s) {
  const uint candidates = RIS_CANDIDATES;  // fixed by the method: the loop unrolls
  uvec2 key = uvec2(floatBitsToUint(uPadding.x), floatBitsToUint(uPadding.y));
  uvec4 decisions = uvec4(0u);
  float weightSum = 0.0;
  vec3 chosen = vec3(0.0);  // L / p_env * f / mean(f) of the kept candidate
  for (uint k = 0u; k < candidates; ++k) {
    vec2 uk = min(fract(u + float(k) * kRisLattice), vec2(kOneMinusEpsilon));
    float pdf;
    vec3 radiance;
    vec3 wi = envSample(uk, s.n, pdf, radiance);
    vec3 wiLocal = toLocal(s, wi);
    bool valid = pdf > 0.0 && wiLocal.z > 0.0;
    vec3 f = valid ? brdfEval(wiLocal, s.woLocal) : vec3(0.0);
    float meanF = (f.r + f.g + f.b) / 3.0;
    float weight = meanF > 0.0 ? meanF * wiLocal.z : 0.0;
    weightSum += weight;
    if ((k & 3u) == 0u) decisions = pcg4d(uvec4(key, k, 0x52495321u));  // four decisions per hash
    float r = uintToUnitFloat(decisions[k & 3u]);
    bool take = weight > 0.0 && r * weightSum < weight;
    chosen = take ? radiance / pdf * (f / meanF) : chosen;
#ifdef IBLX_RECORD_SAMPLES
    if (take) {  // the kept candidate is the sample; its weight gets the factor sum(w) / M below
      RECORD_DRAW(kSampleTechniqueEnv, wi, pdf);
      RECORD_WEIGHT(1.0, f / (meanF * pdf), radiance);
    }
#endif
  }
  RECORD_SCALE_WEIGHT(weightSum / float(candidates));
  return chosen * (weightSum / float(candidates));
}
