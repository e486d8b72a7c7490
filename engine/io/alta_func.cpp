// ALTA function files: the parser and the writer (alta_func.h).
#include "engine/io/alta_func.h"

#include "engine/core/error.h"
#include "engine/core/file_io.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <optional>
#include <sstream>

namespace iblx {
namespace {

constexpr double kPiD = std::numbers::pi;
constexpr std::uint64_t kMaxAltaFileBytes = 64ull << 20;

// The parametrisations a rational function may be written over.

// Each nonlinear plugin's parameter names, in ALTA's file order.
std::vector<std::string> lobeParamNames(AltaLobeKind k) {
  switch (k) {
    case AltaLobeKind::Diffuse:
      return {"kd"};
    case AltaLobeKind::Blinn:
      return {"Ks", "N"};
    case AltaLobeKind::Beckmann:
      return {"Ks", "a"};
    case AltaLobeKind::Ward:
      return {"Ks", "ax", "ay"};
    case AltaLobeKind::Rational:
      return {};
  }
  return {};
}

struct Line {
  int number;
  std::vector<std::string> tokens;
  std::string text;  // trimmed
};

std::vector<std::string> splitTokens(std::string_view s) {
  std::vector<std::string> out;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t')) ++i;
    std::size_t j = i;
    while (j < s.size() && s[j] != ' ' && s[j] != '\t') ++j;
    if (j > i) out.emplace_back(s.substr(i, j - i));
    i = j;
  }
  return out;
}

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

class Parser {
 public:
  Parser(std::string_view text, std::string name) : name_(std::move(name)) {
    int number = 0;
    std::size_t pos = 0;
    while (pos < text.size()) {
      const std::size_t end = std::min(text.find('\n', pos), text.size());
      std::string_view raw = text.substr(pos, end - pos);
      ++number;
      pos = end + 1;
      while (!raw.empty() && (raw.back() == '\r' || raw.back() == ' ' || raw.back() == '\t'))
        raw.remove_suffix(1);
      while (!raw.empty() && (raw.front() == ' ' || raw.front() == '\t')) raw.remove_prefix(1);
      if (raw.find('\0') != std::string_view::npos) fail(number, "a NUL byte: not a text file");
      lines_.push_back({number, splitTokens(raw), std::string(raw)});
    }
    lastLine_ = std::max(1, number);
  }

  AltaFunc parse() {
    if (lines_.empty() || lines_[0].text != "#ALTA FUNC HEADER")
      fail(1, "not an ALTA function file: the first line must be '#ALTA FUNC HEADER'");
    AltaFunc f;
    std::size_t i = 1;
    int dimLine = 0, paramInLine = 0;
    std::string paramInName;
    bool ended = false;
    for (; i < lines_.size(); ++i) {
      const Line& l = lines_[i];
      if (l.text.empty()) continue;
      if (l.text == "#ALTA HEADER END") {
        ended = true;
        ++i;
        break;
      }
      if (l.text[0] != '#') fail(l.number, "'" + clip(l.text) + "' in the header: header lines start with #");
      const std::string key = l.tokens[0].substr(1);
      if (key == "CMD") {
        const std::size_t start = l.text.find_first_not_of(" \t", 4);
        f.command = start == std::string::npos ? "" : l.text.substr(start);
      } else if (key == "DIM") {
        if (l.tokens.size() != 3) fail(l.number, "#DIM needs two integers: nX nY");
        f.dimX = parseInt(l, 1, "#DIM nX");
        f.dimY = parseInt(l, 2, "#DIM nY");
        if (f.dimX < 1 || f.dimX > 6) fail(l.number, "#DIM nX = " + l.tokens[1] + ": must be in [1, 6]");
        if (f.dimY != 1 && f.dimY != 3)
          fail(l.number, "#DIM nY = " + l.tokens[2] + ": iblx reads 1 (grey) or 3 (RGB) output channels");
        dimLine = l.number;
      } else if (key == "PARAM_IN") {
        if (l.tokens.size() != 2) fail(l.number, "#PARAM_IN needs one parametrisation name");
        paramInName = l.tokens[1];
        paramInLine = l.number;
      } else if (key == "PARAM_OUT") {
        if (l.tokens.size() != 2) fail(l.number, "#PARAM_OUT needs one output name");
        f.paramOut = l.tokens[1];
      }
      // Other header keys (ALTA's export-append lines, comments) do not change the function.
    }
    if (!ended) fail(lastLine_, "truncated file: no '#ALTA HEADER END' line");
    if (dimLine == 0) fail(lastLine_, "missing header line '#DIM nX nY'");
    // The basis of rational functions: the plugin #CMD names (--func rational_function_chebychev, ...).
    const std::string cmd = lower(f.command);
    if (cmd.find("chebychev") != std::string::npos || cmd.find("chebyshev") != std::string::npos)
      f.basis = AltaBasis::Chebyshev;
    else if (cmd.find("legendre") != std::string::npos)
      f.basis = AltaBasis::Legendre;

    i = nextContent(i);
    if (i >= lines_.size()) fail(lastLine_, "truncated file: no '#FUNC' block after the header");
    while (i < lines_.size()) {
      const Line& l = lines_[i];
      if (l.tokens[0] != "#FUNC" || l.tokens.size() != 2)
        fail(l.number, "expected '#FUNC <plugin>', got '" + clip(l.text) + "'");
      if (int(f.lobes.size()) == kAltaMaxLobes)
        fail(l.number, "more than " + std::to_string(kAltaMaxLobes) + " lobes");
      AltaLobe lobe;
      lobe.line = l.number;
      const std::string& plugin = l.tokens[1];
      if (plugin == "nonlinear_function_diffuse") {
        lobe.kind = AltaLobeKind::Diffuse;
      } else if (plugin == "nonlinear_function_blinn") {
        lobe.kind = AltaLobeKind::Blinn;
      } else if (plugin == "nonlinear_function_beckmann") {
        lobe.kind = AltaLobeKind::Beckmann;
      } else if (plugin == "nonlinear_function_ward") {
        lobe.kind = AltaLobeKind::Ward;
      } else if (plugin == "rational_function" || plugin == "rational_function_chebychev" ||
                 plugin == "rational_function_legendre") {
        lobe.kind = AltaLobeKind::Rational;
        if (plugin == "rational_function_chebychev") f.basis = AltaBasis::Chebyshev;
        if (plugin == "rational_function_legendre") f.basis = AltaBasis::Legendre;
      } else {
        fail(l.number,
             "unknown plugin '" + clip(plugin) +
                 "'; iblx reads nonlinear_function_diffuse, nonlinear_function_blinn, "
                 "nonlinear_function_beckmann, nonlinear_function_ward and rational_function (monomial, "
                 "chebychev or legendre)");
      }
      if (lobe.kind == AltaLobeKind::Rational) {
        if (paramInLine == 0) fail(l.number, "a rational function needs the header line '#PARAM_IN <name>'");
        const std::optional<AltaParam> known = findAltaParam(paramInName);
        if (known) f.paramIn = *known;
        if (!known)
          fail(paramInLine, "#PARAM_IN " + clip(paramInName) +
                                ": not one of ALTA's parametrisations: " + altaSupportedParams());
        if (f.dimX != altaParamDimension(f.paramIn))
          fail(dimLine, "#DIM nX = " + std::to_string(f.dimX) + " but " + paramInName + " has " +
                            std::to_string(altaParamDimension(f.paramIn)) + " dimensions");
        i = parseRational(i + 1, f, lobe);
        std::size_t terms = 0;
        for (const auto& ch : lobe.rational.channels) terms += ch.p.size() + ch.q.size();
        for (const AltaLobe& earlier : f.lobes)
          for (const auto& ch : earlier.rational.channels) terms += ch.p.size() + ch.q.size();
        if (terms > std::size_t(kAltaMaxFileTerms))
          fail(lobe.line, "the rational functions up to this one have " + std::to_string(terms) +
                              " terms, more than the " + std::to_string(kAltaMaxFileTerms) +
                              " iblx compiles into one shader");
      } else {
        i = parseNonlinear(i + 1, f, lobe);
      }
      f.lobes.push_back(std::move(lobe));
    }
    return f;
  }

 private:
  [[noreturn]] void fail(int line, const std::string& problem) const {
    throw Error(name_ + ":" + std::to_string(line) + ": " + problem);
  }
  static std::string clip(const std::string& s) { return s.size() > 60 ? s.substr(0, 57) + "..." : s; }

  // The next line holding something other than blanks and "# " comments.
  std::size_t nextContent(std::size_t i) const {
    while (i < lines_.size() &&
           (lines_[i].text.empty() || lines_[i].text == "#" || lines_[i].text.rfind("# ", 0) == 0))
      ++i;
    return i;
  }

  double parseNumber(const Line& l, std::size_t token, const std::string& what) const {
    if (token >= l.tokens.size()) fail(l.number, what + " is missing");
    const std::string& t = l.tokens[token];
    double v = 0.0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc() || end != t.data() + t.size())
      fail(l.number, what + " '" + clip(t) + "' is not a number");
    if (!std::isfinite(v)) fail(l.number, what + " " + clip(t) + " is not finite");
    // The GPU evaluates in float: a larger literal would become infinity there and the lobe silently 0.
    if (std::abs(v) > double(std::numeric_limits<float>::max()))
      fail(l.number,
           what + " " + clip(t) + " is beyond float's range (3.4e38), in which the GPU evaluates it");
    return v;
  }
  int parseInt(const Line& l, std::size_t token, const std::string& what) const {
    if (token >= l.tokens.size()) fail(l.number, what + " is missing");
    const std::string& t = l.tokens[token];
    long long v = 0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc() || end != t.data() + t.size())
      fail(l.number, what + " '" + clip(t) + "' is not an integer");
    if (v < -1000000 || v > 1000000) fail(l.number, what + " " + t + " is absurdly large");
    return int(v);
  }

  std::size_t parseNonlinear(std::size_t i, const AltaFunc& f, AltaLobe& lobe) const {
    const auto names = lobeParamNames(lobe.kind);
    const std::string lobeName = altaLobeName(lobe.kind);
    std::string list;
    for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
    for (int c = 0; c < f.dimY; ++c) {
      std::vector<double> values;
      for (std::size_t k = 0; k < names.size(); ++k) {
        i = nextContent(i);
        const std::string have = "the " + lobeName + " lobe (#FUNC at line " + std::to_string(lobe.line) +
                                 ") has " + std::to_string(c * int(names.size()) + int(k)) + " of its " +
                                 std::to_string(f.dimY * int(names.size())) + " values: " + list +
                                 " for each of #DIM's " + std::to_string(f.dimY) + " channels";
        if (i >= lines_.size()) fail(lastLine_, "truncated file: " + have);
        const Line& l = lines_[i];
        if (l.tokens[0] == "#FUNC") fail(l.number, have);
        if (l.tokens.size() != 2 || lower(l.tokens[0]) != lower(names[k]))
          fail(l.number, "expected '" + names[k] + " <value>' (channel " + std::to_string(c + 1) +
                             " of the " + lobeName + " lobe), got '" + clip(l.text) + "'");
        const double v = parseNumber(l, 1, lobeName + " " + names[k]);
        if (names[k] != "Ks" && names[k] != "kd" && !(v > 0.0) && !(names[k] == "N" && v == 0.0))
          fail(l.number, lobeName + " " + names[k] + " = " + l.tokens[1] + ": must be positive");
        if (std::abs(v) > 1e12) fail(l.number, lobeName + " " + names[k] + " = " + l.tokens[1] + ": absurd");
        values.push_back(v);
        ++i;
      }
      lobe.values.push_back(std::move(values));
    }
    i = nextContent(i);
    if (i < lines_.size() && lines_[i].tokens[0] != "#FUNC")
      fail(lines_[i].number, "'" + clip(lines_[i].text) + "' after the " + lobeName + " lobe's " +
                                 std::to_string(f.dimY * int(names.size())) + " values (" + list +
                                 " for each of " + std::to_string(f.dimY) + " channels): too many values");
    return i;
  }

  std::size_t parseRational(std::size_t i, const AltaFunc& f, AltaLobe& lobe) const {
    AltaRational& r = lobe.rational;
    const auto box = [&](const char* key, std::vector<double>& out) {
      i = nextContent(i);
      if (i >= lines_.size()) fail(lastLine_, std::string("truncated file: no ") + key + " line");
      const Line& l = lines_[i];
      if (l.tokens[0] != key)
        fail(l.number, std::string("expected '") + key + " x1 .. xnX', got '" + clip(l.text) + "'");
      if (int(l.tokens.size()) != f.dimX + 1)
        fail(l.number, std::string(key) + " has " + std::to_string(l.tokens.size() - 1) +
                           " values; #DIM nX is " + std::to_string(f.dimX));
      for (int k = 0; k < f.dimX; ++k) out.push_back(parseNumber(l, std::size_t(k) + 1, key));
      ++i;
      return l.number;
    };
    box("#MIN", r.min);
    const int maxLine = box("#MAX", r.max);
    for (int k = 0; k < f.dimX; ++k)
      if (!(r.max[std::size_t(k)] > r.min[std::size_t(k)]))
        fail(maxLine, "#MAX must exceed #MIN in every dimension (dimension " + std::to_string(k + 1) + ")");
    for (int c = 0; c < f.dimY; ++c) {
      AltaRationalChannel ch;
      const auto count = [&](const char* key, int least) {
        i = nextContent(i);
        if (i >= lines_.size())
          fail(lastLine_, std::string("truncated file: no ") + key + " line for channel " +
                              std::to_string(c + 1) + " of #DIM's " + std::to_string(f.dimY));
        const Line& l = lines_[i];
        if (l.tokens[0] != key || l.tokens.size() != 2)
          fail(l.number, std::string("expected '") + key + " <count>' for channel " + std::to_string(c + 1) +
                             ", got '" + clip(l.text) + "'");
        const int n = parseInt(l, 1, key);
        if (n < least || n > kAltaMaxTerms)
          fail(l.number, std::string(key) + " " + l.tokens[1] + ": must be in [" + std::to_string(least) +
                             ", " + std::to_string(kAltaMaxTerms) + "]");
        ++i;
        return n;
      };
      const int np = count("#NP", 0);
      const int nq = count("#NQ", 1);
      for (int t = 0; t < np + nq; ++t) {
        i = nextContent(i);
        const std::string which = std::string(t < np ? "P" : "Q") + " term " +
                                  std::to_string(t < np ? t + 1 : t - np + 1) + " of channel " +
                                  std::to_string(c + 1);
        if (i >= lines_.size()) fail(lastLine_, "truncated file: " + which + " is missing");
        const Line& l = lines_[i];
        if (l.tokens[0][0] == '#')
          fail(l.number, which + " is missing (#NP " + std::to_string(np) + ", #NQ " + std::to_string(nq) +
                             "), got '" + clip(l.text) + "'");
        if (int(l.tokens.size()) != f.dimX + 1)
          fail(l.number, which + " has " + std::to_string(l.tokens.size()) +
                             " numbers; #DIM nX = " + std::to_string(f.dimX) + " needs " +
                             std::to_string(f.dimX) + " degrees and a coefficient");
        AltaTerm term;
        for (int k = 0; k < f.dimX; ++k) {
          const int d = parseInt(l, std::size_t(k), "degree");
          if (d < 0 || d > kAltaMaxDegree)
            fail(l.number, "degree " + l.tokens[std::size_t(k)] + ": must be in [0, " +
                               std::to_string(kAltaMaxDegree) + "]");
          term.degrees.push_back(d);
        }
        term.coefficient = parseNumber(l, std::size_t(f.dimX), "coefficient");
        (t < np ? ch.p : ch.q).push_back(std::move(term));
        ++i;
      }
      r.channels.push_back(std::move(ch));
    }
    i = nextContent(i);
    if (i < lines_.size() && lines_[i].tokens[0] != "#FUNC")
      fail(lines_[i].number, "'" + clip(lines_[i].text) + "' after the rational function's " +
                                 std::to_string(f.dimY) + " channels: too many terms for their #NP and #NQ");
    return i;
  }

  std::string name_;
  std::vector<Line> lines_;
  int lastLine_ = 1;
};

std::string number(double v) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

}  // namespace

std::string altaBasisName(AltaBasis b) {
  return b == AltaBasis::Monomial ? "monomial" : b == AltaBasis::Chebyshev ? "Chebyshev" : "Legendre";
}
std::string altaSupportedParams() {
  std::string s;
  for (AltaParam p : altaParams()) s += (s.empty() ? "" : ", ") + altaParamName(p);
  return s;
}
std::string altaLobeName(AltaLobeKind k) {
  switch (k) {
    case AltaLobeKind::Diffuse:
      return "diffuse";
    case AltaLobeKind::Blinn:
      return "blinn";
    case AltaLobeKind::Beckmann:
      return "beckmann";
    case AltaLobeKind::Ward:
      return "ward";
    case AltaLobeKind::Rational:
      return "rational";
  }
  return "?";
}

AltaFunc parseAltaFunc(std::string_view text, const std::string& displayName) {
  return Parser(text, displayName).parse();
}

AltaFunc loadAltaFunc(const std::filesystem::path& path) {
  return parseAltaFunc(readInputText(path, kMaxAltaFileBytes), path.string());
}

bool looksLikeAltaFunc(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;
  std::ifstream in(path, std::ios::binary);
  char head[18] = {};
  in.read(head, sizeof head);
  return in.gcount() >= 17 && std::string_view(head, 17) == "#ALTA FUNC HEADER" &&
         (in.gcount() == 17 || head[17] == '\n' || head[17] == '\r');
}

std::string formatAltaFunc(const AltaFunc& f) {
  std::ostringstream s;
  s << "#ALTA FUNC HEADER\n#CMD " << f.command << "\n#DIM " << f.dimX << " " << f.dimY << "\n";
  s << "#PARAM_IN " << altaParamName(f.paramIn) << "\n";
  if (!f.paramOut.empty()) s << "#PARAM_OUT " << f.paramOut << "\n";
  s << "#ALTA HEADER END\n\n";
  for (const AltaLobe& lobe : f.lobes) {
    if (lobe.kind == AltaLobeKind::Rational) {
      s << "#FUNC rational_function\n#MIN";
      for (double v : lobe.rational.min) s << " " << number(v);
      s << "\n#MAX";
      for (double v : lobe.rational.max) s << " " << number(v);
      s << "\n";
      for (const auto& ch : lobe.rational.channels) {
        s << "#NP " << ch.p.size() << "\n#NQ " << ch.q.size() << "\n";
        for (const auto* terms : {&ch.p, &ch.q})
          for (const AltaTerm& t : *terms) {
            for (int d : t.degrees) s << d << "\t";
            s << number(t.coefficient) << "\n";
          }
      }
    } else {
      s << "#FUNC nonlinear_function_" << altaLobeName(lobe.kind) << "\n";
      const auto names = lobeParamNames(lobe.kind);
      for (const auto& channel : lobe.values)
        for (std::size_t k = 0; k < names.size(); ++k) s << names[k] << " " << number(channel[k]) << "\n";
    }
    s << "\n";
  }
  return s.str();
}

void writeAltaFunc(const std::filesystem::path& path, const AltaFunc& func) {
  writeFileAtomically(path, formatAltaFunc(func));
}

}  // namespace iblx
