// Piecewise-constant 1D and 2D distributions: table construction in double, sampling, pdf and inversion.
#include "engine/sampling/piecewise_constant.h"

#include "engine/core/error.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace iblx {
namespace {

// Largest double below 1: keeps sampled coordinates inside [0,1).
constexpr double kOneMinusEpsilonD = 1.0 - 0x1p-53;

}  // namespace

PiecewiseConstant1D::PiecewiseConstant1D(std::span<const double> values)
    : func_(values.begin(), values.end()), cdf_(values.size() + 1) {
  const std::size_t n = func_.size();
  if (n == 0) throw Error("PiecewiseConstant1D: the function table is empty");
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(func_[i]) || func_[i] < 0.0)
      throw Error("PiecewiseConstant1D: value " + std::to_string(func_[i]) + " at index " +
                  std::to_string(i) + " is negative or not finite");
  }
  // cdf[i+1] = cdf[i] + f[i] / n, then normalise by the integral.
  cdf_[0] = 0.0;
  for (std::size_t i = 0; i < n; ++i) cdf_[i + 1] = cdf_[i] + func_[i] / double(n);
  integral_ = cdf_[n];
  if (integral_ == 0.0) {
    for (std::size_t i = 1; i <= n; ++i) cdf_[i] = double(i) / double(n);
  } else {
    for (std::size_t i = 1; i <= n; ++i) cdf_[i] /= integral_;
  }
  cdf_[n] = 1.0;
}

PiecewiseConstant1D::Sample PiecewiseConstant1D::sample(double u) const {
  const int n = size();
  u = std::clamp(u, 0.0, kOneMinusEpsilonD);
  // Find bin o with cdf[o] <= u < cdf[o+1]; the last such o skips zero-width bins.
  const auto first = cdf_.begin(), last = cdf_.begin() + n;
  const int o = int(std::upper_bound(first, last, u) - first) - 1;
  // Compute offset du of u inside the bin.
  const double width = cdf_[o + 1] - cdf_[o];
  const double du = width > 0.0 ? std::clamp((u - cdf_[o]) / width, 0.0, kOneMinusEpsilonD) : 0.0;
  Sample s;
  s.bin = o;
  s.x = std::min((o + du) / n, kOneMinusEpsilonD);
  s.pdf = integral_ > 0.0 ? func_[o] / integral_ : 1.0;
  return s;
}

double PiecewiseConstant1D::pdf(double x) const {
  if (!(x >= 0.0 && x < 1.0)) return 0.0;
  if (integral_ == 0.0) return 1.0;
  const int o = std::min(int(x * size()), size() - 1);
  return func_[o] / integral_;
}

std::optional<double> PiecewiseConstant1D::invert(double x) const {
  if (!(x >= 0.0 && x < 1.0)) return std::nullopt;
  const int n = size();
  const int o = std::min(int(x * n), n - 1);
  if (integral_ > 0.0 && func_[o] == 0.0) return std::nullopt;
  // u = lerp(delta, cdf[o], cdf[o+1]) with delta the position of x inside the bin.
  const double delta = x * n - o;
  return std::clamp(cdf_[o] + delta * (cdf_[o + 1] - cdf_[o]), 0.0, kOneMinusEpsilonD);
}

namespace {

std::vector<PiecewiseConstant1D> buildConditionals(std::span<const double> values, int nu, int nv) {
  if (nu <= 0 || nv <= 0 || values.size() != std::size_t(nu) * std::size_t(nv))
    throw Error("PiecewiseConstant2D: expected " + std::to_string(nu) + " x " + std::to_string(nv) +
                " values, got " + std::to_string(values.size()));
  std::vector<PiecewiseConstant1D> rows;
  rows.reserve(std::size_t(nv));
  for (int v = 0; v < nv; ++v)
    rows.emplace_back(values.subspan(std::size_t(v) * std::size_t(nu), std::size_t(nu)));
  return rows;
}

std::vector<double> rowIntegrals(const std::vector<PiecewiseConstant1D>& rows) {
  std::vector<double> integrals;
  integrals.reserve(rows.size());
  for (const auto& r : rows) integrals.push_back(r.integral());
  return integrals;
}

}  // namespace

PiecewiseConstant2D::PiecewiseConstant2D(std::span<const double> values, int nu, int nv)
    : conditional_(buildConditionals(values, nu, nv)), marginal_(rowIntegrals(conditional_)) {}

PiecewiseConstant2D::Sample PiecewiseConstant2D::sample(glm::dvec2 u) const {
  const auto row = marginal_.sample(u.y);
  const auto col = conditional_[std::size_t(row.bin)].sample(u.x);
  return {{col.x, row.x}, row.pdf * col.pdf, {col.bin, row.bin}};
}

double PiecewiseConstant2D::pdf(glm::dvec2 p) const {
  if (!(p.x >= 0.0 && p.x < 1.0 && p.y >= 0.0 && p.y < 1.0)) return 0.0;
  const int nv = marginal_.size();
  const int v = std::min(int(p.y * nv), nv - 1);
  return marginal_.pdf(p.y) * conditional_[std::size_t(v)].pdf(p.x);
}

std::optional<glm::dvec2> PiecewiseConstant2D::invert(glm::dvec2 p) const {
  const auto uy = marginal_.invert(p.y);
  if (!uy) return std::nullopt;
  const int nv = marginal_.size();
  const int v = std::min(int(p.y * nv), nv - 1);
  const auto ux = conditional_[std::size_t(v)].invert(p.x);
  if (!ux) return std::nullopt;
  return glm::dvec2(*ux, *uy);
}

}  // namespace iblx
