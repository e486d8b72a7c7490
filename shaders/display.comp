// The viewer's canvas on the GPU: the renderers' running means through the display transform (exposure, tone
// curve, sRGB or gamma), composed as tools/viewer/compare_view.h's composeCompare composes them on the CPU
// (its reference implementation, which the tests compare this kernel with): one image, A | B split at a
// divider, A | B side by side with their relative squared error against the ground truth below, or A or B
// flipped. One invocation per canvas pixel, written as BGRA8.
#extension GL_GOOGLE_include_directive : require
#include "shared/frame_params.h"
#include "shared/display_params.h"

layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer AccumA { AccumPixel accumA[]; };
layout(std430, set = 0, binding = 1) readonly buffer AccumB { AccumPixel accumB[]; };
layout(std430, set = 0, binding = 2) readonly buffer GBufferData { GPixel gbuffer[]; };
layout(std430, set = 0, binding = 3) readonly buffer ReferenceData { float reference[]; };  // rgb per pixel
layout(std430, set = 0, binding = 4) readonly buffer ColormapData { uint colormapRgb[256]; };  // r | g<<8 | b<<16
layout(std430, set = 0, binding = 5) writeonly buffer CanvasData { uint canvas[]; };        // BGRA8
layout(push_constant) uniform DisplayBlock { DisplayParams display; };

const uint kWindowGrey = 24u;  // tools/viewer/window.h
const uint kGrey = kWindowGrey | (kWindowGrey << 8) | (kWindowGrey << 16) | (255u << 24);

float linearToSrgb(float x) {  // IEC 61966-2-1
  return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}

// engine/io/image_write.cpp's toDisplayByte, in float.
uint displayByte(float radiance) {
  float v = radiance * display.exposureScale;
  if (!(v > 0.0)) return 0u;  // also NaN
  float mapped = 1.0;
  if (v < 1e30) {  // above, every curve is 1 (and v * v would overflow)
    if (display.tonemap == 0u)
      mapped = min(v, 1.0);
    else if (display.tonemap == 1u)
      mapped = v / (1.0 + v);
    else
      mapped = clamp(v * (2.51 * v + 0.03) / (v * (2.43 * v + 0.59) + 0.14), 0.0, 1.0);
  }
  float encoded = display.gamma > 0.0 ? pow(mapped, 1.0 / display.gamma) : linearToSrgb(mapped);
  return uint(floor(255.0 * encoded + 0.5));
}

uint bgra(uint r, uint g, uint b) { return b | (g << 8) | (r << 16) | (255u << 24); }

// Pixel p of image A (or B) as it shows: grey where nothing was rendered yet, or off the object without the
// background.
uint imagePixel(bool isB, uint p) {
  if ((display.flags & (isB ? DISPLAY_HAS_B : DISPLAY_HAS_A)) == 0u) return kGrey;
  if (gbuffer[p].normal.w == 0.0 && (display.flags & DISPLAY_BACKGROUND) == 0u) return kGrey;
  vec3 rgb = isB ? accumB[p].mean.xyz : accumA[p].mean.xyz;
  return bgra(displayByte(rgb.r), displayByte(rgb.g), displayByte(rgb.b));
}

// The error row: the mean over channels of (x - r)^2 / (r^2 + 0.01) (engine/render/metrics.h) on the log
// colour scale; grey off the object, where nothing was rendered, or where the error is not finite.
uint errorPixel(bool isB, uint p) {
  if ((display.flags & (isB ? DISPLAY_HAS_B : DISPLAY_HAS_A)) == 0u || gbuffer[p].normal.w == 0.0) return kGrey;
  vec3 x = isB ? accumB[p].mean.xyz : accumA[p].mean.xyz;
  vec3 r = vec3(reference[3u * p], reference[3u * p + 1u], reference[3u * p + 2u]);
  // Non-finite inputs have no error (the CPU's double error is then not finite either).
  if (any(isnan(x)) || any(isinf(x)) || any(isnan(r)) || any(isinf(r))) return kGrey;
  // In logarithms, so that an error beyond float's range (the CPU computes it in double) still lands where
  // it belongs on the scale: ln e = ln(sum of the channels' (x - r)^2 / (r^2 + 0.01)) - ln 3.
  float logTerm[3];
  const float kMinusInfinity = uintBitsToFloat(0xff800000u);
  float logMax = kMinusInfinity;
  for (int c = 0; c < 3; ++c) {
    float d = abs(x[c] - r[c]), ar = abs(r[c]);
    float logDenominator = ar > 1e15 ? 2.0 * log(ar) : log(ar * ar + 0.01);
    logTerm[c] = d > 0.0 ? 2.0 * log(d) - logDenominator : kMinusInfinity;
    logMax = max(logMax, logTerm[c]);
  }
  float t = logMax > 0.0 ? 1.0 : 0.0;  // no error at all: the bottom; x - r beyond float: the top
  if (!isinf(logMax)) {
    float sum = 0.0;
    for (int c = 0; c < 3; ++c) sum += exp(logTerm[c] - logMax);
    float log10Error = (logMax + log(sum) - log(3.0)) / log(10.0);
    t = (log10Error - display.errorLog10Low) / (display.errorLog10High - display.errorLog10Low);
  }
  uint c = colormapRgb[uint(floor(clamp(t, 0.0, 1.0) * 255.0 + 0.5))];
  return bgra(c & 255u, (c >> 8) & 255u, (c >> 16) & 255u);
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= display.canvasWidth * display.canvasHeight) return;
  uint cx = i % display.canvasWidth, cy = i / display.canvasWidth;
  uint x = cx % display.width, y = cy % display.height;
  uint p = y * display.width + x;
  uint out_ = kGrey;
  if (display.view == 0u) {  // split
    if (cx == display.splitColumn && display.splitColumn > 0u && display.splitColumn < display.width)
      out_ = 0xffffffffu;
    else
      out_ = imagePixel(cx >= display.splitColumn, p);
  } else if (display.view == 1u) {  // side by side, the error row below
    bool isB = cx >= display.width;
    out_ = cy < display.height ? imagePixel(isB, p)
                               : ((display.flags & DISPLAY_ERROR_ROW) != 0u ? errorPixel(isB, p) : kGrey);
  } else {  // flip
    out_ = imagePixel((display.flags & DISPLAY_FLIP_SHOWS_B) != 0u, p);
  }
  canvas[i] = out_;
}
