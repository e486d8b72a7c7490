// QuadGridMap: piecewise bilinear / affine maps over a vertex grid, their inversion, and the quadtree that
// locates image points (see map.h).
#include "engine/ot/map.h"

#include "engine/core/error.h"
#include "engine/ot/geometry.h"
#include "engine/ot/solver.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <span>
#include <string>

namespace iblx {
namespace {

using Vec2 = glm::dvec2;

// (s, t) of y in the affine triangle o + s a + t b.
Vec2 solveAffine(Vec2 o, Vec2 a, Vec2 b, Vec2 y, double& det) {
  det = cross2(a, b);
  const Vec2 h = y - o;
  return det != 0.0 ? Vec2(cross2(h, b) / det, cross2(a, h) / det) : Vec2(-1.0);
}

struct Box {
  Vec2 lo, hi;
};

// Separating-axis test of a convex polygon (counter-clockwise) against a box, closed on both sides.
bool convexOverlapsBox(std::span<const Vec2> poly, const Box& box) {
  Vec2 lo = poly[0], hi = poly[0];
  for (const Vec2& p : poly) lo = glm::min(lo, p), hi = glm::max(hi, p);
  if (lo.x > box.hi.x || hi.x < box.lo.x || lo.y > box.hi.y || hi.y < box.lo.y) return false;
  const Vec2 corners[4] = {box.lo, {box.hi.x, box.lo.y}, box.hi, {box.lo.x, box.hi.y}};
  for (std::size_t k = 0; k < poly.size(); ++k) {
    const Vec2 a = poly[k], edge = poly[(k + 1) % poly.size()] - a;
    bool allOutside = true;  // every box corner strictly right of the edge
    for (const Vec2& c : corners) allOutside = allOutside && cross2(edge, c - a) < 0.0;
    if (allOutside) return false;
  }
  return true;
}

// Whether a cell's piece can contain points of the box: its convex quad, or either triangle of its split.
bool pieceOverlapsBox(QuadPiece piece, const Vec2 c[4], const Box& box) {
  switch (piece) {
    case QuadPiece::Bilinear:
      return convexOverlapsBox(std::span<const Vec2>(c, 4), box);
    case QuadPiece::SplitMainDiagonal: {
      const Vec2 a[3] = {c[0], c[1], c[2]}, b[3] = {c[0], c[2], c[3]};
      return convexOverlapsBox(a, box) || convexOverlapsBox(b, box);
    }
    case QuadPiece::SplitAntiDiagonal: {
      const Vec2 a[3] = {c[0], c[1], c[3]}, b[3] = {c[1], c[2], c[3]};
      return convexOverlapsBox(a, box) || convexOverlapsBox(b, box);
    }
    case QuadPiece::Invalid:
      break;
  }
  return false;  // an Invalid piece is never inverted
}

}  // namespace

QuadPiece classifyQuad(Vec2 p00, Vec2 p10, Vec2 p11, Vec2 p01) {
  if (strictlyConvexQuad(p00, p10, p11, p01)) return QuadPiece::Bilinear;
  if (cross2(p10 - p00, p11 - p00) > 0.0 && cross2(p11 - p00, p01 - p00) > 0.0)
    return QuadPiece::SplitMainDiagonal;
  if (cross2(p10 - p00, p01 - p00) > 0.0 && cross2(p11 - p10, p01 - p10) > 0.0)
    return QuadPiece::SplitAntiDiagonal;
  return QuadPiece::Invalid;
}

Vec2 evaluatePiece(QuadPiece piece, const Vec2 c[4], Vec2 st, double* localJacobian) {
  const Vec2 p00 = c[0], p10 = c[1], p11 = c[2], p01 = c[3];
  const double s = st.x, t = st.y;
  double jac = 0.0;
  Vec2 p;
  switch (piece) {
    case QuadPiece::SplitMainDiagonal:
      if (s >= t) {
        p = p00 + s * (p10 - p00) + t * (p11 - p10);
        jac = cross2(p10 - p00, p11 - p10);
      } else {
        p = p00 + s * (p11 - p01) + t * (p01 - p00);
        jac = cross2(p11 - p01, p01 - p00);
      }
      break;
    case QuadPiece::SplitAntiDiagonal:
      if (s + t <= 1.0) {
        p = p00 + s * (p10 - p00) + t * (p01 - p00);
        jac = cross2(p10 - p00, p01 - p00);
      } else {
        p = p11 + (1.0 - s) * (p01 - p11) + (1.0 - t) * (p10 - p11);
        jac = cross2(p11 - p01, p11 - p10);
      }
      break;
    default: {  // Bilinear (and Invalid, evaluated as bilinear)
      p = (1 - s) * (1 - t) * p00 + s * (1 - t) * p10 + s * t * p11 + (1 - s) * t * p01;
      const Vec2 ds = (1 - t) * (p10 - p00) + t * (p11 - p01), dt = (1 - s) * (p01 - p00) + s * (p11 - p10);
      jac = cross2(ds, dt);
    }
  }
  if (localJacobian) *localJacobian = jac;
  return p;
}

bool invertPiece(QuadPiece piece, const Vec2 c[4], Vec2 y, Vec2& st, double tolerance) {
  const Vec2 p00 = c[0], p10 = c[1], p11 = c[2], p01 = c[3];
  const auto inUnit = [&](Vec2 q) {
    return q.x >= -tolerance && q.y >= -tolerance && q.x <= 1.0 + tolerance && q.y <= 1.0 + tolerance;
  };
  double det = 0.0;
  switch (piece) {
    case QuadPiece::SplitMainDiagonal: {
      // Lower triangle: y = p00 + s (p10 - p00) + t (p11 - p10), s >= t.
      Vec2 q = solveAffine(p00, p10 - p00, p11 - p10, y, det);
      if (det > 0.0 && inUnit(q) && q.x - q.y >= -tolerance) return st = glm::clamp(q, 0.0, 1.0), true;
      q = solveAffine(p00, p11 - p01, p01 - p00, y, det);
      if (det > 0.0 && inUnit(q) && q.y - q.x >= -tolerance) return st = glm::clamp(q, 0.0, 1.0), true;
      return false;
    }
    case QuadPiece::SplitAntiDiagonal: {
      Vec2 q = solveAffine(p00, p10 - p00, p01 - p00, y, det);
      if (det > 0.0 && inUnit(q) && q.x + q.y <= 1.0 + tolerance) return st = glm::clamp(q, 0.0, 1.0), true;
      // y = p11 + a (p01 - p11) + b (p10 - p11) with a = 1 - s, b = 1 - t.
      q = solveAffine(p11, p01 - p11, p10 - p11, y, det);
      q = Vec2(1.0 - q.x, 1.0 - q.y);
      if (det > 0.0 && inUnit(q) && q.x + q.y >= 1.0 - tolerance) return st = glm::clamp(q, 0.0, 1.0), true;
      return false;
    }
    case QuadPiece::Invalid:
      return false;
    case QuadPiece::Bilinear:
      break;
  }
  // Bilinear: y - p00 = e s + f t + g s t; eliminating s gives k2 t^2 + k1 t + k0 = 0 (Quilez, "Inverse
  // bilinear interpolation", 2010), solved with the cancellation-free quadratic formula.
  const Vec2 e = p10 - p00, f = p01 - p00, g = p00 - p10 + p11 - p01, h = y - p00;
  const double k2 = cross2(g, f), k1 = cross2(e, f) + cross2(h, g), k0 = cross2(h, e);
  std::array<double, 2> roots{};
  int count = 0;
  const double scale = std::abs(k1) + std::abs(k0) + std::abs(k2);
  if (std::abs(k2) <= 1e-14 * scale) {
    if (k1 != 0.0) roots[count++] = -k0 / k1;
  } else {
    const double disc = k1 * k1 - 4.0 * k0 * k2;
    if (disc < 0.0) return false;
    const double q = -0.5 * (k1 + std::copysign(std::sqrt(disc), k1));
    roots[count++] = q / k2;
    if (q != 0.0) roots[count++] = k0 / q;
  }
  for (int r = 0; r < count; ++r) {
    const double t = roots[std::size_t(r)];
    const Vec2 den = e + g * t;
    const double s = std::abs(den.x) >= std::abs(den.y) ? (h.x - f.x * t) / den.x : (h.y - f.y * t) / den.y;
    Vec2 q(s, t);
    if (!std::isfinite(s) || !inUnit(q)) continue;
    // Two Newton steps on the bilinear map polish the root (its Jacobian is positive on a convex quad).
    for (int it = 0; it < 2; ++it) {
      double jac = 0.0;
      const Vec2 r0 = evaluatePiece(QuadPiece::Bilinear, c, q, &jac) - y;
      const Vec2 ds = (1 - q.y) * (p10 - p00) + q.y * (p11 - p01),
                 dt = (1 - q.x) * (p01 - p00) + q.x * (p11 - p10);
      if (!(jac > 0.0)) break;
      q -= Vec2(cross2(r0, dt), cross2(ds, r0)) / jac;
    }
    if (!inUnit(q)) continue;
    st = glm::clamp(q, 0.0, 1.0);
    return true;
  }
  return false;
}

QuadGridMap::QuadGridMap(int m, std::vector<Vec2> image, int leafCapacity, int maxDepth)
    : m_(m), image_(std::move(image)) {
  if (m < 1 || image_.size() != std::size_t(m + 1) * (m + 1))
    throw Error("quad grid map: expected (m+1)^2 vertices for m = " + std::to_string(m));
  const std::size_t cells = std::size_t(m) * m;
  pieces_.resize(cells);
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) {
      const std::size_t v = std::size_t(j) * (m + 1) + i, c = std::size_t(j) * m + i;
      const Vec2 p00 = image_[v], p10 = image_[v + 1], p11 = image_[v + m + 2], p01 = image_[v + m + 1];
      pieces_[c] = classifyQuad(p00, p10, p11, p01);
      invalid_ += pieces_[c] == QuadPiece::Invalid ? 1 : 0;
    }
  // Quadtree over [0,1]^2: split while a node lists more than leafCapacity cells, down to maxDepth. A cell is
  // listed in every leaf its piece touches (separating axes, closed boxes grown by a rounding margin), so a
  // point is always found in its own leaf's list; testing the pieces rather than their bounding boxes keeps
  // the lists short where slivers wrap around a sun.
  nodes_.push_back({});
  std::vector<std::uint32_t> all(cells);
  for (std::size_t c = 0; c < cells; ++c) all[c] = std::uint32_t(c);
  const std::function<void(std::size_t, Box, int, std::vector<std::uint32_t>&)> build =
      [&](std::size_t node, Box square, int depth, std::vector<std::uint32_t>& items) {
        depth_ = std::max(depth_, depth);
        if (items.size() <= std::size_t(leafCapacity) || depth >= maxDepth) {
          nodes_[node] = {std::uint32_t(leafCells_.size()), std::uint32_t(items.size())};
          leafCells_.insert(leafCells_.end(), items.begin(), items.end());
          largestLeaf_ = std::max(largestLeaf_, std::uint32_t(items.size()));
          return;
        }
        const Vec2 mid = 0.5 * (square.lo + square.hi);
        std::array<Box, 4> subs;
        std::array<std::vector<std::uint32_t>, 4> inside;
        bool separates = false;
        for (int q = 0; q < 4; ++q) {
          const Box sub{Vec2(q & 1 ? mid.x : square.lo.x, q & 2 ? mid.y : square.lo.y),
                        Vec2(q & 1 ? square.hi.x : mid.x, q & 2 ? square.hi.y : mid.y)};
          subs[std::size_t(q)] = sub;
          const Box grown{sub.lo - Vec2(1e-9), sub.hi + Vec2(1e-9)};
          for (std::uint32_t c : items) {
            const int ci = int(c % std::uint32_t(m)), cj = int(c / std::uint32_t(m));
            const std::size_t v = std::size_t(cj) * (m + 1) + ci;
            const Vec2 corners[4] = {image_[v], image_[v + 1], image_[v + m + 2], image_[v + m + 1]};
            if (pieceOverlapsBox(pieces_[c], corners, grown)) inside[std::size_t(q)].push_back(c);
          }
          separates = separates || inside[std::size_t(q)].size() < items.size();
        }
        // A split that leaves every child with the whole list (pieces meeting at a point, or covering the
        // node) only costs memory and descent steps: stop there.
        if (!separates) {
          nodes_[node] = {std::uint32_t(leafCells_.size()), std::uint32_t(items.size())};
          leafCells_.insert(leafCells_.end(), items.begin(), items.end());
          largestLeaf_ = std::max(largestLeaf_, std::uint32_t(items.size()));
          return;
        }
        const std::size_t child0 = nodes_.size();
        nodes_[node] = {std::uint32_t(child0), kQuadTreeInterior};
        nodes_.resize(child0 + 4);
        items.clear();
        items.shrink_to_fit();
        for (int q = 0; q < 4; ++q)
          build(child0 + std::size_t(q), subs[std::size_t(q)], depth + 1, inside[std::size_t(q)]);
      };
  build(0, Box{Vec2(0.0), Vec2(1.0)}, 0, all);
}

QuadGridMap::Point QuadGridMap::apply(Vec2 x) const {
  const Vec2 scaled = glm::clamp(x, 0.0, 1.0) * double(m_);
  const int i = std::min(int(scaled.x), m_ - 1), j = std::min(int(scaled.y), m_ - 1);
  const std::size_t v = std::size_t(j) * (m_ + 1) + i, c = std::size_t(j) * m_ + i;
  const Vec2 corners[4] = {image_[v], image_[v + 1], image_[v + m_ + 2], image_[v + m_ + 1]};
  double jac = 0.0;
  const Vec2 p = evaluatePiece(pieces_[c], corners, scaled - Vec2(i, j), &jac);
  return {p, jac * double(m_) * double(m_), std::uint32_t(c)};
}

std::optional<QuadGridMap::Point> QuadGridMap::invert(Vec2 y) const {
  std::size_t node = 0;
  Vec2 lo(0.0), hi(1.0);
  while (nodes_[node].count == kQuadTreeInterior) {
    const Vec2 mid = 0.5 * (lo + hi);
    const int q = (y.x >= mid.x ? 1 : 0) + (y.y >= mid.y ? 2 : 0);
    (q & 1 ? lo.x : hi.x) = mid.x;
    (q & 2 ? lo.y : hi.y) = mid.y;
    node = nodes_[node].first + std::size_t(q);
  }
  const QuadTreeNode leaf = nodes_[node];
  // Exact containment first; a point on a shared edge or in a rounding gap between pieces then gets a
  // tolerance.
  for (const double tolerance : {1e-12, 1e-7}) {
    for (std::uint32_t k = 0; k < leaf.count; ++k) {
      const std::uint32_t c = leafCells_[leaf.first + k];
      const int i = int(c % std::uint32_t(m_)), j = int(c / std::uint32_t(m_));
      const std::size_t v = std::size_t(j) * (m_ + 1) + i;
      const Vec2 corners[4] = {image_[v], image_[v + 1], image_[v + m_ + 2], image_[v + m_ + 1]};
      Vec2 st;
      if (!invertPiece(pieces_[c], corners, y, st, tolerance)) continue;
      double jac = 0.0;
      evaluatePiece(pieces_[c], corners, st, &jac);
      return Point{(Vec2(i, j) + st) / double(m_), jac * double(m_) * double(m_), c};
    }
  }
  return std::nullopt;
}

std::vector<Vec2> untangleQuads(std::vector<Vec2> v, int n) {
  const auto invalidCells = [&](std::vector<char>& bad) {
    bad.assign(std::size_t(n) * n, 0);
    int count = 0;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const std::size_t p = std::size_t(j) * (n + 1) + i;
        if (classifyQuad(v[p], v[p + 1], v[p + n + 2], v[p + n + 1]) != QuadPiece::Invalid) continue;
        bad[std::size_t(j) * n + i] = 1;
        ++count;
      }
    return count;
  };
  std::vector<char> bad;
  std::vector<char> moving(std::size_t(n + 1) * (n + 1));
  for (int sweep = 0; sweep < 200 && invalidCells(bad) > 0; ++sweep) {
    std::fill(moving.begin(), moving.end(), 0);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        if (bad[std::size_t(j) * n + i]) {
          const std::size_t p = std::size_t(j) * (n + 1) + i;
          moving[p] = moving[p + 1] = moving[p + n + 1] = moving[p + n + 2] = 1;
        }
    std::vector<Vec2> next = v;
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        const std::size_t p = std::size_t(j) * (n + 1) + i;
        const bool cornerVertex = (i == 0 || i == n) && (j == 0 || j == n);
        if (!moving[p] || cornerVertex) continue;
        Vec2 sum(0.0);
        int count = 0;
        if (i > 0) sum += v[p - 1], ++count;
        if (i < n) sum += v[p + 1], ++count;
        if (j > 0) sum += v[p - std::size_t(n) - 1], ++count;
        if (j < n) sum += v[p + std::size_t(n) + 1], ++count;
        Vec2 q = 0.5 * v[p] + 0.5 * sum / double(count);
        if (i == 0 || i == n) q.x = v[p].x;  // boundary vertices slide along the boundary only
        if (j == 0 || j == n) q.y = v[p].y;
        next[p] = q;
      }
    v.swap(next);
  }
  return v;
}

QuadGridMap forwardMap(const OtMap& map) {
  return QuadGridMap(map.n, untangleQuads(map.vertices, map.n));
}

QuadGridMap tabulatedInverse(const QuadGridMap& forward, int m) {
  if (m < 1) throw Error("OT inverse map: the grid size must be at least 1");
  std::vector<Vec2> image(std::size_t(m + 1) * (m + 1));
  for (int j = 0; j <= m; ++j)
    for (int i = 0; i <= m; ++i) {
      const Vec2 u(double(i) / m, double(j) / m);
      const auto x = forward.invert(u);
      if (!x)
        throw Error("OT inverse map: no forward quad contains (" + std::to_string(u.x) + ", " +
                    std::to_string(u.y) + "); the forward map does not cover the square");
      Vec2 p = x->p;
      // The forward map takes the boundary onto itself, so the inverse does too: snap off rounding.
      if (i == 0) p.x = 0.0;
      if (i == m) p.x = 1.0;
      if (j == 0) p.y = 0.0;
      if (j == m) p.y = 1.0;
      image[std::size_t(j) * (m + 1) + i] = p;
    }
  return QuadGridMap(m, untangleQuads(std::move(image), m));
}

}  // namespace iblx
