// Composition of the compare mode's canvas (tools/viewer/compare_view.h).
#include "tools/viewer/compare_view.h"

#include "engine/analysis/palette.h"
#include "engine/render/metrics.h"
#include "tools/viewer/window.h"

#include <algorithm>
#include <cmath>

namespace iblx::viewer {
namespace {

// One image's pixel (x, y) written at (x0 + x, y0 + y) of the canvas, through the display transform.
void drawImage(CompareCanvas& canvas, int x0, int y0, const CompareFrame& f, std::span<const float> rgb,
               int xBegin, int xEnd) {
  const GBuffer& g = *f.gbuffer;
  for (int y = 0; y < g.height; ++y)
    for (int x = xBegin; x < xEnd; ++x) {
      const std::size_t p = std::size_t(y) * std::size_t(g.width) + std::size_t(x);
      std::uint8_t* out =
          &canvas.bgra[4 * (std::size_t(y0 + y) * std::size_t(canvas.width) + std::size_t(x0 + x))];
      out[3] = 255;
      const bool object = g.pixels[p].normal.w != 0.0f;
      if (rgb.empty() || (!object && !f.background)) {
        out[0] = out[1] = out[2] = kWindowGrey;
        continue;
      }
      out[2] = toDisplayByte(rgb[3 * p + 0], f.display);  // BGRA
      out[1] = toDisplayByte(rgb[3 * p + 1], f.display);
      out[0] = toDisplayByte(rgb[3 * p + 2], f.display);
    }
}

void drawError(CompareCanvas& canvas, int x0, int y0, const GBuffer& g, std::span<const float> rgb,
               std::span<const float> reference, double high) {
  const std::vector<double> error =
      rgb.empty() ? std::vector<double>() : relativeSquaredErrorPerPixel(g, rgb, reference);
  const double logLow = std::log10(high * 1e-4), logHigh = std::log10(high);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const std::size_t p = std::size_t(y) * std::size_t(g.width) + std::size_t(x);
      std::uint8_t* out =
          &canvas.bgra[4 * (std::size_t(y0 + y) * std::size_t(canvas.width) + std::size_t(x0 + x))];
      out[3] = 255;
      if (error.empty() || g.pixels[p].normal.w == 0.0f || !std::isfinite(error[p])) {
        out[0] = out[1] = out[2] = kWindowGrey;
        continue;
      }
      const double t = error[p] > 0.0 ? (std::log10(error[p]) - logLow) / (logHigh - logLow) : 0.0;
      const Rgb8 c = colormap(t);
      out[2] = c.r, out[1] = c.g, out[0] = c.b;
    }
}

}  // namespace

std::optional<double> sharedErrorHigh(const GBuffer& gbuffer, std::span<const float> a,
                                      std::span<const float> b, std::span<const float> reference) {
  std::vector<double> all;
  for (std::span<const float> image : {a, b}) {
    if (image.empty()) continue;
    for (double e : relativeSquaredErrorPerPixel(gbuffer, image, reference))
      if (std::isfinite(e) && e > 0.0) all.push_back(e);
  }
  if (all.empty()) return std::nullopt;
  const auto k = std::size_t(0.995 * double(all.size() - 1));
  std::nth_element(all.begin(), all.begin() + std::ptrdiff_t(k), all.end());
  return all[k];
}

CompareCanvas composeCompare(const CompareFrame& f) {
  const GBuffer& g = *f.gbuffer;
  CompareCanvas canvas;
  const bool errorRow = f.view == CompareView::SideBySide && !f.reference.empty();
  canvas.width = f.view == CompareView::SideBySide ? 2 * g.width : g.width;
  canvas.height = errorRow ? 2 * g.height : g.height;
  canvas.bgra.assign(std::size_t(canvas.width) * std::size_t(canvas.height) * 4, kWindowGrey);
  switch (f.view) {
    case CompareView::Split: {
      const int split = std::clamp(int(std::lround(f.divider * g.width)), 0, g.width);
      drawImage(canvas, 0, 0, f, f.a, 0, split);
      drawImage(canvas, 0, 0, f, f.b, split, g.width);
      if (split > 0 && split < g.width)
        for (int y = 0; y < g.height; ++y) {
          std::uint8_t* out =
              &canvas.bgra[4 * (std::size_t(y) * std::size_t(canvas.width) + std::size_t(split))];
          out[0] = out[1] = out[2] = out[3] = 255;
        }
      break;
    }
    case CompareView::SideBySide:
      drawImage(canvas, 0, 0, f, f.a, 0, g.width);
      drawImage(canvas, g.width, 0, f, f.b, 0, g.width);
      if (errorRow) {
        const double high = sharedErrorHigh(g, f.a, f.b, f.reference).value_or(1.0);
        drawError(canvas, 0, g.height, g, f.a, f.reference, high);
        drawError(canvas, g.width, g.height, g, f.b, f.reference, high);
      }
      break;
    case CompareView::Flip:
      drawImage(canvas, 0, 0, f, f.showB ? f.b : f.a, 0, g.width);
      break;
  }
  return canvas;
}

}  // namespace iblx::viewer
