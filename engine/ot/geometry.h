// Plane geometry shared by the OT solver and its quad maps: the 2D cross product and the strict convexity of
// a grid quad, which decides both whether a solved map folds and how a quad map inverts a cell.
#pragma once

#include <glm/glm.hpp>

namespace iblx {

// a.x b.y - a.y b.x: twice the signed area of the triangle (0, a, b), positive counter-clockwise.
inline double cross2(glm::dvec2 a, glm::dvec2 b) {
  return a.x * b.y - a.y * b.x;
}

// Whether the quad p00, p10, p11, p01 (counter-clockwise in a grid) is strictly convex: at every corner the
// cross product (next - corner) x (previous - corner) is positive.
inline bool strictlyConvexQuad(glm::dvec2 p00, glm::dvec2 p10, glm::dvec2 p11, glm::dvec2 p01) {
  return cross2(p10 - p00, p01 - p00) > 0.0 && cross2(p11 - p10, p00 - p10) > 0.0 &&
         cross2(p01 - p11, p10 - p11) > 0.0 && cross2(p00 - p01, p11 - p01) > 0.0;
}

}  // namespace iblx
