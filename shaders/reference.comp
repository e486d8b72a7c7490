// The ground truth (docs/DESIGN.md §4): Lo = sum over texels j of L_j * integral over texel j of f cos, by composite
// 2-point Gauss-Legendre quadrature on the texel's area-preserving parameterisation (texelToDirection), so each
// point's weight is the texel's exact solid angle / point count. Texels whose centre lies within the fine-zone
// cone around the mirror direction get frame.quadrature.y subdivisions per axis, texels the horizon may cross at
// least frame.strategy.w, the few brightest texels (energy mean(L) * solid angle >= frame.strategy.x, such as a
// sun's) at least frame.strategy.y, the others frame.quadrature.x.
// Each dispatch adds the texels [sampleOffset, samplesPerPass) in row-major order with Kahan-compensated sums in
// accum (mean = sum, meanSquare = compensation); the host sizes these ranges so that no invocation runs more loop
// iterations than lavapipe allows (engine/render/reference.cpp).
//
// With REFERENCE_ORACLE_PASS the same sweep gives the variance of the oracle (engine/render/oracle.h): one
// sample picks texel t with probability w_t / W, w_t = Y(L_t * integral over t of f cos) (Rec. 709 luminance),
// W = sum of w_t, and a direction uniformly in solid angle inside it (texelToDirection preserves area), so its
// estimate is c_t f cos with c_t = L_t * solidAngle_t * W / w_t. Pass 1 sums I (Kahan, in mean.rgb and
// meanSquare.rgb as above) and W (mean.w, compensation meanSquare.w); pass 2 reads them and sums the variance
// of one sample, sum over t of (w_t / W) * mean over t's Gauss points of (c_t f cos - I)^2: a sum of
// non-negative terms, so a near-perfect oracle's small variance does not cancel away as W S - I^2 would.
#ifndef REFERENCE_ORACLE_PASS
#define REFERENCE_ORACLE_PASS 0
#endif
#include "lib/frame_resources.glsl"
#include "lib/latlong.glsl"
#include "lib/pixel_shading.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

const float kGaussNode = 0.21132486540518713;  // (1 - 1/sqrt(3)) / 2: 2-point Gauss-Legendre on [0,1]

vec3 fCos(ivec2 texel, vec2 t, Shading s) {
  vec3 wiLocal = toLocal(s, texelToDirection(texel, t));
  return wiLocal.z > 0.0 ? brdfEval(wiLocal, s.woLocal) * wiLocal.z : vec3(0.0);
}

// One flat loop over the sub-cells, the four Gauss points written out: lavapipe caps the loop iterations an
// invocation may run (about 65535 in all), so the loops here are kept as few and as short as possible.
vec3 texelIntegral(ivec2 texel, Shading s, int subdivisions) {
  vec3 sum = vec3(0.0);
  float inv = 1.0 / float(subdivisions);
  for (int cell = 0; cell < subdivisions * subdivisions; ++cell) {
    vec2 corner = vec2(cell % subdivisions, cell / subdivisions);
    sum += fCos(texel, (corner + vec2(kGaussNode, kGaussNode)) * inv, s);
    sum += fCos(texel, (corner + vec2(1.0 - kGaussNode, kGaussNode)) * inv, s);
    sum += fCos(texel, (corner + vec2(kGaussNode, 1.0 - kGaussNode)) * inv, s);
    sum += fCos(texel, (corner + vec2(1.0 - kGaussNode, 1.0 - kGaussNode)) * inv, s);
  }
  return sum * (texelSolidAngle(texel) / float(4 * subdivisions * subdivisions));
}

#if REFERENCE_ORACLE_PASS != 0
float oracleLuminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

#if REFERENCE_ORACLE_PASS == 2
// A texel's term of the oracle's variance (see the top of the file); `integral` is texelIntegral's.
vec3 texelOracleVariance(ivec2 texel, Shading s, int subdivisions, vec3 radiance, vec3 integral, vec3 mean,
                         float total) {
  float w = oracleLuminance(radiance * integral);
  if (!(w > 0.0) || !(total > 0.0)) return vec3(0.0);
  vec3 c = radiance * (texelSolidAngle(texel) * total / w);
  vec3 sum = vec3(0.0);
  float inv = 1.0 / float(subdivisions);
  for (int cell = 0; cell < subdivisions * subdivisions; ++cell) {
    vec2 corner = vec2(cell % subdivisions, cell / subdivisions);
    vec3 d = c * fCos(texel, (corner + vec2(kGaussNode, kGaussNode)) * inv, s) - mean;
    sum += d * d;
    d = c * fCos(texel, (corner + vec2(1.0 - kGaussNode, kGaussNode)) * inv, s) - mean;
    sum += d * d;
    d = c * fCos(texel, (corner + vec2(kGaussNode, 1.0 - kGaussNode)) * inv, s) - mean;
    sum += d * d;
    d = c * fCos(texel, (corner + vec2(1.0 - kGaussNode, 1.0 - kGaussNode)) * inv, s) - mean;
    sum += d * d;
  }
  return sum * (w / total / float(4 * subdivisions * subdivisions));
}
#endif
#endif

void main() {
  uvec2 pixel = gl_GlobalInvocationID.xy;
  if (pixel.x >= frame.width || pixel.y >= frame.height) return;
  uint index = pixel.y * frame.width + pixel.x;
  GPixel g = gbuffer[index];
  if (g.normal.w == 0.0) {
#if REFERENCE_ORACLE_PASS == 2
    return;  // no variance: pass 1 left the background and a zero variance
#endif
    vec3 radiance = envRadiance(normalize(worldToEnv(g.view.xyz)));
    accum[index].mean = vec4(radiance, 1.0);
    accum[index].meanSquare = vec4(0.0);
    return;
  }
  Shading s = pixelShading(g);
  vec3 mirror = reflect(-s.wo, s.n);
  int coarse = int(frame.quadrature.x), fine = int(frame.quadrature.y);
  float fineZoneCos = frame.quadrature.z;
  float horizonBand = frame.strategy.z;  // |n . centre| below this: the horizon may cross the texel
  int horizonFine = int(frame.strategy.w);
  float brightEnergy = frame.strategy.x;
  int brightFine = int(frame.strategy.y);
  precise vec3 sum = accum[index].mean.rgb;
  precise vec3 compensation = accum[index].meanSquare.rgb;
  uint texelBegin = frame.sampleOffset, texelEnd = frame.samplesPerPass;
  if (texelBegin == 0u) sum = compensation = vec3(0.0);
#if REFERENCE_ORACLE_PASS != 0
  precise float weights = accum[index].mean.w, weightsCompensation = accum[index].meanSquare.w;
  if (texelBegin == 0u) weights = weightsCompensation = 0.0;
#if REFERENCE_ORACLE_PASS == 2
  vec3 oracleMean = accum[index].mean.rgb;
  float oracleTotal = accum[index].mean.w;
  vec3 variance = texelBegin == 0u ? vec3(0.0) : accum[index].meanSquare.rgb;
#endif
#endif
  // Per row, only the texels whose centre can pass the horizon test below are visited. For a row's centres,
  // dot(n, d) = n.y cos(theta) + r sin(theta) cos(phi - phiN) with r = |n.xz|, so they lie in one interval of phi
  // around phiN (widened by two texels against rounding); the exact test still runs on each, so the texels
  // summed, and their order, are those of a loop over every texel: the result is the same, bit for bit.
  uint W = frame.envWidth;
  float r = length(s.n.xz);
  float phiN = atan(s.n.z, s.n.x);
  float texelsPerRadian = float(W) / kTwoPi;
  uint rowFirst = texelBegin / W, rowLast = (texelEnd - 1u) / W;
  for (uint y = rowFirst; y <= rowLast; ++y) {
    uint rowStart = max(texelBegin, y * W), rowEnd = min(texelEnd, (y + 1u) * W);
    vec4 row = tableVec4(envRows, int(y));
    float a = mix(row.y, row.z, 0.5);
    float cosTheta = row.w > 0.5 ? 2.0 * a - 1.0 : 1.0 - 2.0 * a;
    float rs = r * 2.0 * sqrt(max(a * (1.0 - a), 0.0));
    // Up to two ranges of columns, [x0, x1) then [x2, x3), in increasing order.
    int x0 = 0, x1 = int(W), x2 = 0, x3 = 0;
#ifndef REFERENCE_VISIT_EVERY_TEXEL
    if (rs < 1e-4) {
      if (s.n.y * cosTheta + rs <= -horizonBand - 1e-5) continue;  // the whole row is below the band
    } else {
      float c = (-horizonBand - s.n.y * cosTheta) / rs;
      if (c >= 1.0 + 1e-3) continue;
      if (c > -1.0) {
        float h = acos(min(c, 1.0));
        float first = (phiN - h) * texelsPerRadian - 2.5, last = (phiN + h) * texelsPerRadian + 1.5;
        if (last - first < float(W)) {
          float shift = floor(first / float(W)) * float(W);
          int f = int(floor(first - shift)), l = int(ceil(last - shift));
          if (l < int(W)) {
            x0 = f, x1 = l + 1;
          } else {
            x0 = 0, x1 = min(l + 1 - int(W), f), x2 = f, x3 = int(W);  // never a column twice
          }
        }
      }
    }
#endif
    for (int range = 0; range < 2; ++range) {
      uint begin = y * W + uint(range == 0 ? x0 : x2), end = y * W + uint(range == 0 ? x1 : x3);
      begin = max(begin, rowStart), end = min(end, rowEnd);
      for (uint i = begin; i < end; ++i) {
        {
          ivec2 texel = ivec2(i % frame.envWidth, i / frame.envWidth);
          vec3 radiance = envTexelRadiance(texel);
          if (radiance == vec3(0.0)) continue;
          vec3 centre = texelToDirection(texel, vec2(0.5));
          float cosCentre = dot(centre, s.n);
          if (cosCentre <= -horizonBand) continue;  // wholly below the horizon (coherent between neighbouring pixels)
          int k = dot(centre, mirror) >= fineZoneCos ? fine : coarse;
          k = cosCentre < horizonBand ? max(k, horizonFine) : k;
          // A sun holds most of the integral in a few texels, where f cos (a lobe's tail, MERL's piecewise-constant
          // bins) is not smooth enough for 2x2 points; the reference must be far more accurate there than anywhere.
          float energy = (radiance.r + radiance.g + radiance.b) / 3.0 * texelSolidAngle(texel);
          k = energy >= brightEnergy ? max(k, brightFine) : k;
          // k = 0: the midpoint rule (texels small against every feature of f cos); else Gauss on k x k sub-cells.
          vec3 integral;
          if (k == 0) {
            vec3 wiLocal = toLocal(s, centre);
            integral = wiLocal.z > 0.0 ? brdfEval(wiLocal, s.woLocal) * (wiLocal.z * texelSolidAngle(texel)) : vec3(0.0);
          } else {
            integral = texelIntegral(texel, s, k);
          }
#if REFERENCE_ORACLE_PASS == 2
          variance += texelOracleVariance(texel, s, max(k, 1), radiance, integral, oracleMean, oracleTotal);
#else
          precise vec3 term = radiance * integral - compensation;  // Kahan summation
          precise vec3 next = sum + term;
          compensation = (next - sum) - term;
          sum = next;
#endif
#if REFERENCE_ORACLE_PASS == 1
          precise float weightTerm = oracleLuminance(radiance * integral) - weightsCompensation;
          precise float nextWeights = weights + weightTerm;
          weightsCompensation = (nextWeights - weights) - weightTerm;
          weights = nextWeights;
#endif
        }
      }
    }
  }
#if REFERENCE_ORACLE_PASS == 2
  accum[index].meanSquare = vec4(variance, 0.0);
#elif REFERENCE_ORACLE_PASS == 1
  accum[index].mean = vec4(sum, weights);
  accum[index].meanSquare = vec4(compensation, weightsCompensation);
#else
  accum[index].mean = vec4(sum, 1.0);
  accum[index].meanSquare = vec4(compensation, 0.0);
#endif
}
