// BRDF "merl": a MERL measured isotropic table (engine/io/merl.h), looked up at the nearest-lower bin exactly
// as MERL's reference code does (Matusik et al. 2003; BRDF Explorer's BRDFMeasuredMERL). Invalid bins were zeroed at load.
// GPU twin of evalMerl in engine/io/merl.cpp.
#include "lib/table.glsl"
#include "lib/constants.glsl"

// Planar like the file: all R, then all G, then all B; scales applied, in 1/sr.
IBLX_TABLE(merlRgb, 1);

const uint kMerlBins = 1458000u;

vec3 brdfEval(vec3 wi, vec3 wo) {
  if (wi.z <= 0.0 || wo.z <= 0.0) return vec3(0.0);
  vec3 h = normalize(wi + wo);
  // theta_h from atan, not acos(h.z): MERL's first theta_h bins end at 1.9e-4 rad, where cos is 1 in float.
  float sinThetaH = length(h.xy), cosThetaH = h.z;
  float thetaH = atan(sinThetaH, cosThetaH);
  // The difference vector: wi rotated by -phi_h about the normal, then by -theta_h about the bitangent.
  vec2 azimuth = sinThetaH > 0.0 ? h.xy / sinThetaH : vec2(1.0, 0.0);  // (cos phi_h, sin phi_h)
  vec3 r = vec3(wi.x * azimuth.x + wi.y * azimuth.y, -wi.x * azimuth.y + wi.y * azimuth.x, wi.z);
  vec3 d = vec3(r.x * cosThetaH - r.z * sinThetaH, r.y, r.x * sinThetaH + r.z * cosThetaH);
  float thetaD = atan(length(d.xy), d.z);
  float phiD = (d.x == 0.0 && d.y == 0.0) ? 0.0 : atan(d.y, d.x);
  if (phiD < 0.0) phiD += kPi;  // reciprocity: phi_d and phi_d + pi are the same measurement
  if (phiD >= kPi) phiD = 0.0;  // atan gave exactly pi: the same direction as 0
  int iThetaH = thetaH > 0.0 ? clamp(int(sqrt(thetaH / (0.5 * kPi)) * 90.0), 0, 89) : 0;
  int iThetaD = clamp(int(thetaD / (0.5 * kPi) * 90.0), 0, 89);
  int iPhiD = clamp(int(phiD / kPi * 180.0), 0, 179);
  uint bin = uint(iPhiD + 180 * (iThetaD + 90 * iThetaH));
  return vec3(tableFloat(merlRgb, bin), tableFloat(merlRgb, bin + kMerlBins),
              tableFloat(merlRgb, bin + 2u * kMerlBins));
}
