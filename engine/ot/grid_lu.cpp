// The nested-dissection multifrontal LU of grid_lu.h.
#include "engine/ot/grid_lu.h"

#include "engine/core/error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <thread>

// OpenBLAS's CBLAS (libopenblas-dev) and LAPACK's C prototypes (lapack.h, liblapacke-dev); OpenBLAS
// implements both (CMakeLists.txt finds it as the LAPACK vendor). Single precision: see factorNode.
#include <cblas.h>
#include <lapack.h>

namespace iblx {

namespace {

// OpenBLAS's worker threads spin-wait (sched_yield) between calls, so beside the OT solver's own threads they
// take CPU time that the solver's threads need (perf). The fronts are mostly small and the subtrees already
// run on their own threads, so BLAS runs single-threaded.
void useSingleThreadedBlas() {
  static std::once_flag once;
  std::call_once(once, [] { openblas_set_num_threads(1); });
}

// A matrix entry, inverted pivot or solve multiplier in single precision, clamped to its range (an entry
// beyond it, or the inverse of a near-zero pivot that LAPACK kept, must not become an infinity).
float toFactor(double value) {
  constexpr double kMax = std::numeric_limits<float>::max();
  return float(std::min(std::max(value, -kMax), kMax));
}

// The solves' inner loop: y -= c0 x0 + c1 x1 + c2 x2 + c3 x3 over `count` entries, four factor columns in one
// pass over y. Blocked so that y is read and written once per four columns rather than once per column; an
// AVX2 + FMA clone of these loops (GCC target_clones) gained nothing measurable, so they stay portable. The
// four products are summed in single precision (the factors are single already), and only y is double:
// twice the SIMD width for the products, while the residual of one solve on the test matrix only went from
// 6.5e-4 to 6.9e-4 (docs/ot_solver.md, "The LU of the Jacobian" and "Tried and dropped").
inline void subtractColumns(double* __restrict y, std::size_t count, const float* __restrict c0,
                            const float* __restrict c1, const float* __restrict c2,
                            const float* __restrict c3, double x0, double x1, double x2, double x3) {
  const float f0 = toFactor(x0), f1 = toFactor(x1), f2 = toFactor(x2), f3 = toFactor(x3);
  for (std::size_t i = 0; i < count; ++i)
    y[i] -= double((c0[i] * f0 + c1[i] * f1) + (c2[i] * f2 + c3[i] * f3));
}

inline void subtractColumn(double* __restrict y, std::size_t count, const float* __restrict c, double x) {
  for (std::size_t i = 0; i < count; ++i) y[i] -= c[i] * x;
}

// The solves' layout of a front's factors (s own variables, m = s + b front variables, blocks of four columns
// as the solves take them). Each solve reads its array once, from start to end: at n = 1024 most of a solve's
// time went to the 129 000 fronts of at most 16 own variables, which read the column-major panel [L11\U11;
// L21] in short strided pieces, forward for one solve and backward (by columns, in reverse) for the other,
// and so waited on memory (perf: cache misses on the first factor load of each piece).
//
// lower (forward solve), for each block j = 0, 4, ... (j + 4 <= s): L11's six entries below the diagonal in
// the block's 4 x 4 triangle, in the order (1,0) (2,0) (2,1) (3,0) (3,1) (3,2), then the four columns' rows
// j + 4 .. m - 1 one column after the other; then for each remaining column j its rows j + 1 .. m - 1.
std::size_t lowerSize(std::size_t m, std::size_t s) {
  std::size_t size = 0, j = 0;
  for (; j + 4 <= s; j += 4) size += 6 + 4 * (m - j - 4);
  for (; j < s; ++j) size += m - j - 1;
  return size;
}

// upper (backward solve): U12 (s x b, column-major; the backward solve subtracts U12 x_boundary first), then
// for each block from the last (columns top .. top + 3, top = s - 4, s - 8, ... >= 0): the ten entries of its
// 4 x 4 upper triangle in the order (3,3) (2,3) (2,2) (1,3) (1,2) (1,1) (0,3) (0,2) (0,1) (0,0), diagonal
// entries inverted (the solve multiplies), then the four columns' rows 0 .. top - 1 one column after the
// other; then for each remaining column j (s mod 4 of them, from the last) its inverted diagonal and its rows
// 0 .. j - 1.
std::size_t upperSize(std::size_t m, std::size_t s) {
  std::size_t size = s * (m - s), j = s;
  for (; j >= 4; j -= 4) size += 10 + 4 * (j - 4);
  while (j-- > 0) size += 1 + j;
  return size;
}

// Subdomains of at most this many cells are eliminated whole, as one dense front (their separators would
// be fronts of a few variables each, where BLAS calls cost more than the arithmetic).
constexpr int kLeafCells = 16;

}  // namespace

void StencilMatrix::multiply(std::span<const double> x, std::span<double> y) const {
  for (int cy = 0; cy < height; ++cy)
    for (int cx = 0; cx < width; ++cx) {
      const int c = cy * width + cx;
      double sum = 0.0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = cx + dx, ny = cy + dy;
          if (nx >= 0 && nx < width && ny >= 0 && ny < height)
            sum += at(c, dx, dy) * x[std::size_t(ny) * width + nx];
        }
      y[std::size_t(c)] = sum;
    }
}

GridLu::GridLu(int width, int height, int threads) : width_(width), height_(height) {
  IBLX_ASSERT(width > 0 && height > 0);
  useSingleThreadedBlas();
  const int workers = threads > 0 ? threads : int(std::max(1u, std::thread::hardware_concurrency()));
  while ((1 << parallelDepth_) < std::min(workers, 16)) ++parallelDepth_;  // at most 16 subtrees
  std::vector<int> position(std::size_t(width) * height, -1);
  std::vector<std::vector<int>> maps;  // per node and child (2 node + k), flattened into childMaps_ below
  root_ = build(0, width, 0, height, position, maps);
  // build() appends a node after its subtree, so nodes_ is in postorder and a subtree is the index range
  // [subtreeFirst, node]. The elimination order (the fronts' own variables), the pivots and lower_ follow the
  // same order; upper_ follows the reverse one (the backward solve's), set below.
  std::size_t lower = 0, upper = 0, pivots = 0;
  for (Node& node : nodes_) {
    const std::size_t m = node.vars.size(), s = std::size_t(node.own), b = m - s;
    node.lowerOffset = lower, lower += lowerSize(m, s);
    upper += upperSize(m, s);
    node.upperOffset = upper;  // for now the end of the node's block; reversed below
    node.pivotOffset = pivots, pivots += s;
    node.maxFront = m;
    for (int child : node.children)
      if (child >= 0) node.maxFront = std::max(node.maxFront, nodes_[std::size_t(child)].maxFront);
    flops_ += 2.0 / 3.0 * double(s) * s * s + 2.0 * double(s) * s * b + 2.0 * double(s) * b * b;
    node.ownStart = order_.size();
    order_.insert(order_.end(), node.vars.begin(), node.vars.begin() + node.own);
    const std::size_t index = std::size_t(&node - nodes_.data());
    for (std::size_t k = 0; k < 2; ++k) {
      const std::vector<int>& map = maps[2 * index + k];
      node.childMapOffset[k] = childMaps_.size(), node.childMapSize[k] = map.size();
      childMaps_.insert(childMaps_.end(), map.begin(), map.end());
    }
  }
  // upper_ in reverse postorder: the node whose block ends last in postorder starts at 0.
  for (Node& node : nodes_) node.upperOffset = upper - node.upperOffset;
  workspaces_.resize((std::size_t(2) << parallelDepth_) - 1);
  lower_.resize(lower);  // every entry is written by factor()
  upper_.resize(upper);
  pivots_.assign(pivots, 0);
}

int GridLu::build(int x0, int x1, int y0, int y1, std::vector<int>& position,
                  std::vector<std::vector<int>>& maps) {
  const int w = x1 - x0, h = y1 - y0;
  Node node;
  node.subtreeFirst = int(nodes_.size());
  int sx0 = x0, sx1 = x1, sy0 = y0, sy1 = y1;  // the cells eliminated at this node
  if (w * h > kLeafCells) {
    // Separator: the middle line across the longer side; each half is a child.
    if (w >= h) {
      const int xs = x0 + w / 2;
      node.children = {build(x0, xs, y0, y1, position, maps), build(xs + 1, x1, y0, y1, position, maps)};
      sx0 = xs, sx1 = xs + 1;
    } else {
      const int ys = y0 + h / 2;
      node.children = {build(x0, x1, y0, ys, position, maps), build(x0, x1, ys + 1, y1, position, maps)};
      sy0 = ys, sy1 = ys + 1;
    }
  }
  for (int y = sy0; y < sy1; ++y)
    for (int x = sx0; x < sx1; ++x) node.vars.push_back(y * width_ + x);
  node.own = int(node.vars.size());
  // Boundary: the ring of cells around the domain, all on ancestors' separators (nested dissection).
  for (int y = std::max(y0 - 1, 0); y <= std::min(y1, height_ - 1); ++y)
    for (int x = std::max(x0 - 1, 0); x <= std::min(x1, width_ - 1); ++x)
      if (x < x0 || x >= x1 || y < y0 || y >= y1) node.vars.push_back(y * width_ + x);
  for (std::size_t k = 0; k < node.vars.size(); ++k) position[std::size_t(node.vars[k])] = int(k);
  std::array<std::vector<int>, 2> childMaps;
  for (int k = 0; k < 2; ++k) {
    if (node.children[std::size_t(k)] < 0) continue;
    const Node& child = nodes_[std::size_t(node.children[std::size_t(k)])];
    for (std::size_t q = std::size_t(child.own); q < child.vars.size(); ++q) {
      const int at = position[std::size_t(child.vars[q])];
      IBLX_ASSERT(at >= 0);
      childMaps[std::size_t(k)].push_back(at);
    }
  }
  // Original entries: A(v, w) and A(w, v) for own v and every neighbour w not eliminated below this node.
  for (int lv = 0; lv < node.own; ++lv) {
    const int v = node.vars[std::size_t(lv)], vx = v % width_, vy = v / width_;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int nx = vx + dx, ny = vy + dy;
        if (nx < 0 || nx >= width_ || ny < 0 || ny >= height_) continue;
        const int wcell = ny * width_ + nx, lw = position[std::size_t(wcell)];
        const bool inDomain = nx >= x0 && nx < x1 && ny >= y0 && ny < y1;
        if (inDomain && lw < 0) continue;  // eliminated in a child (the domain's other cells are own)
        node.entries.push_back({lv, lw, v * 9 + (dy + 1) * 3 + (dx + 1)});
        if (!inDomain) node.entries.push_back({lw, lv, wcell * 9 + (1 - dy) * 3 + (1 - dx)});
      }
  }
  for (int cell : node.vars) position[std::size_t(cell)] = -1;
  nodes_.push_back(std::move(node));
  maps.push_back(std::move(childMaps[0])), maps.push_back(std::move(childMaps[1]));
  return int(nodes_.size()) - 1;
}

int GridLu::factor(const StencilMatrix& a) {
  IBLX_ASSERT(a.width == width_ && a.height == height_);
  int replaced = 0;
  for (Workspace& work : workspaces_) work.updates.clear();
  factorSubtree(root_, parallelDepth_, 0, a, replaced);
  workspace(0).updates.clear();  // the root has no boundary, so no update
  factored_ = true;
  return replaced;
}

void GridLu::factorSubtree(int index, int depth, std::size_t slot, const StencilMatrix& a, int& replaced) {
  const Node& node = nodes_[std::size_t(index)];
  Workspace& work = workspace(slot);
  if (depth > 0 && node.children[0] >= 0 && node.children[1] >= 0) {
    // The two halves on two threads, each with its own workspace; their updates then go on this stack in
    // order.
    int replacedOther = 0;
    {
      std::jthread other([&] { factorSubtree(node.children[0], depth - 1, 2 * slot + 1, a, replacedOther); });
      factorSubtree(node.children[1], depth - 1, 2 * slot + 2, a, replaced);
    }
    replaced += replacedOther;
    for (std::size_t child : {2 * slot + 1, 2 * slot + 2}) {
      BigBuffer<float>& part = workspace(child).updates;
      work.updates.insert(work.updates.end(), part.begin(), part.end());
      part.clear();
    }
    factorNode(index, a, work, replaced);
    return;
  }
  // One thread for the whole subtree, in postorder, in a front buffer sized once for its largest front.
  if (work.front.size() < node.maxFront * node.maxFront) work.front.resize(node.maxFront * node.maxFront);
  for (int k = node.subtreeFirst; k <= index; ++k) factorNode(k, a, work, replaced);
}

// One front in single precision (sgetrf, strsm, sgemm), the matrix's double entries rounded on assembly. The
// factors were stored in single precision already; computing them so, rather than in double, halves the
// memory the update matrices move and doubles the BLAS's vector width. It is safe because the factors only
// precondition GMRES, which works in double: a solve's residual on the random test matrix went from 3e-4 to
// 6e-4 (512) and 6e-4 to 1.2e-3 (1024), and the OT solver took the same Newton iterations on every
// benchmark map at n = 512 (docs/ot_solver.md, "The LU of the Jacobian" and "Tried and dropped").
void GridLu::factorNode(int index, const StencilMatrix& a, Workspace& work, int& replaced) {
  const Node& node = nodes_[std::size_t(index)];
  const int m = int(node.vars.size()), s = node.own, b = m - s;
  const std::size_t mm = std::size_t(m);
  BigBuffer<float>& front = work.front;
  BigBuffer<float>& stack = work.updates;
  if (front.size() < mm * mm) front.resize(mm * mm);
  std::fill_n(front.begin(), mm * mm, 0.0f);
  for (const auto& [row, col, value] : node.entries)
    front[std::size_t(col) * mm + std::size_t(row)] += toFactor(a.values[std::size_t(value)]);
  // Extend-add the children's update matrices, the second child's on top of the stack.
  for (int k = 1; k >= 0; --k) {
    if (node.children[std::size_t(k)] < 0) continue;
    const int* map = childMap(node, k);
    const std::size_t bc = node.childMapSize[std::size_t(k)], base = stack.size() - bc * bc;
    for (std::size_t q = 0; q < bc; ++q) {
      float* column = front.data() + std::size_t(map[q]) * mm;
      const float* update = stack.data() + base + q * bc;
      for (std::size_t p = 0; p < bc; ++p) column[map[p]] += update[p];
    }
    stack.resize(base);
  }
  int* ipiv = pivots_.data() + node.pivotOffset;
  int info = 0;
  LAPACK_sgetrf(&s, &s, front.data(), &m, ipiv, &info);
  if (info != 0) {
    // Exact zero pivots (LAPACK left their columns unscaled, i.e. zero below the diagonal).
    float scale = 0.0f;
    for (int j = 0; j < s; ++j)
      for (int i = 0; i < s; ++i)
        scale = std::max(scale, std::abs(front[std::size_t(j) * mm + std::size_t(i)]));
    const float tiny = scale > 0.0f && std::isfinite(scale) ? std::max(1e-12f * scale, 1e-30f) : 1.0f;
    for (int i = 0; i < s; ++i) {
      float& pivot = front[std::size_t(i) * mm + std::size_t(i)];
      if (pivot == 0.0f || !std::isfinite(pivot)) pivot = tiny, ++replaced;
    }
  }
  float* u12 = front.data() + std::size_t(s) * mm;  // column q of U12 at u12 + q m
  if (b > 0) {
    const int first = 1, inc = 1;
    float* l21 = front.data() + s;
    LAPACK_slaswp(&b, u12, &m, &first, &s, ipiv, &inc);
    cblas_strsm(CblasColMajor, CblasLeft, CblasLower, CblasNoTrans, CblasUnit, s, b, 1.0f, front.data(), m,
                u12,
                m);  // U12 = L11^-1 P F12
    cblas_strsm(CblasColMajor, CblasRight, CblasUpper, CblasNoTrans, CblasNonUnit, b, s, 1.0f, front.data(),
                m, l21, m);  // L21 = F21 U11^-1
    const std::size_t base = stack.size();
    stack.resize(base + std::size_t(b) * b);
    float* update = stack.data() + base;
    for (int q = 0; q < b; ++q) std::copy_n(u12 + std::size_t(q) * mm + s, b, update + std::size_t(q) * b);
    cblas_sgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, b, b, s, -1.0f, l21, m, u12, m, 1.0f, update,
                b);  // F22 - L21 U12
  }
  // The factors in the solves' layouts (lowerSize, upperSize).
  const std::size_t own = std::size_t(s);
  const auto column = [&](std::size_t j) { return front.data() + j * mm; };
  const auto inverted = [](float pivot) { return toFactor(1.0 / double(pivot)); };
  float* lower = lower_.data() + node.lowerOffset;
  std::size_t j = 0;
  for (; j + 4 <= own; j += 4) {
    const float *c0 = column(j), *c1 = column(j + 1), *c2 = column(j + 2);
    for (float entry : {c0[j + 1], c0[j + 2], c1[j + 2], c0[j + 3], c1[j + 3], c2[j + 3]}) *lower++ = entry;
    for (std::size_t k = 0; k < 4; ++k) lower = std::copy(column(j + k) + j + 4, column(j + k) + mm, lower);
  }
  for (; j < own; ++j) lower = std::copy(column(j) + j + 1, column(j) + mm, lower);
  float* upper = upper_.data() + node.upperOffset;
  for (std::size_t q = 0; q < std::size_t(b); ++q) upper = std::copy_n(u12 + q * mm, own, upper);
  for (j = own; j >= 4; j -= 4) {
    const std::size_t top = j - 4;
    const float *c0 = column(top), *c1 = column(top + 1), *c2 = column(top + 2), *c3 = column(top + 3);
    for (float entry : {inverted(c3[top + 3]), c3[top + 2], inverted(c2[top + 2]), c3[top + 1], c2[top + 1],
                        inverted(c1[top + 1]), c3[top], c2[top], c1[top], inverted(c0[top])})
      *upper++ = entry;
    for (std::size_t k = 0; k < 4; ++k) upper = std::copy_n(column(top + k), top, upper);
  }
  while (j-- > 0) {
    *upper++ = inverted(column(j)[j]);
    upper = std::copy_n(column(j), j, upper);
  }
}

void GridLu::solve(std::span<double> bx) {
  IBLX_ASSERT(factored_ && bx.size() == std::size_t(width_) * height_);
  // In elimination order every front's own entries are contiguous (a separator column of cells would
  // otherwise cost a cache line per entry).
  std::vector<double>& w = solveOrder_;
  w.resize(bx.size());
  for (std::size_t p = 0; p < w.size(); ++p) w[p] = bx[std::size_t(order_[p])];
  for (Workspace& work : workspaces_) work.stack.clear();
  forwardSubtree(root_, parallelDepth_, 0, w);
  workspace(0).stack.clear();  // the root's (empty) update; its boundary is empty too
  backwardSubtree(root_, parallelDepth_, 0, w);
  for (std::size_t p = 0; p < w.size(); ++p) bx[std::size_t(order_[p])] = w[p];
}

// L y = P b, multifrontal: each front takes its children's update vectors and passes -L21 y up, so that
// subtrees never write to shared entries.
void GridLu::forwardSubtree(int index, int depth, std::size_t slot, std::span<double> w) {
  const Node& node = nodes_[std::size_t(index)];
  std::vector<double>& stack = workspace(slot).stack;
  if (depth > 0 && node.children[0] >= 0 && node.children[1] >= 0) {
    {
      std::jthread other([&] { forwardSubtree(node.children[0], depth - 1, 2 * slot + 1, w); });
      forwardSubtree(node.children[1], depth - 1, 2 * slot + 2, w);
    }
    for (std::size_t child : {2 * slot + 1, 2 * slot + 2}) {
      std::vector<double>& part = workspace(child).stack;
      stack.insert(stack.end(), part.begin(), part.end());
      part.clear();
    }
    forwardNode(index, w, stack);
    return;
  }
  for (int k = node.subtreeFirst; k <= index; ++k) forwardNode(k, w, stack);
}

void GridLu::forwardNode(int index, std::span<double> w, std::vector<double>& stack) const {
  const Node& node = nodes_[std::size_t(index)];
  const std::size_t m = node.vars.size(), s = std::size_t(node.own), b = m - s;
  double* own = w.data() + node.ownStart;
  // The boundary's accumulated updates go above the children's on the stack, which stay valid until added.
  const std::size_t base = stack.size();
  stack.resize(base + b, 0.0);
  double* boundary = stack.data() + base;
  std::size_t below = base;
  for (int k = 1; k >= 0; --k) {
    if (node.children[std::size_t(k)] < 0) continue;
    const int* map = childMap(node, k);
    const std::size_t size = node.childMapSize[std::size_t(k)];
    below -= size;
    for (std::size_t p = 0; p < size; ++p) {
      const std::size_t at = std::size_t(map[p]);
      (at < s ? own[at] : boundary[at - s]) += stack[below + p];
    }
  }
  const int* ipiv = pivots_.data() + node.pivotOffset;
  for (std::size_t i = 0; i < s; ++i) std::swap(own[i], own[std::size_t(ipiv[i] - 1)]);
  // [L11; L21] four columns at a time, in lowerSize's layout: their 4 x 4 unit-lower triangle first, then
  // the rows below it (own, then boundary).
  const float* lower = lower_.data() + node.lowerOffset;
  std::size_t j = 0;
  for (; j + 4 <= s; j += 4) {
    const float* t = lower;
    const double y0 = own[j];
    const double y1 = own[j + 1] -= t[0] * y0;
    const double y2 = own[j + 2] -= t[1] * y0 + t[2] * y1;
    const double y3 = own[j + 3] -= t[3] * y0 + t[4] * y1 + t[5] * y2;
    const std::size_t rest = j + 4, rows = m - rest, ownRows = s - rest;
    const float *c0 = lower + 6, *c1 = c0 + rows, *c2 = c1 + rows, *c3 = c2 + rows;
    subtractColumns(own + rest, ownRows, c0, c1, c2, c3, y0, y1, y2, y3);
    subtractColumns(boundary, b, c0 + ownRows, c1 + ownRows, c2 + ownRows, c3 + ownRows, y0, y1, y2, y3);
    lower = c3 + rows;
  }
  for (; j < s; ++j) {
    const std::size_t ownRows = s - j - 1;
    subtractColumn(own + j + 1, ownRows, lower, own[j]);
    subtractColumn(boundary, b, lower + ownRows, own[j]);
    lower += m - j - 1;
  }
  // Pop the children's updates; this node's update takes their place.
  std::copy_n(boundary, b, stack.data() + below);
  stack.resize(below + b);
}

// U x = y, parents before children (reverse postorder). A node finds its boundary's x on top of the stack,
// solves for its own and pushes each child's boundary x, the second child's last (it is solved first).
void GridLu::backwardSubtree(int index, int depth, std::size_t slot, std::span<double> w) {
  const Node& node = nodes_[std::size_t(index)];
  std::vector<double>& stack = workspace(slot).stack;
  if (depth > 0 && node.children[0] >= 0 && node.children[1] >= 0) {
    backwardNode(index, w, stack);
    // The children's boundary x, pushed in order, move to their own workspaces.
    const std::size_t second = node.childMapSize[1], first = node.childMapSize[0];
    std::vector<double>& stack1 = workspace(2 * slot + 2).stack;
    std::vector<double>& stack0 = workspace(2 * slot + 1).stack;
    stack1.assign(stack.end() - std::ptrdiff_t(second), stack.end());
    stack0.assign(stack.end() - std::ptrdiff_t(second + first), stack.end() - std::ptrdiff_t(second));
    stack.resize(stack.size() - first - second);
    std::jthread other([&] { backwardSubtree(node.children[0], depth - 1, 2 * slot + 1, w); });
    backwardSubtree(node.children[1], depth - 1, 2 * slot + 2, w);
    return;
  }
  for (int k = index; k >= node.subtreeFirst; --k) backwardNode(k, w, stack);
}

void GridLu::backwardNode(int index, std::span<double> w, std::vector<double>& stack) const {
  const Node& node = nodes_[std::size_t(index)];
  const std::size_t m = node.vars.size(), s = std::size_t(node.own), b = m - s;
  double* own = w.data() + node.ownStart;
  const float* upper = upper_.data() + node.upperOffset;  // in upperSize's layout
  const std::size_t base = stack.size() - b;              // this node's boundary x, pushed by its parent
  const auto boundaryX = [&](std::size_t q) { return stack[base + q]; };
  std::size_t q = 0;
  for (; q + 4 <= b; q += 4) {
    const float* c0 = upper + q * s;
    subtractColumns(own, s, c0, c0 + s, c0 + 2 * s, c0 + 3 * s, boundaryX(q), boundaryX(q + 1),
                    boundaryX(q + 2), boundaryX(q + 3));
  }
  for (; q < b; ++q) subtractColumn(own, s, upper + q * s, boundaryX(q));
  upper += s * b;
  // U11, four columns at a time from the last: their 4 x 4 upper triangle (inverted diagonal), then the rows
  // above it.
  std::size_t j = s;
  for (; j >= 4; j -= 4) {
    const std::size_t top = j - 4;
    const float* t = upper;
    const double x3 = own[top + 3] *= t[0];
    const double x2 = (own[top + 2] -= t[1] * x3) *= t[2];
    const double x1 = (own[top + 1] -= t[3] * x3 + t[4] * x2) *= t[5];
    const double x0 = (own[top] -= t[6] * x3 + t[7] * x2 + t[8] * x1) *= t[9];
    const float *c0 = upper + 10, *c1 = c0 + top, *c2 = c1 + top, *c3 = c2 + top;
    subtractColumns(own, top, c0, c1, c2, c3, x0, x1, x2, x3);
    upper = c3 + top;
  }
  while (j-- > 0) {
    const double x = own[j] *= upper[0];  // the inverted diagonal
    subtractColumn(own, j, upper + 1, x);
    upper += 1 + j;
  }
  // Pop this node's boundary and push the children's, the second child's on top: the front's x is own
  // (in w) then boundary (on the stack), and a child's map indexes it.
  const std::size_t sizes[2] = {node.childMapSize[0], node.childMapSize[1]};
  const std::size_t top = base + b;
  stack.resize(top + sizes[0] + sizes[1]);
  double* out = stack.data() + top;
  for (int k = 0; k < 2; ++k) {
    const int* map = childMap(node, k);
    for (std::size_t p = 0; p < sizes[k]; ++p) {
      const std::size_t at = std::size_t(map[p]);
      *out++ = at < s ? own[at] : stack[base + at - s];
    }
  }
  std::copy(stack.begin() + std::ptrdiff_t(top), stack.end(), stack.begin() + std::ptrdiff_t(base));
  stack.resize(base + sizes[0] + sizes[1]);
}

}  // namespace iblx
