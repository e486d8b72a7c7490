// Env technique "env-ot-inv": the tabulated inverse of the optimal-transport map (engine/ot/map.h tabulatedInverse: the
// forward map inverted on the vertices of a regular grid over the uniform square). A sample is one bilinear
// (or affine) lookup, x = G(u); its density in the density square is 1 / |det DG(u)| of the piece evaluated,
// divided by dOmega / dx of otParameterToDirection for solid angle. Near-delta texels (suns) are sampled apart
// (lib/ot_sun.glsl): the map carries the capped density only. The OT density of any other direction (a sun
// sample's, or MIS's) needs its preimage under G: the forward map's image of the point names the G cell to
// test first, then its 8 neighbours, then the quadtree over G's image.
#include "lib/table.glsl"
#include "lib/latlong.glsl"
#include "lib/ot_sun.glsl"
#include "lib/quad_grid_map.glsl"

// The forward map F that G tabulates the inverse of (engine/ot/map.h forwardMap), on the same grid: F(x) is a first
// guess of x's preimage under G, so a sun sample's OT density costs a few piece tests, not a quadtree search.
IBLX_TABLE(otForwardVertex, 2);
IBLX_TABLE(otForwardPiece, 1);

vec2 otForwardApply(vec2 x) {
  float jac;
  return quadGridApply(otForwardVertex, otForwardPiece, x, jac);
}

// The OT part's pdf per unit solid angle at w: 1 / |det DG| at the preimage of w's parameter point x, looked
// for in G's cell around F(x) and its 8 neighbours, then (rarely) by the quadtree over G's image.
float otInversePdf(vec3 w) {
  const uint m = OT_GRID;
  float solidAngle;
  vec2 x = otDirectionToParameter(w, solidAngle);
  if (!(solidAngle > 0.0)) return 0.0;
  ivec2 guess = ivec2(min(uvec2(clamp(otForwardApply(x), 0.0, 1.0) * float(m)), uvec2(m - 1u)));
  const ivec2 kAround[9] = ivec2[9](ivec2(0, 0), ivec2(-1, 0), ivec2(1, 0), ivec2(0, -1), ivec2(0, 1),
                                    ivec2(-1, -1), ivec2(1, -1), ivec2(-1, 1), ivec2(1, 1));
  for (int k = 0; k < 9; ++k) {
    ivec2 ij = guess + kAround[k];
    if (any(lessThan(ij, ivec2(0))) || any(greaterThanEqual(ij, ivec2(int(m))))) continue;
    vec2 u;
    float jac;
    if (quadMapInvertCell(uint(ij.y) * m + uint(ij.x), x, 1e-5, u, jac))
      return jac > 0.0 ? 1.0 / (jac * solidAngle) : 0.0;
  }
  vec2 u;
  float jac;
  if (!quadMapInvert(x, u, jac)) return 0.0;
  return jac > 0.0 ? 1.0 / (jac * solidAngle) : 0.0;
}

vec3 envSample(vec2 u, vec3 n, out float pdf, out vec3 radiance) {
  vec3 w;
  ivec2 texel;
  float pSun, pOt;
  if (otSunChoose(u)) {
    w = otSunSample(u, texel, pSun);
    pOt = otInversePdf(w);
  } else {
    float jac, solidAngle;
    w = otParameterToDirection(quadMapApply(u, jac), solidAngle);
    pOt = (jac > 0.0 && solidAngle > 0.0) ? 1.0 / (jac * solidAngle) : 0.0;
    texel = directionToTexel(w);
    pSun = otSunTexelPdf(texel);
  }
  pdf = otSunMixture(pSun, pOt);
  radiance = pdf > 0.0 ? envTexelRadiance(texel) : vec3(0.0);
  return w;
}

float envPdf(vec3 wi, vec3 n) { return otSunMixture(otSunTexelPdf(directionToTexel(wi)), otInversePdf(wi)); }
