// ALTA function files (`#ALTA FUNC HEADER`, .func): the fitted BRDFs written by ALTA (Pacanowski, Belcour,
// Barla et al., "ALTA: A BRDF Analysis Library", Inria), read into a value type and written back.
// Evaluated on the CPU by alta_func_eval.h and fitted by alta_func_fit.h.
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

// A rational function may be written over any of ALTA's parametrisations (engine/io/alta_params.h).
enum class AltaBasis { Monomial, Chebyshev, Legendre };

std::string altaBasisName(AltaBasis b);
// Every parametrisation's name, for messages: "RUSIN_TH_PH_TD_PD, RUSIN_TH_TD_PD, ..."
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
// Every rational term of a file, over its lobes and channels: each becomes GLSL that glslang compiles, whose
// time and memory grow with the count (16 lobes of 2,000 terms took over a minute and 3.4 GB).
constexpr int kAltaMaxFileTerms = 4096;
constexpr int kAltaMaxDegree = 40;  // per input dimension
constexpr int kAltaMaxLobes = 16;

// Throws iblx::Error "NAME:LINE: problem" for any malformed input.
AltaFunc parseAltaFunc(std::string_view text, const std::string& displayName);
AltaFunc loadAltaFunc(const std::filesystem::path& path);
// Whether the file's first line is `#ALTA FUNC HEADER` (reads at most that line).
bool looksLikeAltaFunc(const std::filesystem::path& path);

std::string formatAltaFunc(const AltaFunc& func);
void writeAltaFunc(const std::filesystem::path& path, const AltaFunc& func);

}  // namespace iblx
