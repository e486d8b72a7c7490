// A 2D density on [0, 1]^2 that interpolates a grid bilinearly, sampled by inverting its continuous marginal
// and conditional CDFs, with an optional linear dependence on parameters (one grid per parameter node). It is
// the warp the RGL-EPFL measured materials are defined with (Dupuy & Jakob 2018, §5; the continuous
// "Marginal2D" of their reference reader): a .bsdf's value depends on the exact inverse of its VNDF warp, so
// this twin follows that definition step by step, in double. The GLSL twin is shaders/lib/bilinear_warp.glsl,
// which reads the tables below (cast to float).
//
// Data layout: slices x height x width, x fastest; parameter 0 varies slowest across slices. A point's x is
// the grid's last axis.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace iblx {

class BilinearWarp2D {
 public:
  BilinearWarp2D() = default;
  // `normalize`: scale each slice so that its interpolant integrates to 1 and build the CDFs (a warp);
  // otherwise the values are kept as they are and only eval() is meaningful (an interpolant). Throws
  // iblx::Error for a grid under 2 x 2, parameter values that are not increasing, or a data size that
  // disagrees; a slice whose integral is not positive and finite is an error too when normalizing (the
  // message names the slice).
  BilinearWarp2D(std::span<const float> data, std::uint32_t width, std::uint32_t height,
                 std::vector<std::vector<double>> paramValues, bool normalize);

  struct Result {
    glm::dvec2 point;  // the warped point (sample) or the uniform point (invert)
    double pdf;        // the density at the warped point, on [0, 1]^2
  };
  // Uniform u in [0, 1]^2 to a point distributed as the interpolant.
  Result sample(glm::dvec2 u, std::span<const double> params) const;
  // The inverse of sample(): the uniform point that sample() maps to pos.
  Result invert(glm::dvec2 pos, std::span<const double> params) const;
  // The interpolant (the density, when normalized) at pos.
  double eval(glm::dvec2 pos, std::span<const double> params) const;

  std::uint32_t width() const { return width_; }
  std::uint32_t height() const { return height_; }
  std::size_t slices() const { return slices_; }
  const std::vector<std::vector<double>>& paramValues() const { return paramValues_; }
  // The tables the GPU reads: values (normalized when a warp), conditional CDFs (per row, in units of grid
  // cells, normalized with the values) and marginal CDFs (per slice, 0 to 1). The CDFs are empty for an
  // interpolant.
  const std::vector<double>& values() const { return values_; }
  const std::vector<double>& conditionalCdf() const { return conditional_; }
  const std::vector<double>& marginalCdf() const { return marginal_; }

 private:
  // The slices around a parameter point and their weights (up to 2^dimensions corners).
  struct Corners {
    std::size_t slice[8];
    double weight[8];
    int count;
  };
  Corners corners(std::span<const double> params) const;
  double lookup(const std::vector<double>& table, std::size_t index, std::size_t sliceSize,
                const Corners& c) const;
  // The four values of the grid cell whose lower corner is node `at`, blended over the slices.
  struct Cell {
    double v00, v10, v01, v11;
  };
  Cell cell(std::size_t at, const Corners& c) const;
  // The cell of a point of [0, 1]^2 (clamped) and the point's position in it.
  struct Located {
    std::uint32_t col, row;
    double tx, ty;
  };
  Located locate(glm::dvec2 pos) const;

  std::uint32_t width_ = 0, height_ = 0;
  std::size_t slices_ = 0;
  std::vector<std::vector<double>> paramValues_;
  std::vector<double> values_, conditional_, marginal_;
};

}  // namespace iblx
