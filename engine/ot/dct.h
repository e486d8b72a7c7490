// Fast discrete cosine transforms on n x n grids, for the OT solver's fixed pseudo-Laplacian: its clamped
// (reflecting) boundary makes it diagonal in the DCT-II basis, so one solve is two 2-D transforms,
// O(n^2 log n).
#pragma once

#include <complex>
#include <functional>
#include <span>
#include <vector>

namespace iblx {

// Row transforms of a row-major n x n array of doubles. Powers of two use Makhoul's n-point FFT algorithm
// (IEEE TASSP 28(1), 1980) with two real rows packed into one complex FFT; other n use the O(n^2) definition.
class DctPlan {
 public:
  explicit DctPlan(int n);
  int size() const { return n_; }

  // Unnormalised DCT-II of every row, in place: X_k = sum_i x_i cos(pi k (2i+1) / (2n)).
  void forwardRows(std::span<double> a, int threads) const;
  // Exact inverse of forwardRows (a DCT-III scaled by 1/n, X_0 weighted 1/2), in place.
  void inverseRows(std::span<double> a, int threads) const;

 private:
  void fft(std::complex<double>* z, bool inverse) const;
  void transformRows(std::span<double> a, int threads, bool inverse) const;
  void forwardPair(double* x0, double* x1, std::complex<double>* z) const;
  void inversePair(double* x0, double* x1, std::complex<double>* z) const;

  int n_ = 0;
  bool pow2_ = false;
  std::vector<std::complex<double>> twiddle_;  // e^{-2 pi i k / n}, k < n/2
  std::vector<std::complex<double>> shift_;    // e^{-i pi k / (2n)}, k < n
  std::vector<int> bitReverse_;
  std::vector<double> cosTable_;  // cos(pi k (2i+1) / (2n)) at [k*n+i], only for n not a power of two
};

// Transposes a row-major n x n array in place (blocked for the cache).
void transposeSquare(std::span<double> a, int n);

// Runs fn(begin, end) over [0, count) split into at most `threads` contiguous chunks, one std::jthread each
// beyond the first; small ranges run inline. threads <= 0 means std::thread::hardware_concurrency().
void parallelChunks(int threads, int count, int minChunk, const std::function<void(int, int)>& fn);

}  // namespace iblx
