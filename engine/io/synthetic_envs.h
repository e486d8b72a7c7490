// Synthetic environment maps: the hard cases of docs/DESIGN.md §5 (suns, exactly-zero regions, energy at a pole) and
// smooth skies, made in code so tests and the hard-case suite (engine/render/hard_cases.h) need no files.
#pragma once

#include "engine/io/env_image.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

namespace iblx {

// A W x H image whose texel (x, y) is rgb(phi, theta) at the texel centre.
template <typename Rgb>
EnvImage makeEnv(int width, int height, Rgb rgb) {
  EnvImage image{width, height, std::vector<float>(3 * std::size_t(width) * std::size_t(height))};
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double phi = 2.0 * std::numbers::pi * (x + 0.5) / width,
                   theta = std::numbers::pi * (y + 0.5) / height;
      const auto c = rgb(x, y, phi, theta);
      float* p = &image.rgb[3 * image.index(x, y)];
      p[0] = float(c[0]), p[1] = float(c[1]), p[2] = float(c[2]);
    }
  return image;
}

// Every texel `value` in all channels.
inline EnvImage constantEnv(int width, int height, float value) {
  return makeEnv(width, height, [value](int, int, double, double) {
    return std::array<double, 3>{value, value, value};
  });
}

// A smooth, strictly positive sky: brighter towards +Y and towards phi = 0, slightly blue.
inline EnvImage smoothSky(int width, int height) {
  return makeEnv(width, height, [](int, int, double phi, double theta) {
    const double l = 0.3 + 0.75 * (1.0 + std::cos(theta)) + 0.4 * (1.0 + std::cos(phi));
    return std::array<double, 3>{0.9 * l, l, 1.2 * l};
  });
}

// Sky of 1 on the upper half (rows y < H/2), a sun of 1e6 in the two texels (W/3, H/4) and (W/3 + 1, H/4),
// and the whole lower half exactly 0.
inline EnvImage sunAndZeroHalf(int width, int height) {
  return makeEnv(width, height, [=](int x, int y, double, double) {
    double v = y < height / 2 ? 1.0 : 0.0;
    if (y == height / 4 && (x == width / 3 || x == width / 3 + 1)) v = 1e6;
    return std::array<double, 3>{v, v, v};
  });
}

// Energy concentrated in the two top rows (1000 x (1 + sin(phi)/2), the same in both rows so the density has
// no jump between them), 1e-3 elsewhere: stresses the poles, where texels are thinnest.
inline EnvImage poleEnergy(int width, int height) {
  return makeEnv(width, height, [](int, int y, double phi, double) {
    const double v = y < 2 ? 1000.0 * (1.0 + 0.5 * std::sin(phi)) : 1e-3;
    return std::array<double, 3>{v, v, v};
  });
}

// A smooth sky (smoothSky) with a sun `ratio` times the sky's mean in a square of `sunTexels` x `sunTexels`
// texels whose top-left texel is (x, y).
inline EnvImage sunOverSky(int width, int height, double ratio, int sunTexels, int x, int y) {
  EnvImage image = smoothSky(width, height);
  double mean = 0.0;
  for (float v : image.rgb) mean += v;
  mean /= double(image.rgb.size());
  for (int dy = 0; dy < sunTexels; ++dy)
    for (int dx = 0; dx < sunTexels; ++dx) {
      float* p = &image.rgb[3 * image.index((x + dx) % width, std::min(y + dy, height - 1))];
      p[0] = float(ratio * mean), p[1] = float(ratio * mean * 0.95), p[2] = float(ratio * mean * 0.85);
    }
  return image;
}

}  // namespace iblx
