// BRDF technique "isfunc": the file's own sampling routine, a .brdf file's ::begin isFunc section or an ALTA
// function file's closed-form lobes (engine/scene/alta_func_brdf.h), with iblx's contract
// (engine/scene/analytic_brdf.h): sampleBRDF draws wi with its exact solid-angle density, pdfBRDF gives that
// density for any wi, and the view direction reaches both through the global iblxV. The routine's return
// value (its weight f cos / pdf) is not used: the strategy computes f cos / pdf itself. A pdf that is not
// positive and finite, or a direction that is not finite, drops the sample (pdf 0).
const vec3 kIsFuncN = vec3(0.0, 0.0, 1.0), kIsFuncX = vec3(1.0, 0.0, 0.0), kIsFuncY = vec3(0.0, 1.0, 0.0);

bool isFuncFinite(vec3 v) { return !any(isnan(v)) && !any(isinf(v)); }

vec3 brdfSample(vec2 u, vec3 wo, out float pdf) {
  iblxV = wo;
  vec3 wi = vec3(0.0, 0.0, 1.0);
  float density = 0.0;
  sampleBRDF(u.x, u.y, kIsFuncN, kIsFuncX, kIsFuncY, wi, density);
  float len = length(wi);
  bool valid = density > 0.0 && density <= 3.0e38 && isFuncFinite(wi) && len > 0.0;
  pdf = valid ? density : 0.0;
  return valid ? wi / len : vec3(0.0, 0.0, 1.0);
}

float brdfPdf(vec3 wi, vec3 wo) {
  iblxV = wo;
  float density = pdfBRDF(wi, wo, kIsFuncN, kIsFuncX, kIsFuncY);
  return density > 0.0 && density <= 3.0e38 ? density : 0.0;
}
