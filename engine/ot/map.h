// The maps the OT techniques evaluate: a grid of (m+1)^2 image vertices over the unit square, one piece per
// cell, with point location in the image by a quadtree. env-ot-fwd uses the solver's forward map (density
// square -> uniform square) and inverts it per sample; env-ot-inv uses the tabulated inverse (uniform square
// -> density square) and inverts it only for the pdf of a given direction (a sun sample's, or MIS's).
// shaders/lib/quad_grid_map.glsl is the GPU twin.
//
// A piece is the cell's bilinear patch when its quad is strictly convex (then the patch is injective: its
// Jacobian determinant is bilinear in (s, t) and positive at the four corners). A non-convex quad of positive
// area is split into two affine triangles along the diagonal through its reflex corner, which keeps the map a
// continuous bijection (edges stay straight in both cases) with an exact, piecewise-constant Jacobian. A quad
// for which neither split gives two positive triangles is `Invalid`: the map is not injective there.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace iblx {

struct OtMap;

enum class QuadPiece : std::uint8_t {
  Bilinear = 0,
  SplitMainDiagonal = 1,  // triangles (00, 10, 11) for s >= t and (00, 11, 01) for s < t
  SplitAntiDiagonal = 2,  // triangles (00, 10, 01) for s + t <= 1 and (10, 11, 01) for s + t > 1
  Invalid = 3,
};

// Chooses the piece of the quad p00, p10, p11, p01 (counter-clockwise when unfolded).
QuadPiece classifyQuad(glm::dvec2 p00, glm::dvec2 p10, glm::dvec2 p11, glm::dvec2 p01);

// Quadtree over the image square: a node covers a square; an interior node has 4 children (x-major: child
// c covers quadrant (c & 1, c >> 1)); a leaf lists the cells whose image bounding box overlaps it.
struct QuadTreeNode {
  std::uint32_t first = 0;  // interior: index of child 0 (children are consecutive); leaf: first list entry
  std::uint32_t count = 0;  // 0xffffffff for an interior node; else the leaf's list length
};
inline constexpr std::uint32_t kQuadTreeInterior = 0xffffffffu;

class QuadGridMap {
 public:
  // image: (m+1)^2 vertices, row-major j*(m+1)+i, the image of domain vertex (i/m, j/m).
  QuadGridMap(int m, std::vector<glm::dvec2> image, int leafCapacity = 8, int maxDepth = 14);

  struct Point {
    glm::dvec2 p;        // the mapped point
    double jacobian;     // det of d(image)/d(domain) at the domain point (domain cell side 1/m)
    std::uint32_t cell;  // the cell (domain) the point lies in
  };
  // Domain point -> image point. x outside [0,1]^2 is clamped.
  Point apply(glm::dvec2 x) const;
  // Image point -> domain point (jacobian as for apply at the result); nothing if no piece contains y.
  std::optional<Point> invert(glm::dvec2 y) const;

  int size() const { return m_; }
  std::span<const glm::dvec2> image() const { return image_; }
  std::span<const QuadPiece> pieces() const { return pieces_; }
  std::span<const QuadTreeNode> nodes() const { return nodes_; }
  std::span<const std::uint32_t> leafCells() const { return leafCells_; }
  int invalidPieces() const { return invalid_; }
  int treeDepth() const { return depth_; }
  std::uint32_t largestLeaf() const { return largestLeaf_; }

 private:
  int m_;
  std::vector<glm::dvec2> image_;
  std::vector<QuadPiece> pieces_;
  std::vector<QuadTreeNode> nodes_;
  std::vector<std::uint32_t> leafCells_;
  int invalid_ = 0, depth_ = 0;
  std::uint32_t largestLeaf_ = 0;
};

// Local coordinates (s, t) in [0,1]^2 of the cell piece -> image point and the local Jacobian determinant.
glm::dvec2 evaluatePiece(QuadPiece piece, const glm::dvec2 corners[4], glm::dvec2 st, double* localJacobian);
// Inverse of evaluatePiece for an image point; false if it lies outside the piece (beyond `tolerance` in
// local coordinates).
bool invertPiece(QuadPiece piece, const glm::dvec2 corners[4], glm::dvec2 y, glm::dvec2& st,
                 double tolerance = 1e-9);

// Makes every quad of a vertex grid triangulable (no Invalid piece) by local smoothing: each sweep moves the
// vertices of the Invalid quads half-way to the mean of their 4 grid neighbours (boundary vertices along the
// boundary), until none is left or 200 sweeps. The solver's map can hold self-intersecting quads of positive
// signed area next to a sun (a twist its area equations do not see); the samplers need an injective map, and
// their pdfs stay exact because they come from the untangled map, at the cost of a small mass error there.
std::vector<glm::dvec2> untangleQuads(std::vector<glm::dvec2> vertices, int n);
// The solver's forward map, untangled, as a QuadGridMap (domain = lat-long parameter square, image = uniform
// square).
QuadGridMap forwardMap(const OtMap& map);
// The tabulated inverse: the forward map inverted at the (m+1)^2 vertices of the uniform square's grid
// (domain = uniform square, image = lat-long parameter square).
QuadGridMap tabulatedInverse(const QuadGridMap& forward, int m);

}  // namespace iblx
