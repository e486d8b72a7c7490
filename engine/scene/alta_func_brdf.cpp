// ALTA function files as BRDFs: parameters from the lobes, the generated evaluation and sampling part
// (alta_func_brdf.h).
#include "engine/scene/alta_func_brdf.h"

#include "engine/io/alta_func_eval.h"
#include "engine/scene/glsl_line.h"
#include "engine/core/hash.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <sstream>

namespace iblx {
namespace {

// Each lobe's parameter prefix: its kind, numbered when the file has several of that kind.
std::vector<std::string> lobePrefixes(const AltaFunc& f) {
  std::map<AltaLobeKind, int> total, seen;
  for (const auto& l : f.lobes) ++total[l.kind];
  std::vector<std::string> out;
  for (const auto& l : f.lobes) {
    std::string p = altaLobeName(l.kind);
    if (total[l.kind] > 1) p += std::to_string(++seen[l.kind]);
    out.push_back(p);
  }
  return out;
}

// The GLSL names of a nonlinear lobe's parameters, in ALTA's file order.
std::vector<std::string> paramSuffixes(AltaLobeKind k) {
  switch (k) {
    case AltaLobeKind::Diffuse:
      return {"kd"};
    case AltaLobeKind::Blinn:
      return {"ks", "N"};
    case AltaLobeKind::Beckmann:
      return {"ks", "a"};
    case AltaLobeKind::Ward:
      return {"ks", "ax", "ay"};
    case AltaLobeKind::Rational:
      return {};
  }
  return {};
}

std::string glslFloat(double v) {
  char text[40];
  std::snprintf(text, sizeof text, "%.9g", v);
  std::string s = text;
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

bool sampleable(const AltaFunc& f) {
  return std::none_of(f.lobes.begin(), f.lobes.end(),
                      [](const AltaLobe& l) { return l.kind == AltaLobeKind::Rational; });
}

// Shared helpers: the lobes' values, their sampling routines and densities.
constexpr const char* kHelpers = R"(const float kAltaPi = 3.14159265358979;
vec3 iblxV = vec3(0.0, 0.0, 1.0);  // the view direction for the isfunc hook
void iblxSetView(vec3 v) { iblxV = v; }
// ALTA's nonlinear_function_blinn: Ks cos^N theta_h (Blinn 1977, unnormalised).
vec3 iblxAltaBlinn(vec3 h, vec3 ks, vec3 n) { return h.z > 0.0 ? ks * pow(vec3(h.z), n) : vec3(0.0); }
// ALTA's nonlinear_function_beckmann: Ks D(h) / 4, Beckmann's D (Cook & Torrance 1982).
vec3 iblxAltaBeckmann(vec3 h, vec3 ks, vec3 a) {
  float c2 = h.z * h.z;
  if (h.z <= 0.0 || c2 <= 0.0) return vec3(0.0);
  vec3 a2 = a * a;
  return ks * exp((c2 - 1.0) / (a2 * c2)) / (4.0 * kAltaPi * a2 * c2 * c2);
}
// ALTA's nonlinear_function_ward: Ward 1992's anisotropic Gaussian lobe.
vec3 iblxAltaWard(vec3 wi, vec3 wo, vec3 h, vec3 ks, vec3 ax, vec3 ay) {
  if (h.z <= 0.0) return vec3(0.0);
  vec3 e = (h.x * h.x / (ax * ax) + h.y * h.y / (ay * ay)) / (h.z * h.z);
  return ks / (4.0 * kAltaPi * ax * ay * sqrt(wi.z * wo.z)) * exp(-e);
}
// An angle folded into [lo, hi] by the symmetries of an isotropic reciprocal BRDF, then clamped
// (engine/io/alta_func_eval.h, altaCoordinates).
float iblxAltaFold(float a, float lo, float hi, bool reciprocity) {
  if (a > hi)
    a = a - 2.0 * kAltaPi >= lo ? a - 2.0 * kAltaPi : (reciprocity ? a - kAltaPi : 2.0 * kAltaPi - a);
  return clamp(a, lo, hi);
}
float iblxAltaWrap(float a) { return a - 2.0 * kAltaPi * floor(a / (2.0 * kAltaPi)); }
)";

constexpr const char* kSamplingHelpers =
    R"(// Half-vector densities are read at h = normalize(wi + wo), so wo.h >= 0, and at -h: a sampled h with
// wo.h < 0 gives the same wi as -h, so the density of wi is (p_h(h) + p_h(-h)) / (4 wo.h) and every sample
// keeps a positive density (the pdf integrates to 1 over the sphere, grazing views included).
// Returns 1 / (4 wo.h).
float iblxAltaHalfJacobian(vec3 wi, vec3 wo, out vec3 h) {
  h = wi + wo;
  float len = length(h);
  if (!(len > 0.0)) return 0.0;
  h /= len;
  float d = dot(wo, h);
  return d > 0.0 ? 0.25 / d : 0.0;
}
vec3 iblxAltaReflect(vec3 wo, vec3 h) { return 2.0 * dot(wo, h) * h - wo; }
// Cosine-weighted hemisphere, density cos theta / pi.
vec3 iblxAltaSampleCosine(vec2 u) {
  float r = sqrt(u.x), phi = 2.0 * kAltaPi * u.y;
  return vec3(r * cos(phi), r * sin(phi), sqrt(max(0.0, 1.0 - u.x)));
}
float iblxAltaPdfCosine(vec3 wi) { return wi.z > 0.0 ? wi.z / kAltaPi : 0.0; }
// Half vectors with density (N + 1) / (2 pi) cos^N theta_h.
vec3 iblxAltaSampleBlinn(vec2 u, vec3 wo, float n) {
  float c = pow(1.0 - u.x, 1.0 / (n + 1.0)), s = sqrt(max(0.0, 1.0 - c * c)), phi = 2.0 * kAltaPi * u.y;
  return iblxAltaReflect(wo, vec3(s * cos(phi), s * sin(phi), c));
}
vec3 iblxAltaPdfBlinn(vec3 wi, vec3 wo, vec3 n) {
  vec3 h;
  float j = iblxAltaHalfJacobian(wi, wo, h);
  float c = abs(h.z);
  return j > 0.0 && c > 0.0 ? (n + 1.0) / (2.0 * kAltaPi) * pow(vec3(c), n) * j : vec3(0.0);
}
// Half vectors with the anisotropic Beckmann density D(h) cos theta_h
// (Walter 2005, "Notes on the Ward BRDF").
vec3 iblxAltaSampleBeckmann(vec2 u, vec3 wo, float ax, float ay) {
  float phi = atan(ay * sin(2.0 * kAltaPi * u.y), ax * cos(2.0 * kAltaPi * u.y));
  float cp = cos(phi), sp = sin(phi);
  float tan2 = -log(1.0 - u.x) / (cp * cp / (ax * ax) + sp * sp / (ay * ay));
  float c = 1.0 / sqrt(1.0 + tan2), s = sqrt(max(0.0, 1.0 - c * c));
  return iblxAltaReflect(wo, vec3(s * cp, s * sp, c));
}
vec3 iblxAltaPdfBeckmann(vec3 wi, vec3 wo, vec3 ax, vec3 ay) {
  vec3 h;
  float j = iblxAltaHalfJacobian(wi, wo, h);
  float c = abs(h.z);
  if (!(j > 0.0 && c > 0.0)) return vec3(0.0);
  vec3 e = (h.x * h.x / (ax * ax) + h.y * h.y / (ay * ay)) / (c * c);
  return exp(-e) / (kAltaPi * ax * ay * c * c * c) * j;
}
float iblxAltaWeight(float w) { return w >= 0.0 && w <= 3.0e38 ? w : 0.0; }
)";

// The coordinates of the file's parametrisation, as x0, x1, ... (shaders/lib/alta_params.glsl's forward maps,
// azimuths brought into the box as engine/io/alta_func_eval.cpp's altaCoordinates does).
void emitCoordinates(std::ostringstream& s, const AltaFunc& f, const AltaRational& r) {
  s << "  float x[6];\n  altaParamCoordinates(wi, wo, x);\n";
  for (int d = 0; d < f.dimX; ++d) s << "  float x" << d << " = x[" << d << "];\n";
  for (int d = 0; d < f.dimX; ++d) {
    // Appended, not "x" + to_string(d): GCC 12 reports a false -Wrestrict for that at -O3.
    std::string x = "x";
    x += std::to_string(d);
    const std::string lo = glslFloat(r.min[std::size_t(d)]), hi = glslFloat(r.max[std::size_t(d)]);
    switch (altaAngleKind(f.paramIn, d)) {
      case AltaAngle::NotAngle:
        break;
      case AltaAngle::Turn:
        s << "  " << x << " = clamp(" << lo << " + iblxAltaWrap(" << x << " - " << lo << "), " << lo << ", "
          << hi << ");\n";
        break;
      case AltaAngle::Reciprocity:
      case AltaAngle::Mirror:
        s << "  " << x << " = iblxAltaFold(iblxAltaWrap(" << x << "), " << lo << ", " << hi << ", "
          << (altaAngleKind(f.paramIn, d) == AltaAngle::Reciprocity ? "true" : "false") << ");\n";
        break;
    }
  }
}

void emitRational(std::ostringstream& s, const AltaFunc& f, const AltaLobe& lobe, std::size_t index,
                  const std::string& displayName) {
  const AltaRational& r = lobe.rational;
  // Compile messages name the file and the lobe, not the generated part.
  s << "#line 1 "
    << glslLineFileName(displayName + " (the GLSL generated from its #FUNC at line " +
                        std::to_string(lobe.line) + ")")
    << "\n";
  s << "// Rational function (#FUNC at line " << lobe.line << "): P / Q in the " << altaBasisName(f.basis)
    << " basis over " << altaParamName(f.paramIn) << ", x' = 2 ((x - min) / (max - min) - 0.5) on the\n"
    << "// clamped box (Pacanowski et al. 2012, \"Rational BRDF\").\n"
    << "vec3 iblxAltaRational" << index << "(vec3 wi, vec3 wo) {\n";
  emitCoordinates(s, f, r);
  std::vector<int> maxDegree(std::size_t(f.dimX), 0);
  for (const auto& ch : r.channels)
    for (const auto* terms : {&ch.p, &ch.q})
      for (const auto& t : *terms)
        for (int k = 0; k < f.dimX; ++k)
          maxDegree[std::size_t(k)] = std::max(maxDegree[std::size_t(k)], t.degrees[std::size_t(k)]);
  for (int k = 0; k < f.dimX; ++k) {
    const int n = maxDegree[std::size_t(k)];
    s << "  float b" << k << "[" << n + 1 << "];\n"
      << "  float y" << k << " = 2.0 * ((clamp(x" << k << ", " << glslFloat(r.min[std::size_t(k)]) << ", "
      << glslFloat(r.max[std::size_t(k)]) << ") - " << glslFloat(r.min[std::size_t(k)]) << ") / "
      << glslFloat(r.max[std::size_t(k)] - r.min[std::size_t(k)]) << " - 0.5);\n"
      << "  b" << k << "[0] = 1.0;\n";
    if (n >= 1) {
      s << "  b" << k << "[1] = y" << k << ";\n  for (int n = 1; n < " << n << "; ++n) b" << k
        << "[n + 1] = ";
      if (f.basis == AltaBasis::Monomial)
        s << "y" << k << " * b" << k << "[n];\n";
      else if (f.basis == AltaBasis::Chebyshev)
        s << "2.0 * y" << k << " * b" << k << "[n] - b" << k << "[n - 1];\n";
      else
        s << "((2.0 * float(n) + 1.0) * y" << k << " * b" << k << "[n] - float(n) * b" << k
          << "[n - 1]) / (float(n) + 1.0);\n";
    }
  }
  s << "  vec3 value = vec3(0.0);\n";
  for (std::size_t c = 0; c < r.channels.size(); ++c) {
    const auto& ch = r.channels[c];
    for (const auto& [name, terms] : {std::pair{"p", &ch.p}, std::pair{"q", &ch.q}}) {
      s << "  float " << name << c << " = 0.0;\n";
      for (const auto& t : *terms) {
        s << "  " << name << c << " += " << glslFloat(t.coefficient);
        for (int k = 0; k < f.dimX; ++k)
          if (t.degrees[std::size_t(k)] > 0) s << " * b" << k << "[" << t.degrees[std::size_t(k)] << "]";
        s << ";\n";
      }
    }
    s << "  float v" << c << " = q" << c << " != 0.0 ? p" << c << " / q" << c << " : 0.0;\n";
  }
  if (r.channels.size() == 1)
    s << "  value = vec3(v0);\n";
  else
    s << "  value = vec3(v0, v1, v2);\n";
  s << "  return value;\n}\n";
}

// The lobe's value expression in brdfEval.
std::string lobeTerm(const AltaLobe& lobe, const std::string& p, std::size_t index) {
  switch (lobe.kind) {
    case AltaLobeKind::Diffuse:
      return p + "_kd";
    case AltaLobeKind::Blinn:
      return "iblxAltaBlinn(h, " + p + "_ks, " + p + "_N)";
    case AltaLobeKind::Beckmann:
      return "iblxAltaBeckmann(h, " + p + "_ks, " + p + "_a)";
    case AltaLobeKind::Ward:
      return "iblxAltaWard(wi, wo, h, " + p + "_ks, " + p + "_ax, " + p + "_ay)";
    case AltaLobeKind::Rational:
      return p + "_scale * iblxAltaRational" + std::to_string(index) + "(wi, wo)";
  }
  return "vec3(0.0)";
}

void emitSampling(std::ostringstream& s, const AltaFunc& f, const std::vector<std::string>& prefixes) {
  const std::size_t count = 3 * f.lobes.size();
  s << kSamplingHelpers << "const int kAltaComponents = " << count << ";\n"
    << "// One mixture component per lobe and channel, weighted by its approximate albedo at normal "
       "incidence.\n"
    << "void iblxAltaWeights(out float w[kAltaComponents]) {\n  vec3 l;\n";
  for (std::size_t i = 0; i < f.lobes.size(); ++i) {
    const std::string& p = prefixes[i];
    switch (f.lobes[i].kind) {
      case AltaLobeKind::Diffuse:
        s << "  l = " << p << "_kd * kAltaPi;\n";
        break;
      case AltaLobeKind::Blinn:
        s << "  l = " << p << "_ks * kAltaPi * min(vec3(1.0), 8.0 / (" << p << "_N + 2.0));\n";
        break;
      default:
        s << "  l = " << p << "_ks;\n";
        break;
    }
    for (int c = 0; c < 3; ++c)
      s << "  w[" << 3 * i + std::size_t(c) << "] = iblxAltaWeight(l[" << c << "]);\n";
  }
  s << "}\n"
    << "// The mixture's density: the weighted mean of every component's exact density (cosine when no lobe\n"
    << "// has weight).\n"
    << "float iblxAltaPdf(vec3 wi, vec3 wo, float w[kAltaComponents]) {\n"
    << "  float total = 0.0;\n  for (int k = 0; k < kAltaComponents; ++k) total += w[k];\n"
    << "  if (!(total > 0.0)) return iblxAltaPdfCosine(wi);\n  float p = 0.0;\n";
  for (std::size_t i = 0; i < f.lobes.size(); ++i) {
    const std::string& p = prefixes[i];
    const std::string weights = "vec3(w[" + std::to_string(3 * i) + "], w[" + std::to_string(3 * i + 1) +
                                "], w[" + std::to_string(3 * i + 2) + "])";
    switch (f.lobes[i].kind) {
      case AltaLobeKind::Diffuse:
        s << "  p += (w[" << 3 * i << "] + w[" << 3 * i + 1 << "] + w[" << 3 * i + 2
          << "]) * iblxAltaPdfCosine(wi);\n";
        break;
      case AltaLobeKind::Blinn:
        s << "  p += dot(" << weights << ", iblxAltaPdfBlinn(wi, wo, " << p << "_N));\n";
        break;
      case AltaLobeKind::Beckmann:
        s << "  p += dot(" << weights << ", iblxAltaPdfBeckmann(wi, wo, " << p << "_a, " << p << "_a));\n";
        break;
      case AltaLobeKind::Ward:
        s << "  p += dot(" << weights << ", iblxAltaPdfBeckmann(wi, wo, " << p << "_ax, " << p << "_ay));\n";
        break;
      case AltaLobeKind::Rational:
        break;
    }
  }
  s << "  return p / total;\n}\n"
    << "float pdfBRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) {\n"
    << "  float w[kAltaComponents];\n  iblxAltaWeights(w);\n  return iblxAltaPdf(L, V, w);\n}\n"
    << "// The isfunc hook (engine/scene/analytic_brdf.h): picks a component with u in proportion to its "
       "weight,\n"
    << "// reuses u's remainder, and returns f cos / pdf.\n"
    << "vec3 sampleBRDF(float u, float v, vec3 N, vec3 X, vec3 Y, out vec3 wi, out float pdf) {\n"
    << "  vec3 wo = iblxV;\n  float w[kAltaComponents];\n  iblxAltaWeights(w);\n"
    << "  float total = 0.0;\n  int last = -1;\n"
    << "  for (int k = 0; k < kAltaComponents; ++k) {\n    total += w[k];\n    if (w[k] > 0.0) last = k;\n  "
       "}\n"
    << "  if (last < 0) {\n    wi = iblxAltaSampleCosine(vec2(u, v));\n  } else {\n"
    << "    float target = u * total, before = 0.0;\n    int k = 0;\n"
    << "    for (; k < last; ++k) {\n      if (target < before + w[k]) break;\n      before += w[k];\n    }\n"
    << "    vec2 s = vec2(w[k] > 0.0 ? clamp((target - before) / w[k], 0.0, 0.99999994) : 0.5, v);\n"
    << "    int c = k - 3 * (k / 3);\n    wi = vec3(0.0, 0.0, 1.0);\n";
  for (std::size_t i = 0; i < f.lobes.size(); ++i) {
    const std::string& p = prefixes[i];
    s << "    " << (i == 0 ? "if" : "else if") << " (k < " << 3 * (i + 1) << ") wi = ";
    switch (f.lobes[i].kind) {
      case AltaLobeKind::Diffuse:
        s << "iblxAltaSampleCosine(s);\n";
        break;
      case AltaLobeKind::Blinn:
        s << "iblxAltaSampleBlinn(s, wo, " << p << "_N[c]);\n";
        break;
      case AltaLobeKind::Beckmann:
        s << "iblxAltaSampleBeckmann(s, wo, " << p << "_a[c], " << p << "_a[c]);\n";
        break;
      case AltaLobeKind::Ward:
        s << "iblxAltaSampleBeckmann(s, wo, " << p << "_ax[c], " << p << "_ay[c]);\n";
        break;
      case AltaLobeKind::Rational:
        s << "vec3(0.0, 0.0, 1.0);\n";
        break;
    }
  }
  s << "  }\n  pdf = iblxAltaPdf(wi, wo, w);\n"
    << "  return pdf > 0.0 ? brdfEval(wi, wo) * max(wi.z, 0.0) / pdf : vec3(0.0);\n}\n";
}

}  // namespace

std::string altaFuncBrdfSource(const AltaFunc& f, const std::string& displayName) {
  std::string source = displayName;  // in a // comment: a newline in the path would end it
  std::replace_if(
      source.begin(), source.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20; }, '?');
  const auto prefixes = lobePrefixes(f);
  std::ostringstream s;
  s << "// Generated by iblx from " << source
    << " (engine/scene/alta_func_brdf.cpp): an ALTA function file's sum of lobes as brdfEval.\n"
    << "#ifndef IBLX_ALTA_FUNC\n#define IBLX_ALTA_FUNC\n"
    << "#define ALTA_PARAM_IN " << int(f.paramIn) << "  // " << altaParamName(f.paramIn) << "\n"
    << "#include \"lib/alta_params.glsl\"\n"
    << kHelpers;
  for (std::size_t i = 0; i < f.lobes.size(); ++i)
    if (f.lobes[i].kind == AltaLobeKind::Rational) emitRational(s, f, f.lobes[i], i, displayName);
  s << "#line 1 " << glslLineFileName(displayName + " (the GLSL generated from its lobes)") << "\n"
    << "vec3 brdfEval(vec3 wi, vec3 wo) {\n"
    << "  if (wi.z <= 0.0 || wo.z <= 0.0) return vec3(0.0);\n"
    << "  vec3 h = normalize(wi + wo);\n  vec3 f = vec3(0.0);\n";
  for (std::size_t i = 0; i < f.lobes.size(); ++i)
    s << "  f += " << lobeTerm(f.lobes[i], prefixes[i], i) << ";\n";
  s << "#ifdef IBLX_UNGUARDED_BRDF\n  return f;\n#endif\n"
    << "  // A negative or non-finite value counts as 0 (ordered compares are false for NaN).\n"
    << "  return vec3(f.x >= 0.0 && f.x <= 3.0e38 ? f.x : 0.0, f.y >= 0.0 && f.y <= 3.0e38 ? f.y : 0.0,\n"
    << "              f.z >= 0.0 && f.z <= 3.0e38 ? f.z : 0.0);\n}\n";
  if (sampleable(f)) emitSampling(s, f, prefixes);
  s << "#endif\n";
  return s.str();
}

std::shared_ptr<const BrdfInfo> makeAltaFuncBrdf(const AltaFunc& f, const std::filesystem::path& file) {
  auto info = std::make_shared<BrdfInfo>();
  const auto prefixes = lobePrefixes(f);
  std::string lobes, names;
  for (std::size_t i = 0; i < f.lobes.size(); ++i) {
    const AltaLobe& lobe = f.lobes[i];
    lobes += (lobes.empty() ? "" : " + ") + altaLobeName(lobe.kind);
    if (lobe.kind == AltaLobeKind::Rational) {
      std::size_t np = 0, nq = 0;
      for (const auto& ch : lobe.rational.channels) {
        np = std::max(np, ch.p.size());
        nq = std::max(nq, ch.q.size());
      }
      lobes += " (" + altaParamName(f.paramIn) + ", " + altaBasisName(f.basis) + ", " + std::to_string(np) +
               " / " + std::to_string(nq) + " terms)";
      info->params.push_back(
          {prefixes[i] + "_scale",
           ParamType::Color,
           0.0,
           10.0,
           {1.0, 1.0, 1.0},
           "multiplies the rational function of the #FUNC at line " + std::to_string(lobe.line)});
      names += (names.empty() ? "" : ", ") + prefixes[i] + "_scale";
      continue;
    }
    const auto suffixes = paramSuffixes(lobe.kind);
    for (std::size_t k = 0; k < suffixes.size(); ++k) {
      ParamDecl d;
      d.name = prefixes[i] + "_" + suffixes[k];
      d.type = ParamType::Color;
      double lo = 0.0, hi = 0.0;
      for (int c = 0; c < 3; ++c) {
        const double v = lobe.values[std::size_t(f.dimY == 1 ? 0 : c)][k];
        d.defaultValue[std::size_t(c)] = v;
        lo = c == 0 ? v : std::min(lo, v);
        hi = c == 0 ? v : std::max(hi, v);
      }
      const bool coefficient = suffixes[k] == "kd" || suffixes[k] == "ks";
      if (coefficient) {
        d.min = std::min(0.0, lo);
        d.max = std::max(1.0, 2.0 * hi);
      } else if (suffixes[k] == "N") {
        d.min = 0.0;
        d.max = std::max(1000.0, 2.0 * hi);
      } else {  // roughness: positive
        d.min = std::min(1e-3, lo);
        d.max = std::max(1.0, 2.0 * hi);
      }
      d.description = altaLobeName(lobe.kind) + " " + suffixes[k] + " per channel (#FUNC at line " +
                      std::to_string(lobe.line) + ")";
      names += (names.empty() ? "" : ", ") + d.name;
      info->params.push_back(std::move(d));
    }
  }
  info->name = file.stem().string();
  info->hasSampleHook = sampleable(f);
  info->bestSampler = info->hasSampleHook ? "isfunc" : "brdf-tab";
  info->description = "ALTA function file " + file.string() + ": " + lobes + "; parameters " + names +
                      (info->hasSampleHook ? "; sampled by its lobes' closed forms (isfunc)"
                                           : "; sampled by brdf-tab (a rational function has no closed-form "
                                             "sampling)");
  const std::string source = altaFuncBrdfSource(f, file.string());
  // The part's path carries the source's hash, so two files of the same name never share a cached SPIR-V.
  ContentHash hash;
  hash.add(file.string()).add(source);
  std::ostringstream path;
  path << "generated/alta_" << std::hex << hash.value() << ".glsl";
  info->evalPart = path.str();
  info->evalSource = source;
  info->lobeWidth = [](const Scene& scene, const GpuServices& gpu) { return gpu.measureLobeWidth(scene); };
  return info;
}

}  // namespace iblx
