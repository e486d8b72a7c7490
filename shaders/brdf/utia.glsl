// BRDF of a UTIA .bin file (Filip & Vávra 2014; engine/io/utia.h): quadrilinear lookup over (theta_i, phi_i,
// theta_v, phi_v), theta every 15 deg from 0 to 75 (clamped above), phi every 7.5 deg (wrapping), azimuths in
// the tangent frame; then the file's convention, f = scale * decode(prescale * v) (parameters prescale, srgb
// and scale). GPU twin of evalUtia in engine/io/utia.cpp.
#include "lib/table.glsl"
#include "lib/constants.glsl"

// Planar like the file: all R, then all G, then all B, as stored (negative entries zeroed at load).
IBLX_TABLE(utiaRgb, 1);

const uint kUtiaEntries = 82944u;

// The lower grid index of theta and of phi, the next phi index (wrapping) and the weights of the upper ones.
void utiaGrid(vec3 w, out int theta0, out int phi0, out int phi1, out vec2 weight) {
  float t = clamp(atan(length(w.xy), w.z) / radians(15.0), 0.0, 5.0);
  theta0 = min(int(t), 4);
  float phi = atan(w.y, w.x);
  if (phi < 0.0) phi += 2.0 * kPi;
  float p = phi / radians(7.5);
  float floorP = floor(p);
  phi0 = int(floorP) % 48;
  phi1 = (phi0 + 1) % 48;
  weight = vec2(t - float(theta0), p - floorP);
}

float utiaDecode(float v) {
  v = max(v, 0.0) * prescale;
  if (srgb) v = v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4);  // IEC 61966-2-1
  return scale * v;
}

vec3 brdfEval(vec3 wi, vec3 wo) {
  if (wi.z <= 0.0 || wo.z <= 0.0) return vec3(0.0);
  int ti, pi0, pi1, tv, pv0, pv1;
  vec2 wI, wV;
  utiaGrid(wi, ti, pi0, pi1, wI);
  utiaGrid(wo, tv, pv0, pv1, wV);
  vec3 f = vec3(0.0);
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      for (int c = 0; c < 2; ++c)
        for (int d = 0; d < 2; ++d) {
          float weight = (a == 1 ? wI.x : 1.0 - wI.x) * (b == 1 ? wI.y : 1.0 - wI.y) *
                         (c == 1 ? wV.x : 1.0 - wV.x) * (d == 1 ? wV.y : 1.0 - wV.y);
          uint index = uint(((((ti + a) * 48 + (b == 1 ? pi1 : pi0)) * 6 + (tv + c)) * 48) + (d == 1 ? pv1 : pv0));
          f += weight * vec3(tableFloat(utiaRgb, index), tableFloat(utiaRgb, index + kUtiaEntries),
                             tableFloat(utiaRgb, index + 2u * kUtiaEntries));
        }
  return vec3(utiaDecode(f.r), utiaDecode(f.g), utiaDecode(f.b));
}
