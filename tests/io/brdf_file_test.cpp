// Tests of the .brdf / .bparam reader and writer (engine/io/brdf_file.h): BRDF Explorer's grammar and quirks,
// every class of malformed file with its line number, and the .bparam round trip.
#include "engine/io/brdf_file.h"

#include "tests/io/scratch_files.h"

#include <doctest/doctest.h>

#include <fstream>

using namespace iblx;
using namespace iblx::test;

namespace {

const char* kGood = R"(analytic

# a comment before the parameters
::begin parameters
float alpha 0.001 1 0.25
  # indented comments are dropped too
bool  useFresnel 1
color Kd 0.1 0.2 0.3
::end parameters

::begin shader
const float PI = 3.14159265358979;

# BRDF Explorer drops this line even inside the shader
vec3 BRDF( vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y )
{
    return Kd / PI;
}
::end shader

::begin isFunc
vec3 sampleBRDF( float u, float v, vec3 N, vec3 X, vec3 Y, out vec3 wi, out float pdf ) { pdf = 0.0; return vec3(0.0); }
::end isFunc
)";

std::string parseError(const std::string& text) {
  return errorMessage([&] { parseBrdfText(text, "bad.brdf"); });
}

}  // namespace

TEST_CASE("brdf file: BRDF Explorer's grammar") {
  const BrdfFile f = parseBrdfText(kGood, "good.brdf");
  CHECK(f.kind == BrdfFile::Kind::Analytic);
  REQUIRE(f.params.size() == 3);
  CHECK(f.params[0].decl.name == "alpha");
  CHECK(f.params[0].decl.type == ParamType::Float);
  CHECK(f.params[0].decl.min == 0.001);
  CHECK(f.params[0].decl.max == 1.0);
  CHECK(f.params[0].decl.defaultValue[0] == 0.25);
  CHECK(f.params[0].line == 5);
  CHECK(f.params[1].decl.type == ParamType::Bool);
  CHECK(f.params[1].decl.defaultValue[0] == 1.0);
  CHECK(f.params[1].line == 7);
  CHECK(f.params[2].decl.type == ParamType::Color);
  CHECK(f.params[2].decl.defaultValue == std::array<double, 3>{0.1, 0.2, 0.3});
  // Blank and '#' lines are dropped everywhere; the kept lines keep their numbers and their indentation.
  REQUIRE(f.shader.lines.size() == 5);
  CHECK(f.shader.lines[0] == "const float PI = 3.14159265358979;");
  CHECK(f.shader.lineNumbers == std::vector<int>{12, 15, 16, 17, 18});
  CHECK(f.shader.lines[3] == "    return Kd / PI;");
  REQUIRE(f.isFunc.lines.size() == 1);
  CHECK(f.isFunc.lineNumbers[0] == 22);
}

TEST_CASE("brdf file: Windows line endings and comments before the header") {
  std::string text = std::string("# saved by an editor\r\n") + kGood;
  std::string crlf;
  for (char c : text) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  const BrdfFile f = parseBrdfText(crlf, "crlf.brdf");
  CHECK(f.params.size() == 3);
  REQUIRE(f.shader.lines.size() == 5);
  CHECK(f.shader.lines[0].back() == ';');  // no '\r' left
}

TEST_CASE("brdf file: each class of malformed file names its line") {
  const std::string shader =
      "::begin shader\nvec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) { return vec3(0); }\n"
      "::end shader\n";
  struct Case {
    std::string text, expected;
  };
  const Case cases[] = {
      {"", "bad.brdf:1: empty file"},
      {"measured\n" + shader, "bad.brdf:1: the first line must be 'analytic' or 'bparam PATH'"},
      {"analytic\n::begin parameters\nint n 1 2 3\n::end parameters\n" + shader,
       "bad.brdf:3: unknown parameter type 'int'"},
      {"analytic\n::begin parameters\nfloat n 1 2\n::end parameters\n" + shader,
       "bad.brdf:3: float parameter: expected 'float NAME MIN MAX DEFAULT'"},
      {"analytic\n::begin parameters\nfloat n 1 x 2\n::end parameters\n" + shader,
       "bad.brdf:3: maximum 'x' is not a number"},
      {"analytic\n::begin parameters\nfloat n 3 1 2\n::end parameters\n" + shader,
       "bad.brdf:3: minimum 3 is above maximum 1"},
      {"analytic\n::begin parameters\nbool b true\n::end parameters\n" + shader,
       "bad.brdf:3: bool parameter 'b': default must be 0 or 1"},
      {"analytic\n::begin parameters\ncolor c 1 2 0\n::end parameters\n" + shader,
       "bad.brdf:3: color parameter 'c': channels must be in [0, 1]"},
      {"analytic\n::begin parameters\nfloat 2x 0 1 0\n::end parameters\n" + shader,
       "bad.brdf:3: parameter name '2x' is not a valid GLSL identifier"},
      {"analytic\n::begin parameters\nfloat a 0 1 0\n\nfloat a 0 1 0\n::end parameters\n" + shader,
       "bad.brdf:5: parameter 'a' is declared twice (first on line 3)"},
      {"analytic\n::begin parameters\n::begin shader\n",
       "bad.brdf:3: '::begin shader' inside section 'parameters'"},
      {"analytic\n::begin parameters\n::end shader\n",
       "bad.brdf:3: '::end shader' closes section 'parameters'"},
      {"analytic\n::end shader\n", "bad.brdf:2: '::end shader' without a matching ::begin"},
      {"analytic\n::begin shader\nvec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) { return L; }\n",
       "bad.brdf:2: section 'shader' is never closed"},
      {"analytic\nfloat a 0 1 0\n" + shader, "bad.brdf:2: text outside a section"},
      {"analytic\n::begin parameters\n::end parameters\n", "bad.brdf:1: no '::begin shader' section"},
      {"analytic\n" + shader + shader, "bad.brdf:5: a second shader section"},
      {"bparam\n", "bad.brdf:1: 'bparam' must be followed by the path"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.text);
    const std::string message = parseError(c.text);
    CHECK_MESSAGE(contains(message, c.expected), message);
  }
}

TEST_CASE("brdf file: warnings for what BRDF Explorer tolerates") {
  WarningCapture warnings;
  const BrdfFile f = parseBrdfText(
      "analytic\n::begin notes\nanything goes\n::end notes\n::begin parameters\nfloat n 0 1 5\n::end "
      "parameters\n"
      "::begin shader\nvec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) { return vec3(n); }\n::end shader\n",
      "tolerated.brdf");
  REQUIRE(warnings.messages.size() == 2);
  CHECK(contains(warnings.messages[0], "tolerated.brdf:2: unknown section 'notes' is ignored"));
  CHECK(contains(warnings.messages[1], "tolerated.brdf:6: default 5 of 'n' is outside [0, 1]"));
  REQUIRE(f.params.size() == 1);
  CHECK(f.params[0].decl.max == 5.0);  // widened to include the default
}

TEST_CASE("brdf file: unreadable files") {
  ScratchDir dir;
  CHECK(
      contains(errorMessage([&] { readBrdfFile(dir.file("missing.brdf")); }), "missing.brdf: no such file"));
  std::filesystem::create_directory(dir.file("folder.brdf"));
  CHECK(contains(errorMessage([&] { readBrdfFile(dir.file("folder.brdf")); }), "is a directory"));
  writeBytes(dir.file("binary.brdf"), {'a', 0, 'b'});
  CHECK(contains(errorMessage([&] { readBrdfFile(dir.file("binary.brdf")); }), "not a text file"));
}

TEST_CASE("brdf file: .bparam round trip") {
  ScratchDir dir;
  {
    std::ofstream out(dir.file("model.brdf"));
    out << kGood;
  }
  const BrdfFile model = readBrdfFile(dir.file("model.brdf"));
  std::vector<ParamDecl> decls;
  for (const auto& p : model.params) decls.push_back(p.decl);
  // Values that need all 9 digits (float 0.1 is not 0.1) and a bool off.
  ParamValues values{
      {"alpha", {double(0.123456789f), 0, 0}}, {"useFresnel", {0.0, 0, 0}}, {"Kd", {double(0.1f), 0.5, 1.0}}};
  writeBparam(dir.file("saved.bparam"), "model.brdf", decls, values);
  const BrdfFile saved = readBrdfFile(dir.file("saved.bparam"));
  CHECK(saved.kind == BrdfFile::Kind::Bparam);
  // A relative source resolves against the .bparam's folder.
  CHECK(saved.bparamSource == dir.file("model.brdf"));
  REQUIRE(saved.params.size() == 3);
  for (const auto& p : saved.params) {
    CAPTURE(p.decl.name);
    const auto& v = values.at(p.decl.name);
    for (int c = 0; c < (p.decl.type == ParamType::Color ? 3 : 1); ++c)
      CHECK(float(p.decl.defaultValue[std::size_t(c)]) == float(v[std::size_t(c)]));
  }
  // BRDF Explorer's layout: the header, a blank line, then the parameter section.
  const std::string text = formatBparam("model.brdf", decls, values);
  CHECK(text.rfind("bparam model.brdf\n\n::begin parameters\nfloat alpha 0.001 1 0.123456791\n", 0) == 0);
  CHECK(contains(text, "bool useFresnel 0\n"));
  CHECK(contains(text, "::end parameters\n"));
}

TEST_CASE("brdf file: limits on a file that is a program, checked before compiling") {
  ScratchDir dir;
  const auto shader = [](const std::string& body) {
    return "analytic\n::begin shader\nvec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) {\n" + body +
           "\n}\n::end shader\n";
  };
  // A 20 000-term sum crashed the GPU compiler (stack overflow): refused with its line.
  std::string sum = "  return vec3(1.0";
  for (int i = 0; i < 20000; ++i) sum += "+1.0";
  CHECK(contains(parseError(shader(sum + ");")), "bad.brdf:4: a statement with more than 2000 operators"));
  // At the limit it is accepted, and a statement end resets the count.
  std::string twoSums = "  float a = 1.0";
  for (int i = 0; i < 1500; ++i) twoSums += "+1.0";
  twoSums += ";\n  float b = a";
  for (int i = 0; i < 1500; ++i) twoSums += "+1.0";
  CHECK_NOTHROW(parseBrdfText(shader(twoSums + ";\n  return vec3(b);"), "ok.brdf"));
  // Operators in comments are not counted.
  CHECK_NOTHROW(parseBrdfText(shader("  // " + std::string(5000, '+') + "\n  return vec3(1.0);"), "ok.brdf"));
  CHECK(contains(
      parseError(shader("  return vec3" + std::string(100, '(') + "1.0" + std::string(100, ')') + ";")),
      "bad.brdf:4: brackets nested deeper than 64 levels"));

  // 500 000 parameters took minutes (a quadratic duplicate check): the 257th is refused at once.
  std::string params = "analytic\n::begin parameters\n";
  for (int i = 0; i < 300; ++i) params += "float p" + std::to_string(i) + " 0 1 0.5\n";
  params += "::end parameters\n";
  CHECK(
      contains(parseError(params + shader("  return vec3(p0);")), "bad.brdf:259: more than 256 parameters"));

  // A 10 MB file is refused by its size, before it is read.
  const auto big = dir.file("big.brdf");
  writeBytes(big, std::vector<unsigned char>(kMaxBrdfFileBytes + 1, ' '));
  CHECK(contains(errorMessage([&] { readBrdfFile(big); }),
                 "big.brdf: the file is 256 KiB (262145 bytes), more than the 256 KiB"));
  CHECK(contains(errorMessage([&] { readBrdfFile("/dev/zero"); }), "/dev/zero: it is a device"));
}

TEST_CASE(
    "brdf file: lines of form feeds or vertical tabs are blank (they once read past an empty token list)") {
  CHECK(contains(parseError("\n\f\n#\x03"), "bad.brdf:1: empty file"));
  const BrdfFile f = parseBrdfText(
      "\v\f\nanalytic\n::begin parameters\n\f\v\nfloat n 1 2 1.5\n::end parameters\n"
      "::begin shader\nvec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) { return vec3(n); }\n"
      "::end shader\n",
      "ff.brdf");
  CHECK(f.params.size() == 1);
  CHECK(contains(parseError("bparam\f\n"), "'bparam' must be followed by the path"));
}
