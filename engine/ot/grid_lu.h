// Sparse LU of a matrix with a 3x3 (nine-point) stencil on a rectangular grid of cells, such as the OT
// solver's Newton Jacobian: multifrontal (Duff & Reid, ACM TOMS 9(3), 1983) in the geometric nested-
// dissection order of George (SIAM J. Numer. Anal. 10(2), 1973). The grid's separators are known, so the
// symbolic phase is a recursion over rectangles, and every front is a dense block factored by LAPACK/BLAS.
// The factors are stored in the order the solves read them (one array each, read from start to end).
// Pivoting is partial within each front's fully summed block; a zero pivot there is replaced by a tiny one
// (static pivoting, Li & Demmel, ACM TOMS 29(2), 2003), which the OT solver's GMRES corrects.
// The factorisation runs in single precision and so are its factors (they precondition GMRES, which works in
// double; the right-hand sides and solutions stay double). Constructing a
// GridLu sets OpenBLAS, when that is the BLAS, to one thread for the whole process: the subtrees already run
// on their own threads, and OpenBLAS's idle workers spin.
#pragma once

#include "engine/core/big_buffer.h"

#include <array>
#include <cstddef>
#include <span>
#include <vector>

namespace iblx {

// A width x height cell grid's nine-point matrix: row c = y * width + x holds A(c, c') for the cells c' =
// (x + dx, y + dy), dx, dy in {-1, 0, 1}, at values[c * 9 + (dy + 1) * 3 + (dx + 1)]. Entries that reach
// outside the grid are ignored.
struct StencilMatrix {
  int width = 0, height = 0;
  std::vector<double> values;

  StencilMatrix() = default;
  StencilMatrix(int w, int h) : width(w), height(h), values(std::size_t(w) * h * 9, 0.0) {}
  double& at(int cell, int dx, int dy) { return values[std::size_t(cell) * 9 + (dy + 1) * 3 + (dx + 1)]; }
  double at(int cell, int dx, int dy) const {
    return values[std::size_t(cell) * 9 + (dy + 1) * 3 + (dx + 1)];
  }
  // y = A x.
  void multiply(std::span<const double> x, std::span<double> y) const;
};

class GridLu {
 public:
  // The symbolic phase: the dissection tree and every front's index lists for this grid size. The numeric
  // phases run the subtrees below the top log2(threads) separators on their own threads (threads <= 0: the
  // hardware's).
  GridLu(int width, int height, int threads = 0);

  // Numeric factorisation of a; the pattern is the grid's. Returns the number of pivots that were replaced
  // (0 for a matrix that is not numerically singular within a front).
  int factor(const StencilMatrix& a);
  // x = A^-1 b, in place (b in, x out), with the last factors. Not const: it works in buffers kept from
  // call to call (one GridLu serves one solve at a time).
  void solve(std::span<double> bx);

  bool factored() const { return factored_; }
  // Single-precision entries of the factors.
  std::size_t factorEntries() const { return lower_.size() + upper_.size(); }
  double factorFlops() const { return flops_; }  // of one factorisation

 private:
  struct Node {
    std::array<int, 2> children{-1, -1};
    std::vector<int> vars;  // global cells: the first `own` are eliminated here, the rest are its boundary
    int own = 0;
    // Original entries assembled here: (front row, front column, index into StencilMatrix::values).
    std::vector<std::array<int, 3>> entries;
    // For child k: childMaps_[childMapOffset[k] ..] holds the positions in `vars` of that child's boundary
    // variables, in the child's order (one flat array in postorder, so the solves stream through it).
    std::array<std::size_t, 2> childMapOffset{0, 0};
    std::array<std::size_t, 2> childMapSize{0, 0};
    std::size_t lowerOffset = 0, upperOffset = 0;  // where the node's factors start in lower_ and upper_
    std::size_t pivotOffset = 0;                   // own row interchanges (LAPACK ipiv, 1-based)
    std::size_t maxFront = 0;                      // the largest front size in this subtree
    int subtreeFirst = 0;      // the subtree is nodes_[subtreeFirst .. this node] (nodes_ is in postorder)
    std::size_t ownStart = 0;  // where the own variables start in the elimination order
  };

  // Buffers of one subtree thread, kept between calls (allocating them anew made the kernel clear pages for
  // every factorisation).
  struct Workspace {
    BigBuffer<float> front;     // the frontal matrix (factor)
    BigBuffer<float> updates;   // update matrices waiting for their parent (factor)
    std::vector<double> stack;  // update vectors (forward solve) or boundary solutions (backward solve)
  };

  int build(int x0, int x1, int y0, int y1, std::vector<int>& position, std::vector<std::vector<int>>& maps);
  const int* childMap(const Node& node, int k) const { return childMaps_.data() + node.childMapOffset[k]; }
  // Workspaces are numbered as a heap: slot 0 is the caller's, a split at slot i runs its children on
  // 2i + 1 and 2i + 2.
  Workspace& workspace(std::size_t slot) { return workspaces_[slot]; }
  // Each leaves the node's update over its boundary on top of its workspace's `updates` (factor) or `stack`
  // (solves).
  void factorSubtree(int index, int depth, std::size_t slot, const StencilMatrix& a, int& replaced);
  void factorNode(int index, const StencilMatrix& a, Workspace& work, int& replaced);
  // The solves work on w, the right-hand side in elimination order. The backward pass hands every child its
  // boundary's solution on the stack (a copy from the parent's front) instead of gathering it from w.
  void forwardSubtree(int index, int depth, std::size_t slot, std::span<double> w);
  void forwardNode(int index, std::span<double> w, std::vector<double>& stack) const;
  void backwardSubtree(int index, int depth, std::size_t slot, std::span<double> w);
  void backwardNode(int index, std::span<double> w, std::vector<double>& stack) const;

  int width_, height_, parallelDepth_ = 0;
  std::vector<Node> nodes_;
  std::vector<int> childMaps_;
  std::vector<Workspace> workspaces_;
  std::vector<double> solveOrder_;  // the right-hand side in elimination order
  std::vector<int> order_;          // elimination position -> cell
  int root_ = -1;
  // The factors in the order the solves read them (grid_lu.cpp's lowerSize, upperSize): lower_ for the
  // forward solve, in postorder; upper_ for the backward solve, in reverse postorder.
  BigBuffer<float> lower_, upper_;
  std::vector<int> pivots_;
  double flops_ = 0.0;
  bool factored_ = false;
};

}  // namespace iblx
