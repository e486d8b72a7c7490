// Log axes (log_axes.h): tick choice and labels, data ranges in log space and the data-to-pixel mapping.
#include "engine/analysis/log_axes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace iblx {

std::vector<double> logTicks(double lo, double hi) {
  if (!(lo > 0) || !(hi > 0) || !std::isfinite(lo) || !std::isfinite(hi)) return {};
  if (lo > hi) std::swap(lo, hi);
  // A hair of tolerance so that a range ending exactly at a decade (up to rounding) includes it.
  const double tolerance = 1e-9;
  const auto collect = [&](std::span<const int> mantissas) {
    std::vector<double> ticks;
    const int firstExponent = int(std::floor(std::log10(lo))) - 1,
              lastExponent = int(std::ceil(std::log10(hi)));
    for (int e = firstExponent; e <= lastExponent; ++e)
      for (int m : mantissas) {
        const double v = m * std::pow(10.0, e);
        if (v >= lo * (1 - tolerance) && v <= hi * (1 + tolerance)) ticks.push_back(v);
      }
    return ticks;
  };
  static constexpr std::array<int, 1> kDecades{1};
  static constexpr std::array<int, 3> kOneTwoFive{1, 2, 5};
  static constexpr std::array<int, 9> kAllDigits{1, 2, 3, 4, 5, 6, 7, 8, 9};
  for (std::span<const int> mantissas : {std::span<const int>(kDecades), std::span<const int>(kOneTwoFive),
                                         std::span<const int>(kAllDigits)}) {
    std::vector<double> ticks = collect(mantissas);
    if (ticks.size() >= 2) return ticks;
  }
  // Less than a factor ~2 wide: evenly spaced ticks at a 1, 2 or 5 x 10^k step, 2 to 5 of them.
  if (!(hi > lo)) return {lo};
  for (double step = std::pow(10.0, std::floor(std::log10((hi - lo) / 5))); step <= hi - lo; step *= 10)
    for (double m : {1.0, 2.0, 5.0}) {
      std::vector<double> ticks;
      for (double k = std::ceil(lo / (m * step)); k * m * step <= hi; ++k) ticks.push_back(k * m * step);
      if (ticks.size() >= 2 && ticks.size() <= 5) return ticks;
    }
  return {lo, hi};
}

std::string tickLabel(double v) {
  if (!std::isfinite(v)) return "?";
  if (v == 0) return "0";
  const std::string sign = v < 0 ? "-" : "";
  v = std::abs(v);
  int exponent = int(std::floor(std::log10(v)));
  double mantissa = v / std::pow(10.0, exponent);
  // log10 can land one off near exact powers of ten; rounding to 6 digits can carry into the next decade.
  mantissa = std::round(mantissa * 1e5) / 1e5;
  if (mantissa >= 10) mantissa /= 10, ++exponent;
  if (mantissa < 1) mantissa *= 10, --exponent;
  // The fewest significant digits that still say this value, so 1-2-5 ticks read "2e-3", fine ones "3.105".
  char digits[32], power[16] = "";
  for (int precision = 1; precision <= 6; ++precision) {
    std::snprintf(digits, sizeof digits, "%.*g", precision, mantissa);
    if (std::abs(std::strtod(digits, nullptr) - mantissa) <= 1e-9 * mantissa) break;
  }
  if (exponent != 0) std::snprintf(power, sizeof power, "e%d", exponent);
  return sign + digits + power;
}

std::vector<double> ticksForLog10Range(double log10Lo, double log10Hi) {
  return logTicks(std::pow(10.0, log10Lo), std::pow(10.0, log10Hi));
}

std::size_t labelStride(std::span<const double> pixelPositions, double extent) {
  double minSpacing = std::numeric_limits<double>::infinity();
  for (std::size_t i = 1; i < pixelPositions.size(); ++i)
    minSpacing = std::min(minSpacing, std::abs(pixelPositions[i] - pixelPositions[i - 1]));
  if (!std::isfinite(minSpacing) || minSpacing <= 0) return 1;
  return std::size_t(std::max(1.0, std::ceil((extent + 12) / minSpacing)));
}

bool validLogLogPoint(double x, double y) {
  return std::isfinite(x) && std::isfinite(y) && x > 0 && y > 0;
}

void LogRange::add(double log10Value) {
  lo = std::min(lo, log10Value), hi = std::max(hi, log10Value);
}

void LogLogBounds::add(double xValue, double yValue) {
  if (!validLogLogPoint(xValue, yValue)) return;
  x.add(std::log10(xValue));
  y.add(std::log10(yValue));
}

void LogLogBounds::add(std::span<const double> xs, std::span<const double> ys) {
  for (std::size_t i = 0; i < std::min(xs.size(), ys.size()); ++i) add(xs[i], ys[i]);
}

LogRange paddedRange(LogRange r) {
  if (r.empty()) return {0.0, 1.0};
  if (r.hi - r.lo < 1e-9) return {r.lo - 0.5, r.hi + 0.5};
  const double pad = 0.05 * (r.hi - r.lo);
  return {r.lo - pad, r.hi + pad};
}

LogRange wholeDecades(LogRange r) {
  if (r.empty()) return {0.0, 1.0};
  const double lo = std::floor(r.lo);
  return {lo, std::max(std::ceil(r.hi), lo + 1)};
}

double LogLogAxes::pixelX(double x) const {
  return left + (std::log10(x) - log10XMin) / (log10XMax - log10XMin) * (right - left);
}

double LogLogAxes::pixelY(double y) const {
  return bottom - (std::log10(y) - log10YMin) / (log10YMax - log10YMin) * (bottom - top);
}

}  // namespace iblx
