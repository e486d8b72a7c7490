// ALTA function files evaluated on the CPU, in double: the twin of the generated GLSL part
// (engine/scene/alta_func_brdf.h), which computes the same in float.
#pragma once

#include "engine/io/alta_func.h"

#include <glm/glm.hpp>

#include <span>
#include <vector>

namespace iblx {

// The basis polynomial of degree n at x: x^n, T_n(x) (Chebyshev, first kind) or P_n(x) (Legendre), by their
// three-term recurrences (Abramowitz & Stegun 22.7).
double altaBasisValue(AltaBasis basis, int degree, double x);
// A coordinate of the rational function's box [lo, hi], clamped to it, on [-1, 1] where the basis is
// evaluated (ALTA's rational_function: x' = 2 ((x - min) / (max - min) - 0.5)).
double altaBoxCoordinate(double x, double lo, double hi);
// A channel's P/Q at the parametrisation's coordinates x (clamped to the box first), 0 where Q = 0.
double evalAltaRational(const AltaRational& r, AltaBasis basis, int channel, std::span<const double> x);
// The coordinates of (wi = light, wo = view), local frame n = +z, with angles folded into the box of `r` by
// the symmetries of an isotropic reciprocal BRDF (phi_d by pi, phi_l - phi_v by 2 pi and its sign).
std::vector<double> altaCoordinates(AltaParam p, const glm::dvec3& wi, const glm::dvec3& wo,
                                    std::span<const double> min, std::span<const double> max);
// Each lobe's value in 1/sr (ALTA's plugin formulas, alta_func_eval.cpp) and their sum; 0 below the horizon.
glm::dvec3 evalAltaLobe(const AltaFunc& f, const AltaLobe& lobe, const glm::dvec3& wi, const glm::dvec3& wo);
glm::dvec3 evalAltaFunc(const AltaFunc& f, const glm::dvec3& wi, const glm::dvec3& wo);

// The directions of Rusinkiewicz's (theta_h, theta_d, phi_d) with phi_h = 0 (wi = light).

// The product of the basis polynomials of a term's degrees at the box coordinates xs (in [-1, 1]).
double altaTermBasis(AltaBasis basis, std::span<const int> degrees, std::span<const double> xs);

}  // namespace iblx
