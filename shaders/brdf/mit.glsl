// BRDF of an MIT CSAIL anisotropic .dat file (as BRDF Explorer reads them; engine/io/mit_brdf.h): the bin
// floor(angle * n / range) of (theta_in, theta_out, phi_diff, phi_in), clamped, phi_in from the tangent,
// phi_diff = phi_out - phi_in folded into [0, pi] for half data; times the parameter scale. The bin counts come
// from the file (MIT_THETA_IN, MIT_THETA_OUT, MIT_PHI_DIFF, MIT_PHI_IN, MIT_HALF_DATA). GPU twin of
// evalMitBrdf in engine/io/mit_brdf.cpp.
#include "lib/table.glsl"
#include "lib/constants.glsl"

// Planar: all R, then all G, then all B; unmeasured bins zeroed at load.
IBLX_TABLE(mitRgb, 1);

const uint kMitBins = MIT_THETA_IN * MIT_THETA_OUT * MIT_PHI_DIFF * MIT_PHI_IN;

uint mitBin(float angle, float range, uint bins) {
  float x = angle / range * float(bins);
  return x > 0.0 ? min(uint(x), bins - 1u) : 0u;
}

float mitAzimuth(vec3 w) {
  float phi = (w.x == 0.0 && w.y == 0.0) ? 0.0 : atan(w.y, w.x);
  return phi < 0.0 ? phi + 2.0 * kPi : phi;
}

vec3 brdfEval(vec3 wi, vec3 wo) {
  if (wi.z <= 0.0 || wo.z <= 0.0) return vec3(0.0);
  float phiIn = mitAzimuth(wi);
  float phiDiff = mitAzimuth(wo) - phiIn;
  if (phiDiff < 0.0) phiDiff += 2.0 * kPi;
#if MIT_HALF_DATA
  if (phiDiff > kPi) phiDiff = 2.0 * kPi - phiDiff;  // mirror symmetry
  const float kPhiDiffRange = kPi;
#else
  const float kPhiDiffRange = 2.0 * kPi;
#endif
  uint iThetaIn = mitBin(atan(length(wi.xy), wi.z), 0.5 * kPi, MIT_THETA_IN);
  uint iThetaOut = mitBin(atan(length(wo.xy), wo.z), 0.5 * kPi, MIT_THETA_OUT);
  uint iPhiDiff = mitBin(phiDiff, kPhiDiffRange, MIT_PHI_DIFF);
  uint iPhiIn = mitBin(phiIn, 2.0 * kPi, MIT_PHI_IN);
  uint index = iPhiIn + MIT_PHI_IN * (iPhiDiff + MIT_PHI_DIFF * (iThetaOut + MIT_THETA_OUT * iThetaIn));
  return scale * vec3(tableFloat(mitRgb, index), tableFloat(mitRgb, index + kMitBins),
                      tableFloat(mitRgb, index + 2u * kMitBins));
}
