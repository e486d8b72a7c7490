// The OT solver's level grid (grid.h): the vertex gradient of a cell function and the map of a potential.
#include "engine/ot/grid.h"

namespace iblx {

OtGrid::OtGrid(int n, int threads)
    : n_(n), v_(n + 1), threads_(threads), pad_(std::size_t(n + 2) * (n + 2)) {}

void OtGrid::gradient(std::span<const double> f, std::span<glm::dvec2> g) {
  const int n = n_, w = n + 2;
  for (int j = 0; j < w; ++j) {
    const int sj = std::clamp(j - 1, 0, n - 1);
    for (int i = 0; i < w; ++i)
      pad_[std::size_t(j) * w + i] = f[std::size_t(sj) * n + std::clamp(i - 1, 0, n - 1)];
  }
  const double half = 0.5 * n;
  parallelChunks(threads_, v_, 16, [&](int lo, int hi) {
    for (int j = lo; j < hi; ++j) {
      const double* top = &pad_[std::size_t(j) * w];
      const double* bottom = top + w;
      for (int i = 0; i < v_; ++i) {
        const double a = top[i], b = top[i + 1], c = bottom[i], d = bottom[i + 1];
        // Differences first, so that equal clamped neighbours give an exact 0 on the boundary.
        g[vertex(i, j)] = glm::dvec2(half * ((b - a) + (d - c)), half * ((c - a) + (d - b)));
      }
    }
  });
}

void OtGrid::mapOf(std::span<const double> psi, std::span<glm::dvec2> positions) {
  gradient(psi, positions);
  for (int j = 0; j < v_; ++j)
    for (int i = 0; i < v_; ++i) positions[vertex(i, j)] += glm::dvec2(double(i) / n_, double(j) / n_);
}

}  // namespace iblx
