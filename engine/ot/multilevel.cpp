// The OT solver's coarse-to-fine transfers (multilevel.h).
#include "engine/ot/multilevel.h"

#include <algorithm>
#include <cstddef>

namespace iblx {

std::vector<double> otRestrictDensity(std::span<const double> rho, int n) {
  const int m = n / 2;
  std::vector<double> out(std::size_t(m) * m);
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) {
      const std::size_t a = std::size_t(2 * j) * n + 2 * i, b = a + n;
      out[std::size_t(j) * m + i] = 0.25 * (rho[a] + rho[a + 1] + rho[b] + rho[b + 1]);
    }
  return out;
}

std::vector<double> otProlongPotential(std::span<const double> psi, int m) {
  const int n = 2 * m, v = m + 1;
  std::vector<double> corner(std::size_t(v) * v);
  for (int y = 0; y < v; ++y)
    for (int x = 0; x < v; ++x) {
      const int x0 = std::clamp(x - 1, 0, m - 1), x1 = std::clamp(x, 0, m - 1);
      const int y0 = std::clamp(y - 1, 0, m - 1), y1 = std::clamp(y, 0, m - 1);
      corner[std::size_t(y) * v + x] = 0.25 * (psi[std::size_t(y0) * m + x0] + psi[std::size_t(y0) * m + x1] +
                                               psi[std::size_t(y1) * m + x0] + psi[std::size_t(y1) * m + x1]);
    }
  std::vector<double> out(std::size_t(n) * n);
  for (int j = 0; j < n; ++j) {
    const double y = 0.5 * (j + 0.5);  // fine cell centre in coarse cell units, the coarse vertices at 0..m
    const int y0 = std::min(int(y), m - 1);
    const double wy = y - y0;
    for (int i = 0; i < n; ++i) {
      const double x = 0.5 * (i + 0.5);
      const int x0 = std::min(int(x), m - 1);
      const double wx = x - x0;
      const auto at = [&](int a, int b) { return corner[std::size_t(b) * v + a]; };
      out[std::size_t(j) * n + i] = (1 - wy) * ((1 - wx) * at(x0, y0) + wx * at(x0 + 1, y0)) +
                                    wy * ((1 - wx) * at(x0, y0 + 1) + wx * at(x0 + 1, y0 + 1));
    }
  }
  double mean = 0.0;
  for (double value : out) mean += value;
  mean /= double(out.size());
  for (double& value : out) value -= mean;
  return out;
}

void otSmoothPotential(std::span<double> psi, int n, int passes) {
  std::vector<double> rows(psi.size());
  const auto at = [n](int i, int j) { return std::size_t(j) * n + i; };
  for (int pass = 0; pass < passes; ++pass) {
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        rows[at(i, j)] = 0.25 * (psi[at(std::max(i - 1, 0), j)] + 2.0 * psi[at(i, j)] +
                                 psi[at(std::min(i + 1, n - 1), j)]);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        psi[at(i, j)] = 0.25 * (rows[at(i, std::max(j - 1, 0))] + 2.0 * rows[at(i, j)] +
                                rows[at(i, std::min(j + 1, n - 1))]);
  }
}

int otSmoothUntilUnfolded(std::span<double> psi, int n, int maxPasses,
                          const std::function<int(std::span<const double>)>& foldedQuads, int& passes) {
  passes = 0;
  int folded = 1;  // psi comes in folded
  for (int batch = 1; folded > 0 && passes + batch <= maxPasses; batch = passes) {
    otSmoothPotential(psi, n, batch);
    passes += batch;
    folded = foldedQuads(psi);
  }
  return folded;
}

}  // namespace iblx
