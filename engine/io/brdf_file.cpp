// .brdf / .bparam reading and .bparam writing (grammar in brdf_file.h).
#include "engine/io/brdf_file.h"

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/log.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <unordered_map>

namespace iblx {
namespace {

// Every character isspace() knows, as tokens() splits on: a line of form feeds is blank, not a line with no
// tokens.
constexpr const char* kSpace = " \t\r\n\f\v";

std::string trim(std::string_view s) {
  const auto first = s.find_first_not_of(kSpace);
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(kSpace);
  return std::string(s.substr(first, last - first + 1));
}

std::vector<std::string> tokens(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> out;
  for (std::string t; in >> t;) out.push_back(t);
  return out;
}

bool isIdentifier(const std::string& s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  return std::all_of(s.begin(), s.end(),
                     [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

class Parser {
 public:
  Parser(std::string displayName, std::filesystem::path folder)
      : name_(std::move(displayName)), folder_(std::move(folder)) {}

  [[noreturn]] void fail(int line, const std::string& problem) const {
    throw Error(name_ + ":" + std::to_string(line) + ": " + problem);
  }

  double number(int line, const std::string& text, const std::string& what) const {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v))
      fail(line, what + " '" + text + "' is not a number");
    return v;
  }

  void parameter(int line, const std::string& text) {
    const auto t = tokens(text);
    BrdfFileParam p;
    p.line = line;
    const std::string& type = t[0];
    const auto expect = [&](std::size_t count, const char* layout) {
      if (t.size() != count) fail(line, type + " parameter: expected '" + layout + "'");
    };
    if (type == "float") {
      expect(5, "float NAME MIN MAX DEFAULT");
      p.decl.type = ParamType::Float;
      p.decl.min = number(line, t[2], "minimum");
      p.decl.max = number(line, t[3], "maximum");
      p.decl.defaultValue = {number(line, t[4], "default"), 0.0, 0.0};
      if (p.decl.min > p.decl.max) fail(line, "minimum " + t[2] + " is above maximum " + t[3]);
      const double d = p.decl.defaultValue[0];
      if (d < p.decl.min || d > p.decl.max) {
        warn(name_ + ":" + std::to_string(line) + ": default " + t[4] + " of '" + t[1] + "' is outside [" +
             t[2] + ", " + t[3] + "]; the range is widened to include it");
        p.decl.min = std::min(p.decl.min, d);
        p.decl.max = std::max(p.decl.max, d);
      }
    } else if (type == "bool") {
      expect(3, "bool NAME 0|1");
      if (t[2] != "0" && t[2] != "1") fail(line, "bool parameter '" + t[1] + "': default must be 0 or 1");
      p.decl.type = ParamType::Bool;
      p.decl.defaultValue = {t[2] == "1" ? 1.0 : 0.0, 0.0, 0.0};
    } else if (type == "color") {
      expect(5, "color NAME R G B");
      p.decl.type = ParamType::Color;
      for (int c = 0; c < 3; ++c) {
        const double v = number(line, t[std::size_t(2 + c)], "color channel");
        if (v < 0.0 || v > 1.0) fail(line, "color parameter '" + t[1] + "': channels must be in [0, 1]");
        p.decl.defaultValue[std::size_t(c)] = v;
      }
    } else {
      fail(line, "unknown parameter type '" + type + "' (valid: float, bool, color)");
    }
    p.decl.name = t[1];
    if (!isIdentifier(p.decl.name) || p.decl.name.rfind("gl_", 0) == 0 ||
        p.decl.name.find("__") != std::string::npos)
      fail(line, "parameter name '" + p.decl.name + "' is not a valid GLSL identifier");
    if (const auto [it, inserted] = paramLines_.emplace(p.decl.name, line); !inserted)
      fail(line, "parameter '" + p.decl.name + "' is declared twice (first on line " +
                     std::to_string(it->second) + ")");
    if (file_.params.size() >= kMaxBrdfParams)
      fail(line, "more than " + std::to_string(kMaxBrdfParams) + " parameters");
    file_.params.push_back(std::move(p));
  }

  BrdfFile parse(std::string_view text) {
    file_.displayName = name_;
    bool sawHeader = false, sawShader = false;
    std::string section;  // empty: outside any section
    int sectionLine = 0;
    std::size_t pos = 0;
    for (int lineNo = 1; pos <= text.size(); ++lineNo) {
      const std::size_t end = std::min(text.find('\n', pos), text.size());
      std::string raw(text.substr(pos, end - pos));
      pos = end + 1;
      if (!raw.empty() && raw.back() == '\r') raw.pop_back();
      const std::string line = trim(raw);
      if (line.empty() || line[0] == '#') {  // dropped everywhere, as BRDF Explorer does
        if (end == text.size()) break;
        continue;
      }
      if (!sawHeader) {
        sawHeader = true;
        const auto t = tokens(line);
        if (t[0] == "analytic") {
          file_.kind = BrdfFile::Kind::Analytic;
        } else if (t[0] == "bparam") {
          file_.kind = BrdfFile::Kind::Bparam;
          const std::string source = trim(line.substr(
              line.find_first_of(" \t") == std::string::npos ? line.size() : line.find_first_of(" \t")));
          if (source.empty()) fail(lineNo, "'bparam' must be followed by the path of the BRDF file");
          file_.bparamSource = resolveSource(source);
        } else {
          fail(lineNo, "the first line must be 'analytic' or 'bparam PATH', not '" + t[0] + "'");
        }
      } else if (line.rfind("::begin", 0) == 0 || line.rfind("::end", 0) == 0) {
        const auto t = tokens(line);
        const bool begin = t[0] == "::begin";
        if (!begin && t[0] != "::end") fail(lineNo, "unknown directive '" + t[0] + "'");
        if (t.size() != 2) fail(lineNo, t[0] + " takes one section name");
        if (begin) {
          if (!section.empty())
            fail(lineNo, "'::begin " + t[1] + "' inside section '" + section + "' (opened on line " +
                             std::to_string(sectionLine) + "); sections do not nest");
          section = t[1];
          sectionLine = lineNo;
          if (section == "shader") {
            if (sawShader) fail(lineNo, "a second shader section");
            sawShader = true;
          } else if (section != "parameters" && section != "isFunc") {
            warn(name_ + ":" + std::to_string(lineNo) + ": unknown section '" + section + "' is ignored");
          }
        } else {
          if (section.empty()) fail(lineNo, "'::end " + t[1] + "' without a matching ::begin");
          if (t[1] != section)
            fail(lineNo, "'::end " + t[1] + "' closes section '" + section + "' opened on line " +
                             std::to_string(sectionLine));
          section.clear();
        }
      } else if (section == "parameters") {
        parameter(lineNo, line);
      } else if (section == "shader" || section == "isFunc") {
        BrdfFileSection& s = section == "shader" ? file_.shader : file_.isFunc;
        s.lines.push_back(raw);  // untrimmed, as BRDF Explorer keeps GLSL lines
        s.lineNumbers.push_back(lineNo);
      } else if (section.empty()) {
        fail(lineNo, "text outside a section: '" + line + "'");
      }  // else: inside an unknown section, ignored
      if (end == text.size()) break;
    }
    if (!sawHeader) fail(1, "empty file: expected 'analytic' or 'bparam PATH' on the first line");
    if (!section.empty())
      fail(sectionLine, "section '" + section + "' is never closed (expected '::end " + section + "')");
    if (file_.kind == BrdfFile::Kind::Analytic && !sawShader)
      fail(1,
           "no '::begin shader' section: a .brdf file must define vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, "
           "vec3 Y)");
    checkShaderComplexity(file_.shader);
    checkShaderComplexity(file_.isFunc);
    if (file_.kind == BrdfFile::Kind::Bparam && (!file_.shader.empty() || !file_.isFunc.empty()))
      warn(name_ + ": a .bparam file's shader and isFunc sections are ignored; the BRDF comes from " +
           file_.bparamSource.string());
    return std::move(file_);
  }

 private:
  // The GPU compiler recurses once per operator of an expression and per nesting level; a statement with tens
  // of thousands of terms overflows its stack. Refused here, with the line, before anything is compiled.
  void checkShaderComplexity(const BrdfFileSection& section) const {
    int depth = 0, statementLine = 0;
    std::size_t operators = 0;
    bool blockComment = false;
    for (std::size_t i = 0; i < section.lines.size(); ++i) {
      const std::string& text = section.lines[i];
      const int lineNo = section.lineNumbers[i];
      for (std::size_t k = 0; k < text.size(); ++k) {
        const char c = text[k];
        const char next = k + 1 < text.size() ? text[k + 1] : '\0';
        if (blockComment) {
          if (c == '*' && next == '/') {
            blockComment = false;
            ++k;
          }
          continue;
        }
        if (c == '/' && next == '/') break;
        if (c == '/' && next == '*') {
          blockComment = true;
          ++k;
          continue;
        }
        if (c == ';' || c == '{' || c == '}') operators = 0;
        if (c == '(' || c == '[' || c == '{') {
          if (++depth > kMaxBrdfNesting)
            fail(lineNo, "brackets nested deeper than " + std::to_string(kMaxBrdfNesting) + " levels");
        } else if (c == ')' || c == ']' || c == '}') {
          depth = std::max(0, depth - 1);
        } else if (std::string_view("+-*/%<>=!&|^?:,").find(c) != std::string_view::npos) {
          if (operators == 0) statementLine = lineNo;
          if (++operators > kMaxBrdfStatementOperators)
            fail(statementLine, "a statement with more than " + std::to_string(kMaxBrdfStatementOperators) +
                                    " operators (split it into several statements)");
        }
      }
    }
  }

  std::filesystem::path resolveSource(const std::string& source) const {
    const std::filesystem::path p(source);
    if (p.is_absolute() || folder_.empty()) return p;
    if (std::filesystem::exists(folder_ / p)) return folder_ / p;
    return p;
  }

  std::string name_;
  std::filesystem::path folder_;
  BrdfFile file_;
  std::unordered_map<std::string, int> paramLines_;  // name -> line of its declaration
};

std::string formatNumber(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.9g", v);
  return buffer;
}

}  // namespace

BrdfFile parseBrdfText(std::string_view text, const std::string& displayName,
                       const std::filesystem::path& folder) {
  return Parser(displayName, folder).parse(text);
}

BrdfFile readBrdfFile(const std::filesystem::path& path) {
  const std::string name = path.string();
  const std::string s = readInputText(path, kMaxBrdfFileBytes);
  if (s.find('\0') != std::string::npos) throw Error(name + ": not a text file");
  return parseBrdfText(s, name, path.parent_path());
}

std::string formatBparam(const std::filesystem::path& source, std::span<const ParamDecl> params,
                         const ParamValues& values) {
  std::ostringstream s;
  s << "bparam " << source.string() << "\n\n::begin parameters\n";
  for (const ParamDecl& p : params) {
    const auto it = values.find(p.name);
    const std::array<double, 3> v = it != values.end() ? it->second : p.defaultValue;
    switch (p.type) {
      case ParamType::Float:
        s << "float " << p.name << " " << formatNumber(p.min) << " " << formatNumber(p.max) << " "
          << formatNumber(v[0]) << "\n";
        break;
      case ParamType::Bool:
        s << "bool " << p.name << " " << (v[0] != 0.0 ? 1 : 0) << "\n";
        break;
      case ParamType::Color:
        s << "color " << p.name << " " << formatNumber(v[0]) << " " << formatNumber(v[1]) << " "
          << formatNumber(v[2]) << "\n";
        break;
    }
  }
  s << "::end parameters\n";
  return s.str();
}

void writeBparam(const std::filesystem::path& out, const std::filesystem::path& source,
                 std::span<const ParamDecl> params, const ParamValues& values) {
  writeFileAtomically(out, formatBparam(source, params, values));
}

}  // namespace iblx
