// Shared chi-square goodness-of-fit harness for direction samplers, Mitsuba 3 chi2.py style: sample histogram
// vs integrated pdf on the sphere (ires sub-cells, pooling below 5, zero-expected failures, Sidak, dumps).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace iblx::test {

// pdf w.r.t. solid angle of a batch of unit directions (batched so that a GPU probe can evaluate it).
using BatchPdf = std::function<std::vector<double>(std::span<const glm::dvec3>)>;

struct Chi2Options {
  // Cells of the domain (phi in [0, 2pi)) x (cos(theta) in [-1, 1]): equal-area, so every cell has the same
  // solid angle 4pi / (phiCells * cosThetaCells). Odd counts keep cell edges off the map's symmetry lines.
  int phiCells = 51;
  int cosThetaCells = 25;
  // Each cell is integrated by the midpoint rule on ires x ires sub-cells, refined where the pdf jumps: a
  // sub-cell whose pdf differs from one of its 8 neighbours' is split 2x2, recursively, up to
  // `maxRefineDepth` times (0 = the plain midpoint rule). Piecewise-constant pdfs with 1e6 peaks need it: the
  // midpoint rule errs by up to half a sub-cell at every edge. Splitting stops once N * jump * (area of a
  // strip of such sub-cells across one cell) is below `refineTolerance` samples, which bounds the error an
  // edge adds to a cell.
  int ires = 4;
  int maxRefineDepth = 10;
  double refineTolerance = 0.5;
  // Cells expecting fewer samples are pooled (the chi-square approximation needs about 5 per cell).
  double minExpected = 5.0;
  // Significance level alpha of the whole family of `testCount` tests; Sidak correction: each test runs at
  // 1 - (1 - alpha)^(1 / testCount).
  double significance = 0.01;
  int testCount = 1;
  // Names the table file written on failure.
  std::string label = "chi2";
};

struct Chi2Result {
  bool passed = false;
  double pValue = 0.0, statistic = 0.0;
  double pdfIntegral = 0.0;  // integral of the pdf over the sphere (sum of all cell integrals); should be 1
  int degreesOfFreedom = 0;
  std::string message;  // summary; on failure the reason and the path of the dumped tables
};

// Bins `samples` (any length > 0, normalised inside) and compares them with N * (integral of `pdf` per cell).
// Fails outright on a non-finite sample or pdf value and on a sample in a cell whose expected count is 0.
Chi2Result chi2Test(std::span<const glm::dvec3> samples, const BatchPdf& pdf,
                    const Chi2Options& options = {});

// Deterministic uniform points in [0,1)^2 for the u inputs of samplers under test (splitmix64, 53-bit
// doubles; independent of the standard library's distributions, so every platform sees the same points).
std::vector<glm::dvec2> uniformPoints(std::size_t count, std::uint64_t seed);

// Regularised incomplete gamma functions P(a, x) and Q(a, x) = 1 - P(a, x), a > 0, x >= 0.
// Series for x < a + 1, Lentz continued fraction otherwise (Numerical Recipes 3rd ed. §6.2).
double regularizedGammaP(double a, double x);
double regularizedGammaQ(double a, double x);

// Upper tail of the chi-square distribution: Q(dof / 2, statistic / 2).
double chi2PValue(double statistic, int degreesOfFreedom);

}  // namespace iblx::test
