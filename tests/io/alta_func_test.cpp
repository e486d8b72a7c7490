// ALTA function files: every construct of the grammar, every class of malformed file with its message, the
// rational functions in the three bases against hand-computed values, the parametrisations' coordinates, the
// lobes at directions with closed-form values, the writer's round trip and the least-squares fit.
#include "engine/io/alta_func.h"
#include "engine/io/alta_func_eval.h"
#include "engine/io/alta_func_fit.h"

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "tests/io/scratch_files.h"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

using namespace iblx;
using namespace iblx::test;

namespace {

constexpr double kPi = std::numbers::pi;

std::string header(const std::string& dim = "3 3", const std::string& param = "RUSIN_TH_TD_PD",
                   const std::string& cmd = "ALTA --func rational_function") {
  return "#ALTA FUNC HEADER\n#CMD " + cmd + "\n#DIM " + dim + "\n#PARAM_IN " + param +
         "\n#PARAM_OUT RGB_COLOR\n#ALTA HEADER END\n\n";
}

const std::string kLobes =
    "#FUNC nonlinear_function_diffuse\nkd 0.1\nkd 0.2\nkd 0.3\n\n"
    "#FUNC nonlinear_function_blinn\nKs 1\nN  10\nKs 2\nN  20\nKs 3\nN  30\n\n"
    "# a comment between lobes\n"
    "#FUNC nonlinear_function_beckmann\nKs 0.5\na  0.2\nKs 0.5\na  0.3\nKs 0.5\na  0.4\n\n"
    "#FUNC nonlinear_function_ward\nKs 0.25\nax 0.1\nay 0.3\nKs 0.25\nax 0.1\nay 0.3\nKs 0.25\nax 0.1\nay "
    "0.3\n";

// A 1D rational function over COS_TH on [0, 1]: P = 1 + 2 B1 + 3 B2, Q = 1 + 0.5 B1.
const std::string kRational1d =
    "#FUNC rational_function\n#MIN 0\n#MAX 1\n#NP 3\n#NQ 2\n0 1\n1 2\n2 3\n0 1\n1 0.5\n";

std::string parseError(const std::string& text) {
  return errorMessage([&] { parseAltaFunc(text, "bad.func"); });
}

}  // namespace

TEST_CASE("alta-func: the header and every lobe plugin are read, per channel") {
  const AltaFunc f = parseAltaFunc(header() + kLobes, "good.func");
  CHECK(f.dimX == 3);
  CHECK(f.dimY == 3);
  CHECK(f.paramIn == AltaParam::RusinThTdPd);
  CHECK(f.paramOut == "RGB_COLOR");
  CHECK(f.command == "ALTA --func rational_function");
  REQUIRE(f.lobes.size() == 4);
  CHECK(f.lobes[0].kind == AltaLobeKind::Diffuse);
  CHECK(f.lobes[0].values[2][0] == 0.3);
  CHECK(f.lobes[1].kind == AltaLobeKind::Blinn);
  CHECK(f.lobes[1].values[1] == std::vector<double>{2.0, 20.0});
  CHECK(f.lobes[2].kind == AltaLobeKind::Beckmann);
  CHECK(f.lobes[2].values[2][1] == 0.4);
  CHECK(f.lobes[3].kind == AltaLobeKind::Ward);
  CHECK(f.lobes[3].values[0] == std::vector<double>{0.25, 0.1, 0.3});
  CHECK(f.lobes[3].line == 30);
  // A grey file (nY = 1) and CRLF line ends.
  std::string grey =
      "#ALTA FUNC HEADER\r\n#DIM 3 1\r\n#ALTA HEADER END\r\n#FUNC nonlinear_function_ward\r\n"
      "Ks 1\r\nax 0.2\r\nay 0.2\r\n";
  const AltaFunc g = parseAltaFunc(grey, "grey.func");
  CHECK(g.dimY == 1);
  CHECK(g.lobes[0].values.size() == 1);
}

TEST_CASE("alta-func: rational functions, their basis from #CMD or the plugin name, per-channel #NP/#NQ") {
  const std::string rgb =
      "#FUNC rational_function\n#MIN 0 0 0\n#MAX 1.5 1.5 3.1\n"
      "#NP 2\n#NQ 1\n0 0 0 1\n1 0 2 0.5\n0 0 0 1\n"
      "#NP 1\n#NQ 1\n0 0 0 2\n0 0 0 1\n"
      "#NP 0\n#NQ 1\n0 0 0 1\n";
  const AltaFunc f = parseAltaFunc(
      header("3 3", "RUSIN_TH_TD_PD", "ALTA --func rational_function_chebychev") + rgb, "r.func");
  CHECK(f.basis == AltaBasis::Chebyshev);
  REQUIRE(f.lobes.size() == 1);
  const AltaRational& r = f.lobes[0].rational;
  CHECK(r.max == std::vector<double>{1.5, 1.5, 3.1});
  REQUIRE(r.channels.size() == 3);
  CHECK(r.channels[0].p.size() == 2);
  CHECK(r.channels[0].p[1].degrees == std::vector<int>{1, 0, 2});
  CHECK(r.channels[0].p[1].coefficient == 0.5);
  CHECK(r.channels[1].p[0].coefficient == 2.0);
  CHECK(r.channels[2].p.empty());
  CHECK(
      parseAltaFunc(header("1 1", "COS_TH", "ALTA --func rational_function_legendre") + kRational1d, "l.func")
          .basis == AltaBasis::Legendre);
  CHECK(parseAltaFunc(header("1 1", "COS_TH", "ALTA") + kRational1d, "m.func").basis == AltaBasis::Monomial);
  std::string named = kRational1d;
  named.replace(named.find("rational_function"), 17, "rational_function_legendre");
  CHECK(parseAltaFunc(header("1 1", "COS_TH", "ALTA") + named, "n.func").basis == AltaBasis::Legendre);
  for (const char* p : {"COS_TH_TD", "RUSIN_TH_TD"})
    CHECK(parseAltaFunc(
              header("2 1", p) + "#FUNC rational_function\n#MIN 0 0\n#MAX 1 1\n#NP 1\n#NQ 1\n0 0 1\n0 0 1\n",
              "2d.func")
              .dimX == 2);
}

TEST_CASE("alta-func: every malformed file is one error naming FILE:LINE and the problem") {
  struct Case {
    std::string text, expected;
  };
  const std::string rationalHead = header("1 1", "COS_TH") + "#FUNC rational_function\n#MIN 0\n#MAX 1\n";
  const Case cases[] = {
      {"#ALTA HEADER\n", "bad.func:1: not an ALTA function file: the first line must be '#ALTA FUNC HEADER'"},
      {"", "bad.func:1: not an ALTA function file"},
      {"#ALTA FUNC HEADER\n#ALTA HEADER END\n#FUNC nonlinear_function_diffuse\nkd 1\n",
       "missing header line '#DIM nX nY'"},
      {"#ALTA FUNC HEADER\n#DIM 3 3\n", "bad.func:2: truncated file: no '#ALTA HEADER END' line"},
      {"#ALTA FUNC HEADER\n#DIM 3 3\nkd 1\n#ALTA HEADER END\n", "bad.func:3: 'kd 1' in the header"},
      {header(), "truncated file: no '#FUNC' block after the header"},
      {header() + "#FUNC nonlinear_function_lafortune\n",
       "bad.func:8: unknown plugin 'nonlinear_function_lafortune'"},
      {header() + "kd 0.5\n", "bad.func:8: expected '#FUNC <plugin>', got 'kd 0.5'"},
      // Too few values per channel: Blinn needs Ks and N for each of three channels.
      {header() + "#FUNC nonlinear_function_blinn\nKs 1\nKs 1\n",
       "bad.func:10: expected 'N <value>' (channel 1"},
      {header() + "#FUNC nonlinear_function_blinn\nKs 1\nN 2\n", "truncated file: the blinn lobe"},
      {header() + "#FUNC nonlinear_function_diffuse\nkd 1\n#FUNC nonlinear_function_diffuse\n",
       "bad.func:10: the diffuse lobe (#FUNC at line 8) has 1 of its 3 values"},
      {header() + "#FUNC nonlinear_function_diffuse\nkd 1\nkd 1\nkd 1\nkd 1\n",
       "bad.func:12: 'kd 1' after the "
       "diffuse lobe's 3 values"},
      {header() + "#FUNC nonlinear_function_diffuse\nkd abc\n",
       "bad.func:9: diffuse kd 'abc' is not a number"},
      {header() + "#FUNC nonlinear_function_diffuse\nkd 1.5x\n", "'1.5x' is not a number"},
      {header() + "#FUNC nonlinear_function_diffuse\nkd inf\n", "bad.func:9: diffuse kd inf is not finite"},
      {header() + "#FUNC nonlinear_function_diffuse\nkd nan\n", "diffuse kd nan is not finite"},
      {header() + "#FUNC nonlinear_function_ward\nKs 1\nax 0\n",
       "bad.func:10: ward ax = 0: must be positive"},
      {header() + "#FUNC nonlinear_function_diffuse\nkd 1e20\n", "absurd"},
      {header() + "#FUNC nonlinear_function_diffuse\nkd 1e300\n", "diffuse kd 1e300 is beyond float's range"},
      {header("3 7"), "bad.func:3: #DIM nY = 7: iblx reads 1 (grey) or 3 (RGB) output channels"},
      {header("99 3"), "#DIM nX = 99: must be in [1, 6]"},
      {header("3"), "#DIM needs two integers"},
      {header("3 x"), "#DIM nY 'x' is not an integer"},
      {header("1 1", "RUSIN_TH_PH_TD") + kRational1d,
       "bad.func:4: #PARAM_IN RUSIN_TH_PH_TD: not one of ALTA's parametrisations: RUSIN_TH_PH_TD_PD, "
       "RUSIN_TH_TD_PD, RUSIN_TH_TD"},
      {header("1 1", "ISOTROPIC_TL_TV_PROJ_DPHI") + kRational1d,
       "bad.func:3: #DIM nX = 1 but ISOTROPIC_TL_TV_PROJ_DPHI has 3 dimensions"},
      {header("2 1", "RUSIN_TH_TD_PD") + kRational1d,
       "bad.func:3: #DIM nX = 2 but RUSIN_TH_TD_PD has 3 dimensions"},
      {"#ALTA FUNC HEADER\n#DIM 1 1\n#ALTA HEADER END\n" + kRational1d,
       "bad.func:4: a rational function needs the header line '#PARAM_IN <name>'"},
      {header("1 1", "COS_TH") + "#FUNC rational_function\n#MAX 1\n",
       "bad.func:9: expected '#MIN x1 .. xnX'"},
      {header("1 1", "COS_TH") + "#FUNC rational_function\n#MIN 0 0\n",
       "bad.func:9: #MIN has 2 values; #DIM nX is 1"},
      {header("1 1", "COS_TH") + "#FUNC rational_function\n#MIN 1\n#MAX 1\n",
       "bad.func:10: #MAX must exceed #MIN"},
      {rationalHead + "#NP 5000\n#NQ 1\n", "bad.func:11: #NP 5000: must be in [0, 1000]"},
      {rationalHead + "#NP 99999999999\n", "#NP 99999999999 is absurdly large"},
      {rationalHead + "#NP 1\n#NQ 0\n", "#NQ 0: must be in [1, 1000]"},
      {rationalHead + "#NQ 1\n", "expected '#NP <count>' for channel 1"},
      {rationalHead + "#NP 1\n#NQ 1\n0 0 1\n0 1\n",
       "bad.func:13: P term 1 of channel 1 has 3 numbers; #DIM nX = 1 "
       "needs 1 degrees and a coefficient"},
      {rationalHead + "#NP 1\n#NQ 1\n41 1\n0 1\n", "bad.func:13: degree 41: must be in [0, 40]"},
      {rationalHead + "#NP 1\n#NQ 1\n-1 1\n0 1\n", "degree -1: must be in [0, 40]"},
      {rationalHead + "#NP 1\n#NQ 1\n0 1\n0 nan\n", "bad.func:14: coefficient nan is not finite"},
      // Finite in double, infinite in the GPU's float: it used to render as a black lobe without a word.
      {rationalHead + "#NP 1\n#NQ 1\n0 1e300\n0 1\n",
       "bad.func:13: coefficient 1e300 is beyond float's range"},
      {rationalHead + "#NP 2\n#NQ 1\n0 1\n", "bad.func:13: truncated file: P term 2 of channel 1 is missing"},
      {rationalHead + "#NP 1\n#NQ 2\n0 1\n0 1\n#FUNC nonlinear_function_diffuse\n",
       "bad.func:15: Q term 2 of channel 1 is missing (#NP 1, #NQ 2)"},
      {rationalHead + "#NP 1\n#NQ 1\n0 1\n0 1\n0 1\n",
       "bad.func:15: '0 1' after the rational function's 1 channels"},
      {header() + std::string("#FUNC nonlinear_function_diffuse\nkd 1\0\n", 39), "a NUL byte"},
  };
  for (const Case& c : cases) {
    const std::string message = parseError(c.text);
    INFO("file:\n" << c.text << "\nmessage: " << message);
    CHECK(message.find(c.expected) != std::string::npos);
  }
  std::string many = header();
  for (int k = 0; k <= kAltaMaxLobes; ++k) many += "#FUNC nonlinear_function_diffuse\nkd 1\nkd 1\nkd 1\n";
  CHECK(parseError(many).find("more than 16 lobes") != std::string::npos);
}

TEST_CASE("alta-func: the three bases against hand-computed values") {
  // x' = 0.5: T2 = 2 x^2 - 1 = -0.5, T3 = 4 x^3 - 3 x = -1; P2 = (3 x^2 - 1) / 2 = -0.125,
  // P3 = (5 x^3 - 3 x) / 2 = -0.4375.
  CHECK(altaBasisValue(AltaBasis::Monomial, 3, 0.5) == doctest::Approx(0.125));
  CHECK(altaBasisValue(AltaBasis::Chebyshev, 2, 0.5) == doctest::Approx(-0.5));
  CHECK(altaBasisValue(AltaBasis::Chebyshev, 3, 0.5) == doctest::Approx(-1.0));
  CHECK(altaBasisValue(AltaBasis::Legendre, 2, 0.5) == doctest::Approx(-0.125));
  CHECK(altaBasisValue(AltaBasis::Legendre, 3, 0.5) == doctest::Approx(-0.4375));
  for (const AltaBasis b : {AltaBasis::Monomial, AltaBasis::Chebyshev, AltaBasis::Legendre})
    CHECK(altaBasisValue(b, 0, 0.3) == 1.0);
  // P = 1 + 2 B1 + 3 B2 and Q = 1 + 0.5 B1 at cos theta_h = 0.75 on [0, 1], x' = 0.5: monomial 2.75 / 1.25,
  // Chebyshev 0.5 / 1.25, Legendre 1.625 / 1.25.
  struct Case {
    const char* cmd;
    double expected;
  };
  for (const Case& c :
       {Case{"ALTA --func rational_function", 2.2}, Case{"ALTA --func rational_function_chebychev", 0.4},
        Case{"ALTA --func rational_function_legendre", 1.3}}) {
    const AltaFunc f = parseAltaFunc(header("1 1", "COS_TH", c.cmd) + kRational1d, "r.func");
    const double x = 0.75;
    CHECK(evalAltaRational(f.lobes[0].rational, f.basis, 0, std::span(&x, 1)) == doctest::Approx(c.expected));
  }
  // Outside the box the input is clamped: cos theta_h = 1 (normal incidence) is x' = 1 on [0, 0.5].
  AltaFunc f = parseAltaFunc(header("1 1", "COS_TH") + kRational1d, "r.func");
  f.lobes[0].rational.max = {0.5};
  const glm::dvec3 n(0.0, 0.0, 1.0);
  CHECK(evalAltaFunc(f, n, n).x == doctest::Approx(6.0 / 1.5));
  CHECK(evalAltaFunc(f, n, n).z == doctest::Approx(6.0 / 1.5));  // a grey file fills every channel
  // Two dimensions: the term (1, 1) is the product of the bases, 2 x0' x1' at x' = (0.5, 1).
  const AltaFunc g =
      parseAltaFunc(header("2 1", "COS_TH_TD") +
                        "#FUNC rational_function\n#MIN 0 0\n#MAX 1 1\n#NP 1\n#NQ 1\n1 1 2\n0 0 1\n",
                    "g.func");
  const double xs[2] = {0.75, 1.0};
  CHECK(evalAltaRational(g.lobes[0].rational, g.basis, 0, xs) == doctest::Approx(1.0));
}

TEST_CASE("alta-func: the parametrisations' coordinates, with angles folded into the file's box") {
  glm::dvec3 wi, wo;
  altaRusinDirections(0.3, 0.5, 1.2, wi, wo);
  const std::vector<double> lo{0.0, 0.0, 0.0}, hiPi{kPi / 2, kPi / 2, kPi};
  auto x = altaCoordinates(AltaParam::RusinThTdPd, wi, wo, lo, hiPi);
  CHECK(x[0] == doctest::Approx(0.3));
  CHECK(x[1] == doctest::Approx(0.5));
  CHECK(x[2] == doctest::Approx(1.2));
  // phi_d + pi is the same configuration with wi and wo swapped: folded back by reciprocity.
  x = altaCoordinates(AltaParam::RusinThTdPd, wo, wi, lo, hiPi);
  CHECK(x[2] == doctest::Approx(1.2));
  x = altaCoordinates(AltaParam::RusinThTd, wi, wo, lo, hiPi);
  CHECK(x.size() == 2);
  CHECK(x[1] == doctest::Approx(0.5));
  x = altaCoordinates(AltaParam::CosThTd, wi, wo, lo, hiPi);
  CHECK(x[0] == doctest::Approx(std::cos(0.3)));
  CHECK(x[1] == doctest::Approx(std::cos(0.5)));
  CHECK(altaCoordinates(AltaParam::CosTh, wi, wo, lo, hiPi)[0] == doctest::Approx(std::cos(0.3)));
  // Light at azimuth -30 degrees, view at 0: phi_l - phi_v is 330 degrees, folded to 30 on [0, pi] (isotropy)
  // and to -30 on [-pi, pi].
  const double a = -kPi / 6;
  const glm::dvec3 light(std::sin(0.4) * std::cos(a), std::sin(0.4) * std::sin(a), std::cos(0.4));
  const glm::dvec3 view(std::sin(0.7), 0.0, std::cos(0.7));
  x = altaCoordinates(AltaParam::IsotropicTvTlDphi, light, view, lo, hiPi);
  CHECK(x[0] == doctest::Approx(0.7));
  CHECK(x[1] == doctest::Approx(0.4));
  CHECK(x[2] == doctest::Approx(kPi / 6));
  const std::vector<double> loSym{0.0, 0.0, -kPi}, hiSym{kPi / 2, kPi / 2, kPi},
      hi2Pi{kPi / 2, kPi / 2, 2 * kPi};
  CHECK(altaCoordinates(AltaParam::IsotropicTvTlDphi, light, view, loSym, hiSym)[2] ==
        doctest::Approx(-kPi / 6));
  CHECK(altaCoordinates(AltaParam::IsotropicTvTlDphi, light, view, lo, hi2Pi)[2] ==
        doctest::Approx(11 * kPi / 6));
}

TEST_CASE("alta-func: the lobes at directions with closed-form values; 0 below the horizon") {
  const AltaFunc f = parseAltaFunc(header() + kLobes, "good.func");
  const glm::dvec3 n(0.0, 0.0, 1.0);
  // At wi = wo = n the half vector is n: diffuse kd, Blinn Ks, Beckmann Ks / (4 pi a^2), Ward Ks / (4 pi ax
  // ay).
  CHECK(evalAltaLobe(f, f.lobes[0], n, n).y == doctest::Approx(0.2));
  CHECK(evalAltaLobe(f, f.lobes[1], n, n).z == doctest::Approx(3.0));
  CHECK(evalAltaLobe(f, f.lobes[2], n, n).x == doctest::Approx(0.5 / (4 * kPi * 0.04)));
  CHECK(evalAltaLobe(f, f.lobes[3], n, n).x == doctest::Approx(0.25 / (4 * kPi * 0.03)));
  // Half vector tilted by t in the tangent direction: Blinn cos^N t; Ward's exponent tan^2 t / ax^2.
  const double t = 0.1;
  const glm::dvec3 wo(std::sin(0.5), 0.0, std::cos(0.5)),
      wi(std::sin(2 * t - 0.5), 0.0, std::cos(2 * t - 0.5));
  CHECK(evalAltaLobe(f, f.lobes[1], wi, wo).x == doctest::Approx(std::pow(std::cos(t), 10.0)));
  CHECK(evalAltaLobe(f, f.lobes[3], wi, wo).x ==
        doctest::Approx(0.25 / (4 * kPi * 0.03 * std::sqrt(wi.z * wo.z)) *
                        std::exp(-std::tan(t) * std::tan(t) / 0.01)));
  CHECK(evalAltaFunc(f, glm::dvec3(0.0, 0.6, -0.8), n) == glm::dvec3(0.0));
}

TEST_CASE("alta-func: the writer round-trips every lobe; looksLikeAltaFunc reads the first line") {
  const AltaFunc f =
      parseAltaFunc(header("3 3", "RUSIN_TH_TD_PD", "ALTA --func rational_function_chebychev") + kLobes +
                        "#FUNC rational_function\n#MIN 0 0 0\n#MAX 1.5 1.5 3.1\n"
                        "#NP 1\n#NQ 1\n0 0 0 0.1234567890123\n0 0 0 1\n#NP 1\n#NQ 1\n1 2 3 2\n0 0 0 1\n"
                        "#NP 1\n#NQ 1\n0 0 0 3\n0 0 0 1\n",
                    "in.func");
  ScratchDir dir;
  const auto path = dir.file("out.whatever");
  writeAltaFunc(path, f);
  CHECK(looksLikeAltaFunc(path));
  const AltaFunc g = loadAltaFunc(path);
  CHECK(g.basis == AltaBasis::Chebyshev);
  REQUIRE(g.lobes.size() == f.lobes.size());
  for (std::size_t i = 0; i < f.lobes.size(); ++i) {
    CHECK(g.lobes[i].kind == f.lobes[i].kind);
    CHECK(g.lobes[i].values == f.lobes[i].values);
  }
  CHECK(g.lobes[4].rational.channels[0].p[0].coefficient == 0.1234567890123);
  CHECK(g.lobes[4].rational.channels[1].p[0].degrees == std::vector<int>{1, 2, 3});
  writeFileAtomically(dir.file("other.func"), std::string_view("#ALTA FUNC HEADERS\n"));
  CHECK_FALSE(looksLikeAltaFunc(dir.file("other.func")));
  CHECK_FALSE(looksLikeAltaFunc(dir.file("missing.func")));
}

TEST_CASE("alta-func: the least-squares fit recovers a rational function exactly and reports its error") {
  // y = (1 + 2 x0' + x1' x2') / (2 + x0') over RUSIN_TH_TD_PD's box: total degrees 2 / 1 represent it.
  const std::vector<double> lo{0.0, 0.0, 0.0}, hi{kPi / 2, kPi / 2, kPi};
  std::vector<double> x;
  std::vector<std::vector<double>> y(1);
  for (int i = 0; i < 7; ++i)
    for (int j = 0; j < 6; ++j)
      for (int k = 0; k < 5; ++k) {
        const double v[3] = {(i + 0.5) / 7 * hi[0], (j + 0.5) / 6 * hi[1], (k + 0.5) / 5 * hi[2]};
        double s[3];
        for (int d = 0; d < 3; ++d) s[d] = 2.0 * (v[d] / hi[std::size_t(d)] - 0.5);
        x.insert(x.end(), v, v + 3);
        y[0].push_back((1.0 + 2.0 * s[0] + s[1] * s[2] + 3.0) / (2.0 + s[0]));
      }
  const AltaFitResult fit = fitAltaRational(3, x, y, lo, hi, 2, 1);
  CHECK(fit.rmsRelative < 1e-8);
  const double probe[3] = {0.3, 1.1, 2.0};
  const double s0 = 2.0 * (0.3 / hi[0] - 0.5), s1 = 2.0 * (1.1 / hi[1] - 0.5), s2 = 2.0 * (2.0 / hi[2] - 0.5);
  CHECK(evalAltaRational(fit.rational, AltaBasis::Chebyshev, 0, probe) ==
        doctest::Approx((4.0 + 2.0 * s0 + s1 * s2) / (2.0 + s0)));
  // A function no low-degree rational represents: the error is reported, not hidden.
  std::vector<std::vector<double>> peak(1);
  for (std::size_t s = 0; s < x.size() / 3; ++s)
    peak[0].push_back(std::exp(-40.0 * x[3 * s] * x[3 * s]) * 10.0);
  CHECK(fitAltaRational(3, x, peak, lo, hi, 1, 0).rmsRelative > 0.05);
}

TEST_CASE("alta-func: more rational terms than one shader compiles in seconds are refused at the lobe") {
  // Five grey lobes of 1,000 + 1 terms: the fifth passes the file's 4,096.
  std::string text = "#ALTA FUNC HEADER\n#DIM 1 1\n#PARAM_IN COS_TH\n#ALTA HEADER END\n";
  int line = 4;
  int fifth = 0;
  for (int lobe = 0; lobe < 5; ++lobe) {
    text += "#FUNC rational_function\n#MIN 0\n#MAX 1\n#NP 1000\n#NQ 1\n";
    if (lobe == 4) fifth = line + 1;
    line += 5;
    for (int k = 0; k < 1000; ++k) text += std::to_string(k % 40) + " 0.001\n";
    text += "0 1\n";
    line += 1001;
  }
  const std::string message = test::errorMessage([&] { parseAltaFunc(text, "many.func"); });
  CHECK(test::contains(message,
                       "many.func:" + std::to_string(fifth) +
                           ": the rational functions up to this one have 5005 terms, more than the 4096"));
}
