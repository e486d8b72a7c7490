// Dense linear least squares by Householder QR (Golub & Van Loan, "Matrix Computations", 4th ed., §5.3.3), in
// double: the x minimising |A x - b| for A with rows x cols entries, row-major (rows >= cols). A column that
// is zero after the reflections gets x = 0.
#pragma once

#include <cstddef>
#include <vector>

namespace iblx {

std::vector<double> leastSquares(std::vector<double> a, std::vector<double> b, std::size_t rows,
                                 std::size_t cols);

}  // namespace iblx
