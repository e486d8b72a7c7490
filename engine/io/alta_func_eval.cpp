// ALTA function files on the CPU: the basis polynomials, the rational functions, the coordinates of each
// parametrisation and every lobe (alta_func_eval.h).
#include "engine/io/alta_func_eval.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace iblx {
namespace {

constexpr double kPiD = std::numbers::pi;

double clampTo(double x, double lo, double hi) {
  return std::min(std::max(x, lo), hi);
}

// The angle folded into [lo, hi] when an equivalent one lies there: a - 2 pi (a box over [-pi, pi]), else the
// image under the BRDF's symmetry `mirror` (phi_d - pi by reciprocity; 2 pi - dphi by isotropy); then
// clamped.
double foldAngle(double a, double lo, double hi, bool reciprocity) {
  if (a > hi) {
    if (a - 2.0 * kPiD >= lo)
      a -= 2.0 * kPiD;
    else
      a = reciprocity ? a - kPiD : 2.0 * kPiD - a;
  }
  return clampTo(a, lo, hi);
}

double wrap2Pi(double a) {
  a = std::fmod(a, 2.0 * kPiD);
  return a < 0.0 ? a + 2.0 * kPiD : a;
}

}  // namespace

double altaBasisValue(AltaBasis basis, int degree, double x) {
  if (basis == AltaBasis::Monomial) return std::pow(x, degree);
  // T_{n+1} = 2x T_n - T_{n-1}; (n+1) P_{n+1} = (2n+1) x P_n - n P_{n-1}.
  double prev = 1.0, cur = x;
  if (degree == 0) return 1.0;
  for (int n = 1; n < degree; ++n) {
    const double next = basis == AltaBasis::Chebyshev ? 2.0 * x * cur - prev
                                                      : ((2.0 * n + 1.0) * x * cur - n * prev) / (n + 1.0);
    prev = cur;
    cur = next;
  }
  return cur;
}

double altaBoxCoordinate(double x, double lo, double hi) {
  return 2.0 * ((clampTo(x, lo, hi) - lo) / (hi - lo) - 0.5);
}

double evalAltaRational(const AltaRational& r, AltaBasis basis, int channel, std::span<const double> x) {
  std::vector<double> xs(x.size());
  for (std::size_t k = 0; k < x.size(); ++k) xs[k] = altaBoxCoordinate(x[k], r.min[k], r.max[k]);
  const AltaRationalChannel& ch = r.channels[std::size_t(channel)];
  double p = 0.0, q = 0.0;
  for (const AltaTerm& t : ch.p) p += t.coefficient * altaTermBasis(basis, t.degrees, xs);
  for (const AltaTerm& t : ch.q) q += t.coefficient * altaTermBasis(basis, t.degrees, xs);
  return q != 0.0 ? p / q : 0.0;
}

std::vector<double> altaCoordinates(AltaParam p, const glm::dvec3& wi, const glm::dvec3& wo,
                                    std::span<const double> min, std::span<const double> max) {
  const std::array<double, 6> k = altaRawCoordinates(p, wi, wo);
  std::vector<double> x(k.begin(), k.begin() + altaParamDimension(p));
  for (std::size_t d = 0; d < x.size(); ++d) {
    switch (altaAngleKind(p, int(d))) {
      case AltaAngle::NotAngle:
        break;
      case AltaAngle::Turn:
        x[d] = clampTo(min[d] + wrap2Pi(x[d] - min[d]), min[d], max[d]);
        break;
      case AltaAngle::Reciprocity:
      case AltaAngle::Mirror:
        x[d] = foldAngle(wrap2Pi(x[d]), min[d], max[d], altaAngleKind(p, int(d)) == AltaAngle::Reciprocity);
        break;
    }
  }
  return x;
}

glm::dvec3 evalAltaLobe(const AltaFunc& f, const AltaLobe& lobe, const glm::dvec3& wi, const glm::dvec3& wo) {
  if (wi.z <= 0.0 || wo.z <= 0.0) return glm::dvec3(0.0);
  const glm::dvec3 h = glm::normalize(wi + wo);
  glm::dvec3 out(0.0);
  for (int c = 0; c < 3; ++c) {
    const int ch = f.dimY == 1 ? 0 : c;
    const std::vector<double>* v = lobe.values.empty() ? nullptr : &lobe.values[std::size_t(ch)];
    double value = 0.0;
    switch (lobe.kind) {
      case AltaLobeKind::Diffuse:
        value = (*v)[0];
        break;
      // ALTA's nonlinear_function_blinn: Ks cos^N theta_h (Blinn 1977, unnormalised).
      case AltaLobeKind::Blinn:
        value = h.z > 0.0 ? (*v)[0] * std::pow(h.z, (*v)[1]) : 0.0;
        break;
      // ALTA's nonlinear_function_beckmann: Ks D(h) / 4 with Beckmann's D (Cook & Torrance 1982), no
      // shadowing and no 1 / (cos theta_i cos theta_o).
      case AltaLobeKind::Beckmann: {
        const double a2 = (*v)[1] * (*v)[1], c2 = h.z * h.z;
        value = h.z > 0.0 ? (*v)[0] * std::exp((c2 - 1.0) / (a2 * c2)) / (4.0 * kPiD * a2 * c2 * c2) : 0.0;
        break;
      }
      // ALTA's nonlinear_function_ward: Ward 1992's anisotropic Gaussian lobe.
      case AltaLobeKind::Ward: {
        const double ax = (*v)[1], ay = (*v)[2];
        const double e = ((h.x / ax) * (h.x / ax) + (h.y / ay) * (h.y / ay)) / (h.z * h.z);
        value = (*v)[0] / (4.0 * kPiD * ax * ay * std::sqrt(wi.z * wo.z)) * std::exp(-e);
        break;
      }
      case AltaLobeKind::Rational: {
        const auto x = altaCoordinates(f.paramIn, wi, wo, lobe.rational.min, lobe.rational.max);
        value = evalAltaRational(lobe.rational, f.basis, ch, x);
        break;
      }
    }
    out[c] = value;
  }
  return out;
}

glm::dvec3 evalAltaFunc(const AltaFunc& f, const glm::dvec3& wi, const glm::dvec3& wo) {
  glm::dvec3 sum(0.0);
  for (const AltaLobe& lobe : f.lobes) sum += evalAltaLobe(f, lobe, wi, wo);
  for (int c = 0; c < 3; ++c) sum[c] = std::isfinite(sum[c]) && sum[c] > 0.0 ? sum[c] : 0.0;
  return sum;
}

double altaTermBasis(AltaBasis basis, std::span<const int> degrees, std::span<const double> xs) {
  double v = 1.0;
  for (std::size_t k = 0; k < degrees.size(); ++k) v *= altaBasisValue(basis, degrees[k], xs[k]);
  return v;
}

}  // namespace iblx
