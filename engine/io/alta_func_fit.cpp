// The rational fit of ALTA function files (alta_func_fit.h).
#include "engine/io/alta_func_fit.h"

#include "engine/core/error.h"
#include "engine/core/least_squares.h"
#include "engine/io/alta_func_eval.h"

#include <algorithm>
#include <cmath>

namespace iblx {
namespace {

// Every degree vector of total degree <= n in dims dimensions, by total degree.
std::vector<std::vector<int>> monomials(int dims, int n) {
  std::vector<std::vector<int>> out;
  for (int total = 0; total <= n; ++total) {
    std::vector<int> d(std::size_t(dims), 0);
    // Enumerate compositions of `total` into dims parts.
    const auto rec = [&](auto&& self, int k, int left) -> void {
      if (k == dims - 1) {
        d[std::size_t(k)] = left;
        out.push_back(d);
        return;
      }
      for (int v = left; v >= 0; --v) {
        d[std::size_t(k)] = v;
        self(self, k + 1, left - v);
      }
    };
    rec(rec, 0, total);
  }
  return out;
}

}  // namespace

AltaFitResult fitAltaRational(int dimX, std::span<const double> x, std::span<const std::vector<double>> y,
                              std::span<const double> min, std::span<const double> max, int degreeP,
                              int degreeQ) {
  if (dimX < 1 || x.size() % std::size_t(dimX) != 0 || y.empty())
    throw Error("fitAltaRational: inconsistent sample arrays");
  const std::size_t n = x.size() / std::size_t(dimX);
  const auto pTerms = monomials(dimX, degreeP), qTerms = monomials(dimX, degreeQ);
  // Basis values at every sample, on the box mapped to [-1, 1].
  std::vector<double> xs(x.size());
  for (std::size_t s = 0; s < n; ++s)
    for (int k = 0; k < dimX; ++k) {
      const std::size_t i = s * std::size_t(dimX) + std::size_t(k);
      xs[i] = altaBoxCoordinate(x[i], min[std::size_t(k)], max[std::size_t(k)]);
    }
  const auto basisAt = [&](const std::vector<int>& d, std::size_t s) {
    return altaTermBasis(AltaBasis::Chebyshev, d,
                         std::span<const double>(xs).subspan(s * std::size_t(dimX), std::size_t(dimX)));
  };
  AltaFitResult result;
  result.rational.min.assign(min.begin(), min.end());
  result.rational.max.assign(max.begin(), max.end());
  double squared = 0.0;
  std::size_t counted = 0;
  for (const std::vector<double>& values : y) {
    double mean = 0.0;
    for (double v : values) mean += v;
    mean /= double(n);
    const double floor = 0.01 * mean + 1e-12;
    AltaRationalChannel channel;
    for (const bool rational : {true, false}) {
      const std::size_t qCount = rational ? qTerms.size() - 1 : 0, cols = pTerms.size() + qCount;
      // Rows: w (P(x) - y Q'(x)) = w y, plus a light ridge (1e-9 of each column's scale) against rank loss.
      std::vector<double> a((n + cols) * cols, 0.0), b(n + cols, 0.0), scale(cols, 0.0);
      for (std::size_t s = 0; s < n; ++s) {
        const double w = 1.0 / (std::max(values[s], 0.0) + floor);
        for (std::size_t t = 0; t < pTerms.size(); ++t) a[s * cols + t] = w * basisAt(pTerms[t], s);
        for (std::size_t t = 0; t < qCount; ++t)
          a[s * cols + pTerms.size() + t] = -w * values[s] * basisAt(qTerms[t + 1], s);
        b[s] = w * values[s];
      }
      for (std::size_t c = 0; c < cols; ++c) {
        for (std::size_t s = 0; s < n; ++s) scale[c] += a[s * cols + c] * a[s * cols + c];
        scale[c] = scale[c] > 0.0 ? std::sqrt(scale[c]) : 1.0;
        for (std::size_t s = 0; s < n; ++s) a[s * cols + c] /= scale[c];
        a[(n + c) * cols + c] = 1e-9;
      }
      std::vector<double> coef = leastSquares(std::move(a), std::move(b), n + cols, cols);
      for (std::size_t c = 0; c < cols; ++c) coef[c] /= scale[c];
      channel.p.clear();
      channel.q.clear();
      for (std::size_t t = 0; t < pTerms.size(); ++t) channel.p.push_back({pTerms[t], coef[t]});
      channel.q.push_back({qTerms[0], 1.0});
      for (std::size_t t = 0; t < qCount; ++t) channel.q.push_back({qTerms[t + 1], coef[pTerms.size() + t]});
      // A Q that is not positive at a sample has a pole inside the data: use the polynomial instead.
      bool positive = true;
      for (std::size_t s = 0; s < n && positive; ++s) {
        double q = 0.0;
        for (const AltaTerm& t : channel.q) q += t.coefficient * basisAt(t.degrees, s);
        positive = q > 1e-6;
      }
      if (positive) break;
    }
    for (std::size_t s = 0; s < n; ++s) {
      double p = 0.0, q = 0.0;
      for (const AltaTerm& t : channel.p) p += t.coefficient * basisAt(t.degrees, s);
      for (const AltaTerm& t : channel.q) q += t.coefficient * basisAt(t.degrees, s);
      const double fit = q != 0.0 ? p / q : 0.0, r = values[s];
      squared += (fit - r) * (fit - r) / (r * r + 0.01);
      ++counted;
    }
    result.rational.channels.push_back(std::move(channel));
  }
  result.rmsRelative = std::sqrt(squared / double(std::max<std::size_t>(counted, 1)));
  return result;
}

}  // namespace iblx
