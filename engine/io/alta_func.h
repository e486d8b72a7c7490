// ALTA function files (`#ALTA FUNC HEADER`, .func): the fitted BRDFs written by ALTA (Pacanowski, Belcour,
// Barla et al., "ALTA: A BRDF Analysis Library", Inria), read into a value type, evaluated on the CPU (the
// twin of the generated GLSL part, engine/scene/alta_func_brdf.h), written back, and fitted: a rational
// function by linear least squares as in Pacanowski et al. 2012, "Rational BRDF", IEEE TVCG 18(11).
//
// Grammar (ALTA's function-file format):
//   #ALTA FUNC HEADER                       first line, exactly
//   #CMD <the fitting command>              names the plugin (--func) and so the rational basis
//   #DIM nX nY                              input and output dimensions (nY 1 or 3)
//   #PARAM_IN <parametrisation>             the rational functions' inputs
//   #PARAM_OUT <output>                     optional
//   #ALTA HEADER END
//   then one block per lobe of the sum, parameters per colour channel in turn:
//   #FUNC nonlinear_function_diffuse        kd
//   #FUNC nonlinear_function_blinn          Ks, N
//   #FUNC nonlinear_function_beckmann       Ks, a
//   #FUNC nonlinear_function_ward           Ks, ax, ay
//   #FUNC rational_function                 #MIN x1..xnX, #MAX x1..xnX, then per channel #NP n, #NQ m,
//                                           n lines `deg_1 .. deg_nX coeff` of P, then m lines of Q
// Blank lines and lines starting with "# " (a comment) are skipped.
#pragma once

#include <glm/glm.hpp>

#include <array>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "engine/io/alta_params.h"

namespace iblx {

// A rational function may be written over COS_TH, COS_TH_TD, RUSIN_TH_TD, RUSIN_TH_TD_PD and
// ISOTROPIC_TV_TL_DPHI (all cheap in GLSL).
enum class AltaBasis { Monomial, Chebyshev, Legendre };

std::string altaBasisName(AltaBasis b);
// "COS_TH, COS_TH_TD, RUSIN_TH_TD, RUSIN_TH_TD_PD, ISOTROPIC_TV_TL_DPHI"
std::string altaSupportedParams();

struct AltaTerm {
  std::vector<int> degrees;  // one per input dimension
  double coefficient = 0.0;
};
struct AltaRationalChannel {
  std::vector<AltaTerm> p, q;
};
struct AltaRational {
  std::vector<double> min, max;               // the box mapped to [-1, 1]^nX
  std::vector<AltaRationalChannel> channels;  // nY of them
};

enum class AltaLobeKind { Diffuse, Blinn, Beckmann, Ward, Rational };
std::string altaLobeName(AltaLobeKind k);  // "diffuse", "blinn", ...

struct AltaLobe {
  AltaLobeKind kind = AltaLobeKind::Diffuse;
  // Per channel (nY of them), the plugin's parameters in file order: diffuse {kd}, blinn {Ks, N},
  // beckmann {Ks, a}, ward {Ks, ax, ay}; empty for a rational function.
  std::vector<std::vector<double>> values;
  AltaRational rational;
  int line = 0;  // of its #FUNC
};

struct AltaFunc {
  std::string command;  // #CMD
  int dimX = 0, dimY = 0;
  AltaParam paramIn = AltaParam::RusinThTdPd;
  std::string paramOut;  // #PARAM_OUT, empty when absent
  AltaBasis basis = AltaBasis::Monomial;
  std::vector<AltaLobe> lobes;
};

// Limits on what a file may declare (the generated GLSL unrolls every term).
constexpr int kAltaMaxTerms = 1000;  // #NP and #NQ
constexpr int kAltaMaxDegree = 40;   // per input dimension
constexpr int kAltaMaxLobes = 16;

// Throws iblx::Error "NAME:LINE: problem" for any malformed input.
AltaFunc parseAltaFunc(std::string_view text, const std::string& displayName);
AltaFunc loadAltaFunc(const std::filesystem::path& path);
// Whether the file's first line is `#ALTA FUNC HEADER` (reads at most that line).
bool looksLikeAltaFunc(const std::filesystem::path& path);

std::string formatAltaFunc(const AltaFunc& func);
void writeAltaFunc(const std::filesystem::path& path, const AltaFunc& func);

// ---- evaluation (double; the GLSL part computes the same in float)
// The basis polynomial of degree n at x: x^n, T_n(x) (Chebyshev, first kind) or P_n(x) (Legendre), by their
// three-term recurrences (Abramowitz & Stegun 22.7).
double altaBasisValue(AltaBasis basis, int degree, double x);
// A channel's P/Q at the parametrisation's coordinates x (clamped to the box first), 0 where Q = 0.
double evalAltaRational(const AltaRational& r, AltaBasis basis, int channel, std::span<const double> x);
// The coordinates of (wi = light, wo = view), local frame n = +z, with angles folded into the box of `r` by
// the symmetries of an isotropic reciprocal BRDF (phi_d by pi, phi_l - phi_v by 2 pi and its sign).
std::vector<double> altaCoordinates(AltaParam p, const glm::dvec3& wi, const glm::dvec3& wo,
                                    std::span<const double> min, std::span<const double> max);
// Each lobe's value in 1/sr (ALTA's plugin formulas, alta_func.cpp) and their sum; 0 below the horizon.
glm::dvec3 evalAltaLobe(const AltaFunc& f, const AltaLobe& lobe, const glm::dvec3& wi, const glm::dvec3& wo);
glm::dvec3 evalAltaFunc(const AltaFunc& f, const glm::dvec3& wi, const glm::dvec3& wo);

// The directions of Rusinkiewicz's (theta_h, theta_d, phi_d) with phi_h = 0 (wi = light).

// ---- fitting
// A rational function of total degree `degreeP` over `degreeQ` in the Chebyshev basis, per channel, over
// samples x (dimX each) with values y (per channel): linear least squares on P(x) - y Q(x) = 0 with Q's
// constant coefficient fixed to 1 (the normalisation), rows weighted by 1 / (y + 0.01 mean y) so the fit
// minimises relative error. A channel whose Q is not positive at every sample is refitted as a polynomial
// (Q = 1). Returns the lobe and sets rmsRelative = sqrt(mean((fit - y)^2 / (y^2 + 0.01))) over all channels.
struct AltaFitResult {
  AltaRational rational;
  double rmsRelative = 0.0;
};
AltaFitResult fitAltaRational(int dimX, std::span<const double> x, std::span<const std::vector<double>> y,
                              std::span<const double> min, std::span<const double> max, int degreeP,
                              int degreeQ);

}  // namespace iblx
