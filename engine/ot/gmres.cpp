// GMRES with right preconditioning and row weights (gmres.h): Arnoldi by modified Gram-Schmidt, the
// Hessenberg least-squares problem by Givens rotations (Saad & Schultz 1986).
#include "engine/ot/gmres.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace iblx {

namespace {

double dot(std::span<const double> a, std::span<const double> b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

// ||W a||^2.
double weightedNormSquared(std::span<const double> a, std::span<const double> w) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) s += a[i] * w[i] * a[i] * w[i];
  return s;
}

}  // namespace

Gmres::Result Gmres::solve(const LinearMap& apply, const LinearMap& precondition, std::span<const double> b,
                           std::span<const double> rowWeights, int maxSteps, double tolerance,
                           std::span<double> x) {
  const int m = maxSteps;
  const std::size_t size = b.size();
  basis_.resize(std::size_t(m + 1));
  preconditioned_.resize(std::size_t(m));
  basis_[0].resize(size);
  unweighted_.resize(size);
  // H is (m + 1) x m upper Hessenberg; cs, sn the Givens rotations applied to it; g the rotated W b.
  std::vector<double> h(std::size_t((m + 1) * m), 0.0), cs(static_cast<std::size_t>(m)),
      sn(static_cast<std::size_t>(m)), g(std::size_t(m + 1), 0.0);
  const auto H = [&](int row, int col) -> double& { return h[std::size_t(row * m + col)]; };
  const double beta0 = std::sqrt(weightedNormSquared(b, rowWeights));
  Result result;
  if (!(beta0 > 0.0)) {
    std::fill(x.begin(), x.end(), 0.0);
    return result;
  }
  for (std::size_t c = 0; c < size; ++c) basis_[0][c] = b[c] * rowWeights[c] / beta0;
  g[0] = beta0;
  int k = 0;
  for (; k < m; ++k) {
    preconditioned_[std::size_t(k)].resize(size), basis_[std::size_t(k + 1)].resize(size);
    // z_k = M W^-1 v_k: the preconditioner approximates A^-1, so it sees the unweighted vector.
    const std::vector<double>& v = basis_[std::size_t(k)];
    for (std::size_t c = 0; c < size; ++c) unweighted_[c] = v[c] / rowWeights[c];
    precondition(unweighted_, preconditioned_[std::size_t(k)]);
    ++result.steps;
    apply(preconditioned_[std::size_t(k)], basis_[std::size_t(k + 1)]);
    auto& w = basis_[std::size_t(k + 1)];
    for (std::size_t c = 0; c < size; ++c) w[c] *= rowWeights[c];
    for (int i = 0; i <= k; ++i) {  // modified Gram-Schmidt
      const double hik = dot(w, basis_[std::size_t(i)]);
      H(i, k) = hik;
      for (std::size_t c = 0; c < size; ++c) w[c] -= hik * basis_[std::size_t(i)][c];
    }
    const double norm = std::sqrt(dot(w, w));
    H(k + 1, k) = norm;
    for (int i = 0; i < k; ++i) {  // the previous Givens rotations
      const double a = H(i, k), bb = H(i + 1, k);
      H(i, k) = cs[std::size_t(i)] * a + sn[std::size_t(i)] * bb;
      H(i + 1, k) = -sn[std::size_t(i)] * a + cs[std::size_t(i)] * bb;
    }
    const double a = H(k, k), bb = H(k + 1, k), rr = std::hypot(a, bb);
    cs[std::size_t(k)] = rr > 0.0 ? a / rr : 1.0, sn[std::size_t(k)] = rr > 0.0 ? bb / rr : 0.0;
    H(k, k) = rr, H(k + 1, k) = 0.0;
    g[std::size_t(k + 1)] = -sn[std::size_t(k)] * g[std::size_t(k)];
    g[std::size_t(k)] = cs[std::size_t(k)] * g[std::size_t(k)];
    if (!(norm > 1e-300)) {  // happy breakdown: the Krylov space holds the solution
      ++k;
      break;
    }
    for (double& value : w) value /= norm;
    if (std::abs(g[std::size_t(k + 1)]) <= tolerance * beta0) {
      ++k;
      break;
    }
  }
  // y = R^-1 g by back substitution (R the rotated H's upper triangle), x = Z y.
  std::vector<double> y(std::size_t(k), 0.0);
  for (int i = k - 1; i >= 0; --i) {
    double s = g[std::size_t(i)];
    for (int j = i + 1; j < k; ++j) s -= H(i, j) * y[std::size_t(j)];
    y[std::size_t(i)] = H(i, i) != 0.0 ? s / H(i, i) : 0.0;
  }
  std::fill(x.begin(), x.end(), 0.0);
  for (int i = 0; i < k; ++i)
    for (std::size_t c = 0; c < size; ++c) x[c] += y[std::size_t(i)] * preconditioned_[std::size_t(i)][c];
  result.relativeResidual = std::abs(g[std::size_t(k)]) / beta0;
  return result;
}

}  // namespace iblx
