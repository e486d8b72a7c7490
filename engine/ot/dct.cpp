// Fast DCT-II / DCT-III rows for the OT solver (see dct.h), a blocked transpose and a chunked parallel
// loop.
#include "engine/ot/dct.h"

#include "engine/core/error.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>
#include <thread>

namespace iblx {

void parallelChunks(int threads, int count, int minChunk, const std::function<void(int, int)>& fn) {
  if (threads <= 0) threads = int(std::max(1u, std::thread::hardware_concurrency()));
  const int chunks = std::clamp(count / std::max(minChunk, 1), 1, threads);
  if (chunks <= 1) {
    if (count > 0) fn(0, count);
    return;
  }
  std::vector<std::jthread> workers;
  workers.reserve(std::size_t(chunks - 1));
  const auto bound = [&](int c) { return int(std::int64_t(count) * c / chunks); };
  for (int c = 1; c < chunks; ++c)
    workers.emplace_back([&fn, lo = bound(c), hi = bound(c + 1)] { fn(lo, hi); });
  fn(0, bound(1));
}  // the jthreads join here

void transposeSquare(std::span<double> a, int n) {
  constexpr int kBlock = 32;
  for (int bi = 0; bi < n; bi += kBlock)
    for (int bj = bi; bj < n; bj += kBlock)
      for (int i = bi; i < std::min(bi + kBlock, n); ++i)
        for (int j = std::max(bj, i + 1); j < std::min(bj + kBlock, n); ++j)
          std::swap(a[std::size_t(i) * n + j], a[std::size_t(j) * n + i]);
}

DctPlan::DctPlan(int n) : n_(n), pow2_(n >= 2 && std::has_single_bit(unsigned(n))) {
  IBLX_ASSERT(n >= 1);
  const double pi = std::numbers::pi;
  if (pow2_) {
    twiddle_.resize(std::size_t(n / 2));
    for (int k = 0; k < n / 2; ++k) twiddle_[std::size_t(k)] = std::polar(1.0, -2.0 * pi * k / n);
    shift_.resize(std::size_t(n));
    for (int k = 0; k < n; ++k) shift_[std::size_t(k)] = std::polar(1.0, -pi * k / (2.0 * n));
    bitReverse_.resize(std::size_t(n));
    const int bits = std::countr_zero(unsigned(n));
    for (int i = 0; i < n; ++i) {
      int r = 0;
      for (int b = 0; b < bits; ++b) r |= ((i >> b) & 1) << (bits - 1 - b);
      bitReverse_[std::size_t(i)] = r;
    }
  } else {
    cosTable_.resize(std::size_t(n) * n);
    for (int k = 0; k < n; ++k)
      for (int i = 0; i < n; ++i)
        cosTable_[std::size_t(k) * n + i] = std::cos(pi * k * (2.0 * i + 1.0) / (2.0 * n));
  }
}

// Iterative radix-2 Cooley-Tukey; the inverse is unscaled (callers divide by n).
void DctPlan::fft(std::complex<double>* z, bool inverse) const {
  const int n = n_;
  for (int i = 0; i < n; ++i) {
    const int r = bitReverse_[std::size_t(i)];
    if (r > i) std::swap(z[i], z[r]);
  }
  for (int len = 2; len <= n; len <<= 1) {
    const int half = len / 2, step = n / len;
    for (int s = 0; s < n; s += len)
      for (int k = 0; k < half; ++k) {
        std::complex<double> w = twiddle_[std::size_t(k * step)];
        if (inverse) w = std::conj(w);
        const std::complex<double> u = z[s + k], v = z[s + k + half] * w;
        z[s + k] = u + v;
        z[s + k + half] = u - v;
      }
  }
}

// Makhoul: v = (x_0, x_2, ..., x_3, x_1); X_k = Re(e^{-i pi k/(2n)} FFT(v)_k). Two rows share one FFT.
void DctPlan::forwardPair(double* x0, double* x1, std::complex<double>* z) const {
  const int n = n_, h = n / 2;
  for (int i = 0; i < h; ++i) {
    z[i] = {x0[2 * i], x1[2 * i]};
    z[n - 1 - i] = {x0[2 * i + 1], x1[2 * i + 1]};
  }
  fft(z, false);
  for (int k = 0; k < n; ++k) {
    const std::complex<double> a = z[k], b = std::conj(z[(n - k) % n]);
    const std::complex<double> v0 = 0.5 * (a + b), v1 = std::complex<double>(0.0, -0.5) * (a - b);
    x0[k] = (shift_[std::size_t(k)] * v0).real();
    x1[k] = (shift_[std::size_t(k)] * v1).real();
  }
}

// Inverse of forwardPair: V_k = e^{i pi k/(2n)} (X_k - i X_{n-k}), v = IFFT(V), then undo the permutation.
void DctPlan::inversePair(double* x0, double* x1, std::complex<double>* z) const {
  const int n = n_, h = n / 2;
  for (int k = 0; k < n; ++k) {
    const std::complex<double> s = std::conj(shift_[std::size_t(k)]);
    const std::complex<double> v0 = s * std::complex<double>(x0[k], k ? -x0[n - k] : 0.0);
    const std::complex<double> v1 = s * std::complex<double>(x1[k], k ? -x1[n - k] : 0.0);
    z[k] = v0 + std::complex<double>(0.0, 1.0) * v1;  // both spectra are Hermitian: one inverse FFT
  }
  fft(z, true);
  const double scale = 1.0 / n;
  for (int i = 0; i < h; ++i) {
    x0[2 * i] = z[i].real() * scale, x1[2 * i] = z[i].imag() * scale;
    x0[2 * i + 1] = z[n - 1 - i].real() * scale, x1[2 * i + 1] = z[n - 1 - i].imag() * scale;
  }
}

// Both directions share the row pairing: two real rows go through one complex FFT.
void DctPlan::transformRows(std::span<double> a, int threads, bool inverse) const {
  const int n = n_;
  IBLX_ASSERT(a.size() == std::size_t(n) * n);
  if (n == 1) return;
  parallelChunks(threads, (n + 1) / 2, 16, [&](int lo, int hi) {
    std::vector<std::complex<double>> z(static_cast<std::size_t>(n));
    std::vector<double> tmp(static_cast<std::size_t>(n)), spare(static_cast<std::size_t>(n), 0.0);
    for (int p = lo; p < hi; ++p) {
      double* r0 = &a[std::size_t(2 * p) * n];
      double* r1 = 2 * p + 1 < n ? &a[std::size_t(2 * p + 1) * n] : spare.data();
      if (pow2_) {
        inverse ? inversePair(r0, r1, z.data()) : forwardPair(r0, r1, z.data());
        continue;
      }
      for (double* r : {r0, r1}) {
        if (inverse) {
          // x_i = (1/n) (X_0 + 2 sum_{k>=1} X_k cos(pi k (2i+1)/(2n))), the DCT-III inverse of DCT-II.
          std::fill(tmp.begin(), tmp.end(), 0.0);
          for (int k = 0; k < n; ++k) {
            const double w = (k ? 2.0 : 1.0) * r[k] / n;
            const double* c = &cosTable_[std::size_t(k) * n];
            for (int i = 0; i < n; ++i) tmp[std::size_t(i)] += w * c[i];
          }
        } else {
          for (int k = 0; k < n; ++k) {
            double s = 0.0;
            const double* c = &cosTable_[std::size_t(k) * n];
            for (int i = 0; i < n; ++i) s += c[i] * r[i];
            tmp[std::size_t(k)] = s;
          }
        }
        std::copy(tmp.begin(), tmp.end(), r);
      }
    }
  });
}

void DctPlan::forwardRows(std::span<double> a, int threads) const {
  transformRows(a, threads, false);
}

void DctPlan::inverseRows(std::span<double> a, int threads) const {
  transformRows(a, threads, true);
}

}  // namespace iblx
