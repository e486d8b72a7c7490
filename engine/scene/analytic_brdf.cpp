// .brdf files as BRDFs: parameter checks, renaming of the snippet's top-level names, the generated part.
#include "engine/scene/analytic_brdf.h"

#include "engine/scene/glsl_line.h"

#include "engine/core/error.h"
#include "engine/core/hash.h"
#include "engine/core/log.h"

#include <algorithm>
#include <cctype>
#include <set>
#include <sstream>

namespace iblx {
namespace {

// GLSL 4.60 keywords and reserved words (GLSL spec §3.6), which a parameter may not be called.
const std::set<std::string>& glslReservedWords() {
  static const std::set<std::string> words = {
      "attribute", "const", "uniform", "varying", "buffer", "shared", "coherent", "volatile", "restrict",
      "readonly", "writeonly", "atomic_uint", "layout", "centroid", "flat", "smooth", "noperspective",
      "patch", "sample", "invariant", "precise", "break", "continue", "do", "for", "while", "switch", "case",
      "default", "if", "else", "subroutine", "in", "out", "inout", "int", "void", "bool", "true", "false",
      "float", "double", "discard", "return", "vec2", "vec3", "vec4", "ivec2", "ivec3", "ivec4", "bvec2",
      "bvec3", "bvec4", "uint", "uvec2", "uvec3", "uvec4", "dvec2", "dvec3", "dvec4", "mat2", "mat3", "mat4",
      "mat2x2", "mat2x3", "mat2x4", "mat3x2", "mat3x3", "mat3x4", "mat4x2", "mat4x3", "mat4x4", "dmat2",
      "dmat3", "dmat4", "lowp", "mediump", "highp", "precision", "struct", "common", "partition", "active",
      "asm", "class", "union", "enum", "typedef", "template", "this", "resource", "goto", "inline",
      "noinline", "public", "static", "extern", "external", "interface", "long", "short", "half", "fixed",
      "unsigned", "superp", "input", "output", "hvec2", "hvec3", "hvec4", "fvec2", "fvec3", "fvec4", "filter",
      "sizeof", "cast", "namespace", "using", "sampler2D", "sampler3D", "samplerCube", "image2D", "texture",
      "main",
      // GLSL built-in functions a parameter would shadow
      "radians", "degrees", "sin", "cos", "tan", "asin", "acos", "atan", "sinh", "cosh", "tanh", "asinh",
      "acosh", "atanh", "pow", "exp", "log", "exp2", "log2", "sqrt", "inversesqrt", "abs", "sign", "floor",
      "trunc", "round", "roundEven", "ceil", "fract", "mod", "modf", "min", "max", "clamp", "mix", "step",
      "smoothstep", "isnan", "isinf", "fma", "length", "distance", "dot", "cross", "normalize", "faceforward",
      "reflect", "refract", "transpose", "determinant", "inverse", "any", "all", "not", "equal", "notEqual",
      "lessThan", "greaterThan",
      // names the generated part and the kernels use at global scope
      "BRDF", "sampleBRDF", "pdfBRDF", "frame"};
  return words;
}

// Type names that can start a top-level function or variable declaration in a snippet.
bool isTypeName(const std::string& t) {
  static const std::set<std::string> types = {
      "void",   "float",  "int",    "uint",   "bool",   "double", "vec2",   "vec3",   "vec4",
      "ivec2",  "ivec3",  "ivec4",  "uvec2",  "uvec3",  "uvec4",  "bvec2",  "bvec3",  "bvec4",
      "mat2",   "mat3",   "mat4",   "dvec2",  "dvec3",  "dvec4",  "mat2x2", "mat2x3", "mat2x4",
      "mat3x2", "mat3x3", "mat3x4", "mat4x2", "mat4x3", "mat4x4"};
  return types.count(t) != 0;
}

struct Token {
  std::size_t begin, end;  // [begin, end) in the text
  bool identifier;
};

// Identifiers and single punctuation characters, skipping comments, whitespace and numbers' insides.
std::vector<Token> tokenize(const std::string& s) {
  std::vector<Token> out;
  std::size_t i = 0;
  const auto isIdentStart = [](char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; };
  const auto isIdent = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
  while (i < s.size()) {
    const char c = s[i];
    if (c == '/' && i + 1 < s.size() && s[i + 1] == '/') {
      i = std::min(s.find('\n', i), s.size());
    } else if (c == '/' && i + 1 < s.size() && s[i + 1] == '*') {
      const std::size_t close = s.find("*/", i + 2);
      i = close == std::string::npos ? s.size() : close + 2;
    } else if (std::isspace(static_cast<unsigned char>(c))) {
      ++i;
    } else if (isIdentStart(c)) {
      std::size_t j = i;
      while (j < s.size() && isIdent(s[j])) ++j;
      out.push_back({i, j, true});
      i = j;
    } else if (std::isdigit(static_cast<unsigned char>(c)) ||
               (c == '.' && i + 1 < s.size() && std::isdigit(static_cast<unsigned char>(s[i + 1])))) {
      std::size_t j = i;  // a number, exponent and suffix included (1e-3, 2.0f, 0x1Fu)
      while (j < s.size() && (isIdent(s[j]) || s[j] == '.' ||
                              ((s[j] == '-' || s[j] == '+') && (s[j - 1] == 'e' || s[j - 1] == 'E'))))
        ++j;
      out.push_back({i, j, false});
      i = j;
    } else {
      out.push_back({i, i + 1, false});
      ++i;
    }
  }
  return out;
}

// The snippet's top-level function names and global variable names (outside braces and parentheses).
struct TopLevelNames {
  std::set<std::string> functions, variables;
};
TopLevelNames topLevelNames(const std::string& s, const std::vector<Token>& tokens) {
  TopLevelNames names;
  int depth = 0, parens = 0;  // a function's parameters (parens > 0) are not globals
  const auto text = [&](const Token& t) { return s.substr(t.begin, t.end - t.begin); };
  for (std::size_t k = 0; k < tokens.size(); ++k) {
    const Token& t = tokens[k];
    if (!t.identifier) {
      const char c = s[t.begin];
      if (c == '{') ++depth;
      if (c == '}') depth = std::max(0, depth - 1);
      if (c == '(') ++parens;
      if (c == ')') parens = std::max(0, parens - 1);
      continue;
    }
    if (depth != 0 || parens != 0 || !isTypeName(text(t)) || k + 2 >= tokens.size() ||
        !tokens[k + 1].identifier)
      continue;
    const std::string name = text(tokens[k + 1]);
    const char next = s[tokens[k + 2].begin];
    if (next == '(')
      names.functions.insert(name);
    else if (next == '=' || next == ';' || next == '[' || next == ',')
      names.variables.insert(name);
  }
  return names;
}

void appendSection(std::ostringstream& out, const std::vector<std::string>& lines,
                   const std::vector<int>& numbers, const std::string& file) {
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (i == 0 || numbers[i] != numbers[i - 1] + 1)
      out << "#line " << numbers[i] << " " << glslLineFileName(file) << "\n";
    out << lines[i] << "\n";
  }
}

std::vector<std::string> splitLines(const std::string& s) {
  std::vector<std::string> lines;
  std::size_t pos = 0;
  while (pos <= s.size()) {
    const std::size_t end = std::min(s.find('\n', pos), s.size());
    lines.push_back(s.substr(pos, end - pos));
    if (end == s.size()) break;
    pos = end + 1;
  }
  return lines;
}

std::string joinLines(const std::vector<std::string>& lines) {
  std::string s;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (i) s += '\n';
    s += lines[i];
  }
  return s;
}

}  // namespace

std::string renameBuiltinRedefinitions(const std::string& glsl, std::vector<std::string>* renamed) {
  // Every top-level function and global of the snippet except its entry points is renamed iblxUser_NAME:
  // that covers redefined built-ins (glslang rejects `vec3 reflect(vec3, vec3)`) and any clash with the
  // kernels' own helpers, which the snippet is compiled with.
  const std::vector<Token> tokens = tokenize(glsl);
  TopLevelNames names = topLevelNames(glsl, tokens);
  std::set<std::string> rename;
  for (const auto& set : {names.functions, names.variables})
    for (const auto& n : set)
      if (n != "BRDF" && n != "sampleBRDF" && n != "pdfBRDF") rename.insert(n);
  if (renamed) renamed->assign(rename.begin(), rename.end());
  std::string out;
  std::size_t copied = 0;
  for (std::size_t k = 0; k < tokens.size(); ++k) {
    const Token& t = tokens[k];
    if (!t.identifier || !rename.count(glsl.substr(t.begin, t.end - t.begin))) continue;
    if (k > 0 && glsl[tokens[k - 1].begin] == '.' && tokens[k - 1].end == t.begin) continue;  // v.length()
    out.append(glsl, copied, t.begin - copied);
    out += "iblxUser_";
    out.append(glsl, t.begin, t.end - t.begin);
    copied = t.end;
  }
  out.append(glsl, copied, std::string::npos);
  return out;
}

std::string analyticBrdfSource(const BrdfFile& file, const std::string& partPath) {
  // Rename across both sections together (the isFunc may call the shader's helpers), then split them again:
  // renaming never adds or removes a line, so the #line numbers stay right.
  std::vector<std::string> all = file.shader.lines;
  all.insert(all.end(), file.isFunc.lines.begin(), file.isFunc.lines.end());
  const std::vector<std::string> renamedLines = splitLines(renameBuiltinRedefinitions(joinLines(all)));
  const std::vector<std::string> shader(renamedLines.begin(),
                                        renamedLines.begin() + std::ptrdiff_t(file.shader.lines.size()));
  const std::vector<std::string> isFunc(renamedLines.begin() + std::ptrdiff_t(file.shader.lines.size()),
                                        renamedLines.end());
  std::ostringstream s;
  std::string source = file.displayName;  // in a // comment: a newline in the path would end it
  std::replace_if(
      source.begin(), source.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20; }, '?');
  s << "// Generated by iblx from " << source
    << " (engine/scene/analytic_brdf.cpp): BRDF Explorer's BRDF(L, V, N, X, Y) as brdfEval.\n"
    << "#ifndef IBLX_ANALYTIC_BRDF\n#define IBLX_ANALYTIC_BRDF\n"
    << "vec3 iblxV = vec3(0.0, 0.0, 1.0);  // the view direction for the isFunc hook\n"
    << "void iblxSetView(vec3 v) { iblxV = v; }  // for kernels included before this part (test probes)\n";
  appendSection(s, shader, file.shader.lineNumbers, file.displayName);
  appendSection(s, isFunc, file.isFunc.lineNumbers, file.displayName);
  s << "#line 1 " << glslLineFileName(partPath + " (generated wrapper)") << "\n"
    << "vec3 brdfEval(vec3 wi, vec3 wo) {\n"
    << "  if (wi.z <= 0.0 || wo.z <= 0.0) return vec3(0.0);\n"
    << "  vec3 f = BRDF(wi, wo, vec3(0.0, 0.0, 1.0), vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0));\n"
    << "#ifdef IBLX_UNGUARDED_BRDF\n  return f;  // tests of the file itself (BrdfEvaluator's unguarded "
       "mode)\n#endif\n"
    << "  // A negative or non-finite value counts as 0 (ordered compares are false for NaN).\n"
    << "  return vec3(f.x >= 0.0 && f.x <= 3.0e38 ? f.x : 0.0, f.y >= 0.0 && f.y <= 3.0e38 ? f.y : 0.0,\n"
    << "              f.z >= 0.0 && f.z <= 3.0e38 ? f.z : 0.0);\n"
    << "}\n#endif\n";
  return s.str();
}

std::shared_ptr<const BrdfInfo> makeAnalyticBrdf(const BrdfFile& file) {
  if (file.kind != BrdfFile::Kind::Analytic)
    throw Error(file.displayName + ": a .bparam file has no shader; load the BRDF it names");
  auto info = std::make_shared<BrdfInfo>();
  for (const BrdfFileParam& p : file.params) {
    if (glslReservedWords().count(p.decl.name) || p.decl.name.rfind("iblx", 0) == 0)
      throw Error(file.displayName + ":" + std::to_string(p.line) + ": parameter name '" + p.decl.name +
                  "' is reserved in GLSL or by iblx; rename it");
    info->params.push_back(p.decl);
  }
  std::string all;
  for (const auto& l : file.shader.lines) all += l + "\n";
  for (const auto& l : file.isFunc.lines) all += l + "\n";
  const TopLevelNames names = topLevelNames(all, tokenize(all));
  if (!names.functions.count("BRDF"))
    throw Error(file.displayName + ":" +
                std::to_string(file.shader.lineNumbers.empty() ? 1 : file.shader.lineNumbers[0]) +
                ": the shader section defines no 'vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)'");
  const bool sample = names.functions.count("sampleBRDF") != 0, pdf = names.functions.count("pdfBRDF") != 0;
  if (sample && !pdf)
    warn(file.displayName +
         ": its isFunc defines sampleBRDF but no pdfBRDF(L, V, N, X, Y); iblx needs both "
         "to use it (MIS evaluates the density of any direction), so it samples with brdf-tab");
  info->hasSampleHook = sample && pdf;

  const std::string stem = std::filesystem::path(file.displayName).stem().string();
  info->name = stem;
  info->description = "BRDF Explorer file " + file.displayName;
  // The part's path carries the source's hash, so two files of the same name never share a cached SPIR-V.
  ContentHash hash;
  hash.add(file.displayName).add(all);
  std::ostringstream path;
  path << "generated/brdf_" << std::hex << hash.value() << ".glsl";
  info->evalPart = path.str();
  info->evalSource = analyticBrdfSource(file, info->evalPart);
  info->bestSampler = info->hasSampleHook ? "isfunc" : "brdf-tab";
  info->lobeWidth = [](const Scene& scene, const GpuServices& gpu) { return gpu.measureLobeWidth(scene); };
  return info;
}

}  // namespace iblx
