// Bilinear 2D warp with parameters (bilinear_warp.h). Each step cites the continuous inversion it implements:
// within a grid cell the row integral and the interpolated row are linear, so each CDF is quadratic there and
// is inverted in closed form.
#include "engine/sampling/bilinear_warp.h"

#include "engine/core/error.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace iblx {
namespace {

// The largest i in [0, size - 2] with before(i) true, for a predicate that is true up to some index; 0 when
// it is false everywhere.
template <typename Before>
std::uint32_t findInterval(std::uint32_t size, Before before) {
  std::uint32_t lo = 0, hi = size - 2;  // before(lo) is assumed; the answer lies in [lo, hi]
  while (lo < hi) {
    const std::uint32_t mid = (lo + hi + 1) / 2;
    if (before(mid))
      lo = mid;
    else
      hi = mid - 1;
  }
  return lo;
}

double safeSqrt(double x) {
  return std::sqrt(std::max(x, 0.0));
}

// t in [0, 1] with integral_0^t ((1 - s) a + s b) ds = y (a, b >= 0): the root of the quadratic,
// (a - sqrt(D)) / (a - b) with D = a^2 - 2 y (a - b), in the form without cancellation, 2 y / (a + sqrt(D)),
// which also covers a = b.
double invertLinear(double y, double a, double b) {
  const double d = a + safeSqrt(a * a - 2.0 * y * (a - b));
  return d > 0.0 ? std::clamp(2.0 * y / d, 0.0, 1.0) : 0.0;
}

}  // namespace

BilinearWarp2D::BilinearWarp2D(std::span<const float> data, std::uint32_t width, std::uint32_t height,
                               std::vector<std::vector<double>> paramValues, bool normalize)
    : width_(width), height_(height), paramValues_(std::move(paramValues)) {
  if (width < 2 || height < 2)
    throw Error("a bilinear warp needs a grid of at least 2 x 2 values, not " + std::to_string(width) +
                " x " + std::to_string(height));
  if (paramValues_.size() > 3) throw Error("a bilinear warp takes at most 3 parameters");
  slices_ = 1;
  for (const std::vector<double>& values : paramValues_) {
    if (values.empty()) throw Error("a bilinear warp's parameter has no values");
    for (std::size_t k = 1; k < values.size(); ++k)
      if (!(values[k] > values[k - 1]))
        throw Error("a bilinear warp's parameter values must increase, but value " + std::to_string(k) +
                    " is " + std::to_string(values[k]) + " after " + std::to_string(values[k - 1]));
    slices_ *= values.size();
  }
  const std::size_t sliceSize = std::size_t(width) * height;
  if (data.size() != slices_ * sliceSize)
    throw Error("a bilinear warp of " + std::to_string(slices_) + " slices of " + std::to_string(width) +
                " x " + std::to_string(height) + " needs " + std::to_string(slices_ * sliceSize) +
                " values, not " + std::to_string(data.size()));
  values_.assign(data.begin(), data.end());
  if (!normalize) return;

  conditional_.assign(values_.size(), 0.0);
  marginal_.assign(slices_ * height, 0.0);
  for (std::size_t slice = 0; slice < slices_; ++slice) {
    double* v = values_.data() + slice * sliceSize;
    double* cond = conditional_.data() + slice * sliceSize;
    double* marg = marginal_.data() + slice * height;
    // Trapezoid sums are the exact integrals of the linear interpolant along rows and of the row integrals.
    for (std::uint32_t y = 0; y < height; ++y) {
      const std::size_t row = std::size_t(y) * width;
      for (std::uint32_t x = 0; x + 1 < width; ++x)
        cond[row + x + 1] = cond[row + x] + 0.5 * (v[row + x] + v[row + x + 1]);
    }
    for (std::uint32_t y = 0; y + 1 < height; ++y)
      marg[y + 1] =
          marg[y] + 0.5 * (cond[(y + 1) * std::size_t(width) - 1] + cond[(y + 2) * std::size_t(width) - 1]);
    const double total = marg[height - 1];
    if (!(total > 0.0) || !std::isfinite(total))
      throw Error("slice " + std::to_string(slice) + " of a bilinear warp integrates to " +
                  std::to_string(total) + ", so it cannot be sampled");
    for (std::size_t i = 0; i < sliceSize; ++i) v[i] /= total, cond[i] /= total;
    for (std::uint32_t y = 0; y < height; ++y) marg[y] /= total;
  }
}

BilinearWarp2D::Corners BilinearWarp2D::corners(std::span<const double> params) const {
  Corners c{};
  c.slice[0] = 0, c.weight[0] = 1.0, c.count = 1;
  std::size_t stride = 1;
  // The last parameter varies fastest across slices.
  for (std::size_t d = paramValues_.size(); d-- > 0;) {
    const std::vector<double>& values = paramValues_[d];
    const auto n = std::uint32_t(values.size());
    if (n > 1) {
      const double p = params[d];
      const std::uint32_t i = findInterval(n, [&](std::uint32_t k) { return values[k] < p; });
      const double w1 = std::clamp((p - values[i]) / (values[i + 1] - values[i]), 0.0, 1.0);
      for (int k = 0; k < c.count; ++k) {
        c.slice[c.count + k] = c.slice[k] + stride * (i + 1);
        c.weight[c.count + k] = c.weight[k] * w1;
        c.slice[k] += stride * i;
        c.weight[k] *= 1.0 - w1;
      }
      c.count *= 2;
    }
    stride *= n;
  }
  return c;
}

double BilinearWarp2D::lookup(const std::vector<double>& table, std::size_t index, std::size_t sliceSize,
                              const Corners& c) const {
  double v = 0.0;
  for (int k = 0; k < c.count; ++k) v += c.weight[k] * table[c.slice[k] * sliceSize + index];
  return v;
}

BilinearWarp2D::Cell BilinearWarp2D::cell(std::size_t at, const Corners& c) const {
  const std::size_t w = width_, sliceSize = std::size_t(width_) * height_;
  return {lookup(values_, at, sliceSize, c), lookup(values_, at + 1, sliceSize, c),
          lookup(values_, at + w, sliceSize, c), lookup(values_, at + w + 1, sliceSize, c)};
}

BilinearWarp2D::Located BilinearWarp2D::locate(glm::dvec2 pos) const {
  pos = glm::clamp(pos, glm::dvec2(0.0), glm::dvec2(1.0)) * glm::dvec2(width_ - 1.0, height_ - 1.0);
  const auto col = std::min(std::uint32_t(pos.x), width_ - 2),
             row = std::min(std::uint32_t(pos.y), height_ - 2);
  return {col, row, pos.x - col, pos.y - row};
}

BilinearWarp2D::Result BilinearWarp2D::sample(glm::dvec2 u, std::span<const double> params) const {
  const Corners c = corners(params);
  const std::size_t w = width_, sliceSize = std::size_t(width_) * height_;
  u = glm::clamp(u, glm::dvec2(1e-12), glm::dvec2(1.0 - 1e-12));
  // Row: the marginal CDF is piecewise quadratic in y.
  const auto marginal = [&](std::uint32_t y) { return lookup(marginal_, y, height_, c); };
  const std::uint32_t row = findInterval(height_, [&](std::uint32_t y) { return marginal(y) < u.y; });
  const double r0 = lookup(conditional_, row * w + w - 1, sliceSize, c);
  const double r1 = lookup(conditional_, (row + 1) * w + w - 1, sliceSize, c);
  const double ty = invertLinear(u.y - marginal(row), r0, r1);
  // Column: the conditional CDF of the interpolated row is piecewise quadratic in x.
  const double target = u.x * ((1.0 - ty) * r0 + ty * r1);
  const auto conditional = [&](std::uint32_t x) {
    return (1.0 - ty) * lookup(conditional_, row * w + x, sliceSize, c) +
           ty * lookup(conditional_, (row + 1) * w + x, sliceSize, c);
  };
  const std::uint32_t col = findInterval(width_, [&](std::uint32_t x) { return conditional(x) < target; });
  const Cell v = cell(row * w + col, c);
  const double c0 = (1.0 - ty) * v.v00 + ty * v.v01, c1 = (1.0 - ty) * v.v10 + ty * v.v11;
  const double tx = invertLinear(target - conditional(col), c0, c1);
  return {glm::dvec2((col + tx) / (width_ - 1.0), (row + ty) / (height_ - 1.0)),
          ((1.0 - tx) * c0 + tx * c1) * (width_ - 1.0) * (height_ - 1.0)};
}

BilinearWarp2D::Result BilinearWarp2D::invert(glm::dvec2 pos, std::span<const double> params) const {
  const Corners c = corners(params);
  const std::size_t w = width_, sliceSize = std::size_t(width_) * height_;
  const auto [col, row, tx, ty] = locate(pos);
  const std::size_t at = row * w + col;
  const Cell v = cell(at, c);
  const double c0 = (1.0 - ty) * v.v00 + ty * v.v01, c1 = (1.0 - ty) * v.v10 + ty * v.v11;
  const double pdf = (1.0 - tx) * c0 + tx * c1;
  const double r0 = lookup(conditional_, row * w + w - 1, sliceSize, c);
  const double r1 = lookup(conditional_, (row + 1) * w + w - 1, sliceSize, c);
  const double rowIntegral = (1.0 - ty) * r0 + ty * r1;
  const double x = tx * (c0 + 0.5 * tx * (c1 - c0)) + (1.0 - ty) * lookup(conditional_, at, sliceSize, c) +
                   ty * lookup(conditional_, at + w, sliceSize, c);
  const double y = ty * (r0 + 0.5 * ty * (r1 - r0)) + lookup(marginal_, row, height_, c);
  return {glm::dvec2(rowIntegral > 0.0 ? x / rowIntegral : 0.0, y), pdf * (width_ - 1.0) * (height_ - 1.0)};
}

double BilinearWarp2D::eval(glm::dvec2 pos, std::span<const double> params) const {
  const auto [col, row, tx, ty] = locate(pos);
  const Cell k = cell(std::size_t(row) * width_ + col, corners(params));
  const double v = (1.0 - ty) * ((1.0 - tx) * k.v00 + tx * k.v10) + ty * ((1.0 - tx) * k.v01 + tx * k.v11);
  // A warp's values are normalized per grid cell; as a density on [0, 1]^2 they scale by the cell count.
  return conditional_.empty() ? v : v * (width_ - 1.0) * (height_ - 1.0);
}

}  // namespace iblx
