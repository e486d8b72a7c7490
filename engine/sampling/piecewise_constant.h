// Piecewise-constant 1D and 2D distributions on [0,1) and [0,1)^2 (CPU, double): sample, pdf and invert.
#pragma once

#include <glm/glm.hpp>

#include <optional>
#include <span>
#include <vector>

namespace iblx {

// Density proportional to a step function with n equal bins on [0,1); the CDF is accumulated in double.
// Zero bins are never sampled; an all-zero function becomes the uniform density (pdf 1 everywhere).
// pbrt-v4 PiecewiseConstant1D (src/pbrt/util/sampling.h), on the fixed domain [0,1).
class PiecewiseConstant1D {
 public:
  struct Sample {
    double x = 0.0;    // in [0,1)
    double pdf = 0.0;  // density w.r.t. x of the bin actually chosen
    int bin = 0;
  };

  // Throws iblx::Error on an empty table or on a negative or non-finite value.
  explicit PiecewiseConstant1D(std::span<const double> values);

  // x = (bin + (u - cdf[bin]) / (cdf[bin+1] - cdf[bin])) / n, with bin the last index where cdf[bin] <= u.
  Sample sample(double u) const;
  // Density w.r.t. x: f(x) / integral(); 0 outside [0,1).
  double pdf(double x) const;
  // The u with sample(u).x == x; empty outside [0,1) and inside a zero bin.
  std::optional<double> invert(double x) const;

  // Integral of the step function over [0,1): sum(values) / n (0 for an all-zero function).
  double integral() const { return integral_; }
  int size() const { return int(func_.size()); }
  double func(int bin) const { return func_[bin]; }
  std::span<const double> cdf() const { return cdf_; }

 private:
  std::vector<double> func_;
  std::vector<double> cdf_;  // n + 1 entries, cdf_[0] = 0, cdf_[n] = 1
  double integral_ = 0.0;
};

// Density proportional to a step function on an nu x nv grid over [0,1)^2: a marginal over rows (v) and one
// conditional per row (u). Continuous in u.x within a row, discontinuous across rows.
// pbrt-v4 PiecewiseConstant2D (src/pbrt/util/sampling.h).
class PiecewiseConstant2D {
 public:
  struct Sample {
    glm::dvec2 p{0.0};  // in [0,1)^2; p.x along a row, p.y across rows
    double pdf = 0.0;   // density w.r.t. area on [0,1)^2
    glm::ivec2 bin{0};  // (column, row)
  };

  // values: nv rows of nu entries, row-major. Throws iblx::Error on a size mismatch or a bad value.
  PiecewiseConstant2D(std::span<const double> values, int nu, int nv);

  // u.y picks the row from the marginal, u.x the column from that row's conditional.
  Sample sample(glm::dvec2 u) const;
  // marginal pdf(p.y) * conditional pdf(p.x) = f(p) / integral() (uniform for an all-zero function).
  double pdf(glm::dvec2 p) const;
  std::optional<glm::dvec2> invert(glm::dvec2 p) const;

  double integral() const { return marginal_.integral(); }

 private:
  std::vector<PiecewiseConstant1D> conditional_;
  PiecewiseConstant1D marginal_;
};

}  // namespace iblx
