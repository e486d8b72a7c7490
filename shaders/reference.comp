// The ground truth (DESIGN §4): Lo = sum over texels j of L_j * integral over texel j of f cos, by composite
// 2-point Gauss-Legendre quadrature on the texel's area-preserving parameterisation (texelToDirection), so each
// point's weight is the texel's exact solid angle / point count. Texels whose centre lies within the fine-zone
// cone around the mirror direction, or that the horizon may cross, get frame.quadrature.y subdivisions per axis,
// the others .x.
// Each dispatch adds the rows [rowBegin, rowBegin + quadrature.w) with Kahan-compensated sums in accum
// (mean = sum, meanSquare = compensation), so long references are split into short dispatches.
#include "lib/frame_resources.glsl"
#include "lib/latlong.glsl"
#include "lib/pixel_shading.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

const float kGaussNode = 0.21132486540518713;  // (1 - 1/sqrt(3)) / 2: 2-point Gauss-Legendre on [0,1]

vec3 texelIntegral(ivec2 texel, Shading s, int subdivisions) {
  vec3 sum = vec3(0.0);
  float inv = 1.0 / float(subdivisions);
  for (int j = 0; j < subdivisions; ++j)
    for (int i = 0; i < subdivisions; ++i)
      for (int q = 0; q < 4; ++q) {
        vec2 node = vec2((q & 1) == 0 ? kGaussNode : 1.0 - kGaussNode, (q & 2) == 0 ? kGaussNode : 1.0 - kGaussNode);
        vec3 wi = texelToDirection(texel, (vec2(i, j) + node) * inv);
        vec3 wiLocal = toLocal(s, wi);
        if (wiLocal.z > 0.0) sum += brdfEval(wiLocal, s.woLocal) * wiLocal.z;
      }
  return sum * (texelSolidAngle(texel) / float(4 * subdivisions * subdivisions));
}

void main() {
  uvec2 pixel = gl_GlobalInvocationID.xy;
  if (pixel.x >= frame.width || pixel.y >= frame.height) return;
  uint index = pixel.y * frame.width + pixel.x;
  GPixel g = gbuffer[index];
  if (g.normal.w == 0.0) {
    vec3 radiance = envRadiance(normalize(worldToEnv(g.view.xyz)));
    accum[index].mean = vec4(radiance, 1.0);
    accum[index].meanSquare = vec4(0.0);
    return;
  }
  Shading s = pixelShading(g);
  vec3 mirror = reflect(-s.wo, s.n);
  int coarse = int(frame.quadrature.x), fine = int(frame.quadrature.y);
  float fineZoneCos = frame.quadrature.z;
  float horizonBand = frame.strategy.z;  // |n . centre| below this: the horizon crosses the texel
  precise vec3 sum = accum[index].mean.rgb;
  precise vec3 compensation = accum[index].meanSquare.rgb;
  if (frame.rowBegin == 0u) sum = compensation = vec3(0.0);
  uint rowEnd = min(frame.rowBegin + uint(frame.quadrature.w), frame.envHeight);
  for (uint y = frame.rowBegin; y < rowEnd; ++y) {
    for (uint x = 0u; x < frame.envWidth; ++x) {
      ivec2 texel = ivec2(x, y);
      vec3 radiance = envTexelRadiance(texel);
      if (radiance == vec3(0.0)) continue;
      vec3 centre = texelToDirection(texel, vec2(0.5));
      bool refine = dot(centre, mirror) >= fineZoneCos || abs(dot(centre, s.n)) < horizonBand;
      int k = refine ? fine : coarse;
      precise vec3 term = radiance * texelIntegral(texel, s, k) - compensation;  // Kahan summation
      precise vec3 next = sum + term;
      compensation = (next - sum) - term;
      sum = next;
    }
  }
  accum[index].mean = vec4(sum, 1.0);
  accum[index].meanSquare = vec4(compensation, 0.0);
}
