// The grid of one level of the OT solver (Nader & Guennebaud 2018, "Instant transport maps on 2D grids", ACM
// TOG 37(6), §4): n x n cells carry the potential psi and the target masses, (n+1)^2 vertices carry the map,
// and every vertex moves by the 2x2 difference of psi over the four cells around it. Shared by the
// continuation (solver.cpp), the Newton system (newton.h) and the line searches (line_search.h).
#pragma once

#include "engine/ot/dct.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cstddef>
#include <limits>
#include <mutex>
#include <span>
#include <utility>
#include <vector>

namespace iblx {

// Deterministic parallel reduction over [0, count): fn(lo, hi) returns K partial sums (or maxima, where isMax
// says so) of its chunk, and the chunks are combined in their order, so the result does not depend on which
// thread finished first (it does depend on the number of threads, which sets the chunks).
template <int K, typename F>
std::array<double, K> otReduceChunks(int threads, int count, int minChunk, F fn,
                                     std::array<bool, K> isMax = {}) {
  std::mutex mutex;
  std::vector<std::pair<int, std::array<double, K>>> parts;
  parallelChunks(threads, count, minChunk, [&](int lo, int hi) {
    const std::array<double, K> p = fn(lo, hi);
    const std::lock_guard lock(mutex);
    parts.emplace_back(lo, p);
  });
  std::sort(parts.begin(), parts.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::array<double, K> total{};
  for (int k = 0; k < K; ++k)
    if (isMax[std::size_t(k)]) total[std::size_t(k)] = -std::numeric_limits<double>::infinity();
  for (const auto& [lo, p] : parts)
    for (std::size_t k = 0; k < K; ++k) total[k] = isMax[k] ? std::max(total[k], p[k]) : total[k] + p[k];
  return total;
}

// The vertex indices of one cell's quad, counter-clockwise 00, 10, 11, 01 (i right, j down the rows).
struct OtQuad {
  std::size_t p00, p10, p11, p01;
};

// The current map of a level, as the Newton system and the line searches read it.
struct OtMapState {
  std::span<const glm::dvec2> positions;  // (n+1)^2 vertex positions P
  std::span<const double> mass;           // n^2 target areas m of the current continuation stage
  std::span<const double> residual;       // n^2 areas minus targets, A - m, at `positions`
};

class OtGrid {
 public:
  OtGrid(int n, int threads);

  int n() const { return n_; }
  int threads() const { return threads_; }
  std::size_t cellCount() const { return std::size_t(n_) * n_; }
  std::size_t vertexCount() const { return std::size_t(v_) * v_; }
  std::size_t cell(int i, int j) const { return std::size_t(j) * n_ + i; }
  std::size_t vertex(int i, int j) const { return std::size_t(j) * v_ + i; }
  OtQuad quad(int i, int j) const {
    const std::size_t p00 = vertex(i, j), p01 = p00 + std::size_t(v_);
    return {p00, p00 + 1, p01 + 1, p01};
  }

  // g = the vertex gradient of the cell function f: the 2x2 difference of the four cells around a vertex,
  // with cell indices clamped to the grid. Clamping gives exactly the boundary rule (normal component 0,
  // tangential 1-D difference, corners 0), so boundary vertices slide along the boundary.
  void gradient(std::span<const double> f, std::span<glm::dvec2> g);
  // positions = the identity grid (i/n, j/n) moved by gradient(psi): the map of psi.
  void mapOf(std::span<const double> psi, std::span<glm::dvec2> positions);

 private:
  int n_, v_, threads_;
  std::vector<double> pad_;  // f with a clamped border of one cell, (n+2)^2
};

}  // namespace iblx
