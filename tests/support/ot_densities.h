// Synthetic densities on the n x n lat-long grid for the OT solver and map tests (row-major, row = v).
#pragma once

#include <cmath>
#include <numbers>
#include <vector>

namespace iblx::test {

// Smooth sky-like density on the lat-long square: radiance times sin(theta) at the cell centre.
inline std::vector<double> smoothDensity(int n) {
  constexpr double pi = std::numbers::pi;
  std::vector<double> d(std::size_t(n) * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double u = (i + 0.5) / n, v = (j + 0.5) / n;
      d[std::size_t(j) * n + i] =
          (0.3 + 0.75 * (1 + std::cos(pi * v)) + 0.4 * (1 + std::cos(2 * pi * u))) * std::sin(pi * v);
    }
  return d;
}

// 1 everywhere plus `peak` times a Gaussian of sigma = 1 cell centred on cell (n/3, n/4): the sun covers a
// few cells.
inline std::vector<double> sunDensity(int n, double peak) {
  std::vector<double> d(std::size_t(n) * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double r2 = double(i - n / 3) * (i - n / 3) + double(j - n / 4) * (j - n / 4);
      d[std::size_t(j) * n + i] = 1.0 + peak * std::exp(-0.5 * r2);
    }
  return d;
}

// Left half exactly 0, right half 1.
inline std::vector<double> halfZeroDensity(int n) {
  std::vector<double> d(std::size_t(n) * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) d[std::size_t(j) * n + i] = i < n / 2 ? 0.0 : 1.0;
  return d;
}

}  // namespace iblx::test
