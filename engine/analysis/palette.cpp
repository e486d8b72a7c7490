// The figures' colours (palette.h): the Tableau 10 palette and the heat-map colormap's table.
#include "engine/analysis/palette.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace iblx {

Rgb8 paletteColor(std::size_t index) {
  // Tableau 10 (the classic set): distinguishable, and still readable in print.
  static constexpr std::array<Rgb8, 10> kTableau10{{{31, 119, 180},
                                                    {255, 127, 14},
                                                    {44, 160, 44},
                                                    {214, 39, 40},
                                                    {148, 103, 189},
                                                    {140, 86, 75},
                                                    {227, 119, 194},
                                                    {127, 127, 127},
                                                    {188, 189, 34},
                                                    {23, 190, 207}}};
  return kTableau10[index % kTableau10.size()];
}

namespace {

double luma(const std::array<int, 3>& rgb) {
  return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2];
}

// 256 entries, one per 8-bit output level, so the map is computed once and its quantization can be checked.
std::array<Rgb8, 256> buildColormapTable() {
  // Evenly spaced sRGB control points, dark blue -> blue -> teal -> green -> yellow, chosen so that luma
  // rises by roughly equal steps (25 -> 220): ordered dark to bright, and still ordered in greyscale print.
  static constexpr std::array<std::array<double, 3>, 6> kControl{
      {{32, 18, 72}, {58, 58, 134}, {40, 112, 150}, {34, 160, 134}, {128, 202, 76}, {246, 230, 48}}};
  constexpr int kSegments = int(kControl.size()) - 1;
  std::array<Rgb8, 256> table{};
  std::array<int, 3> previous{};
  for (int i = 0; i < 256; ++i) {
    const double t = i / 255.0;
    const int segment = std::min(int(t * kSegments), kSegments - 1);
    const double u = t * kSegments - segment;
    // Catmull-Rom through the control points (ends repeated) for a map without visible kinks.
    const auto& p0 = kControl[std::size_t(std::max(segment - 1, 0))];
    const auto& p1 = kControl[std::size_t(segment)];
    const auto& p2 = kControl[std::size_t(segment + 1)];
    const auto& p3 = kControl[std::size_t(std::min(segment + 2, kSegments))];
    std::array<int, 3> rgb{};
    for (std::size_t c = 0; c < 3; ++c) {
      const double v =
          0.5 * (2 * p1[c] + (p2[c] - p0[c]) * u + (2 * p0[c] - 5 * p1[c] + 4 * p2[c] - p3[c]) * u * u +
                 (3 * p1[c] - p0[c] - 3 * p2[c] + p3[c]) * u * u * u);
      rgb[c] = int(std::lround(std::clamp(v, 0.0, 255.0)));
    }
    // The spline's luma rises by ~0.8 per level, less than one code of rounding noise; nudging green (the
    // heaviest luma weight) up by a code where rounding made luma stall keeps it strictly increasing.
    while (i > 0 && luma(rgb) <= luma(previous) && rgb[1] < 255) ++rgb[1];
    table[std::size_t(i)] = {std::uint8_t(rgb[0]), std::uint8_t(rgb[1]), std::uint8_t(rgb[2])};
    previous = rgb;
  }
  return table;
}

}  // namespace

Rgb8 colormap(double t) {
  if (std::isnan(t)) return kMaskedGrey;
  static const std::array<Rgb8, 256> kTable = buildColormapTable();
  return kTable[std::size_t(std::lround(std::clamp(t, 0.0, 1.0) * 255.0))];
}

}  // namespace iblx
