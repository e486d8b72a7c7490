// Householder QR least squares (least_squares.h).
#include "engine/core/least_squares.h"

#include <cmath>

namespace iblx {

std::vector<double> leastSquares(std::vector<double> a, std::vector<double> b, std::size_t rows,
                                 std::size_t cols) {
  for (std::size_t k = 0; k < cols; ++k) {
    double norm = 0.0;
    for (std::size_t r = k; r < rows; ++r) norm += a[r * cols + k] * a[r * cols + k];
    norm = std::sqrt(norm);
    if (norm == 0.0) continue;
    const double alpha = a[k * cols + k] > 0.0 ? -norm : norm;
    std::vector<double> v(rows - k);
    for (std::size_t r = k; r < rows; ++r) v[r - k] = a[r * cols + k];
    v[0] -= alpha;
    double vv = 0.0;
    for (double e : v) vv += e * e;
    if (vv == 0.0) continue;
    for (std::size_t c = k; c < cols; ++c) {
      double s = 0.0;
      for (std::size_t r = k; r < rows; ++r) s += v[r - k] * a[r * cols + c];
      s = 2.0 * s / vv;
      for (std::size_t r = k; r < rows; ++r) a[r * cols + c] -= s * v[r - k];
    }
    double s = 0.0;
    for (std::size_t r = k; r < rows; ++r) s += v[r - k] * b[r];
    s = 2.0 * s / vv;
    for (std::size_t r = k; r < rows; ++r) b[r] -= s * v[r - k];
  }
  std::vector<double> x(cols, 0.0);
  for (std::size_t k = cols; k-- > 0;) {
    double s = b[k];
    for (std::size_t c = k + 1; c < cols; ++c) s -= a[k * cols + c] * x[c];
    const double d = a[k * cols + k];
    x[k] = d != 0.0 ? s / d : 0.0;
  }
  return x;
}

}  // namespace iblx
