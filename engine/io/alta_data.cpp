// ALTA data files: the reader with its checks and the writer (alta_data.h).
#include "engine/io/alta_data.h"

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/log.h"

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

namespace iblx {
namespace {

namespace fs = std::filesystem;

constexpr double kMaxAltaValue = 1e15;  // the float headroom of kMaxEnvRadiance (engine/io/env_image.h)
// Text files beyond this are not a measurement iblx can hold as a table anyway.
constexpr std::uint64_t kMaxAltaFileBytes = std::uint64_t(4) << 30;

std::string supportedParams() {
  std::string s;
  for (AltaParam p : altaParams()) s.append(s.empty() ? "" : ", ").append(altaParamName(p));
  return s;
}

bool isAltaFunctionHeader(const std::string& line) {
  return line.rfind("#ALTA FUNC HEADER", 0) == 0;
}

bool isSpace(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && isSpace(s.front())) s.remove_prefix(1);
  while (!s.empty() && isSpace(s.back())) s.remove_suffix(1);
  return s;
}

// A header line "#KEY value" as ALTA writes it: the key runs from after the '#' to the first blank, the value
// is the rest with the blanks around it dropped (so "#PARAM_IN  COS_TH" and "#DIM\t3 1" read as meant); "#"
// followed by a blank, or nothing, is a comment.
struct HeaderLine {
  std::string key, value;
};
std::optional<HeaderLine> splitHeaderLine(std::string_view line) {
  line = trim(line);
  if (line.size() < 2 || line[0] != '#' || isSpace(line[1])) return std::nullopt;
  std::size_t end = 1;
  while (end < line.size() && !isSpace(line[end])) ++end;
  return HeaderLine{std::string(line.substr(1, end - 1)), std::string(trim(line.substr(end)))};
}

// The header's keys and values, and where the body starts.
struct Header {
  std::map<std::string, std::string> keys;
  std::map<std::string, int> lines;  // the line of each key
  std::size_t bodyOffset = 0;        // the first byte after the header
  int bodyLine = 1;
};

Header readHeader(const std::string& text, const std::string& name) {
  Header h;
  std::size_t at = 0;
  int line = 1;
  while (at < text.size()) {
    const std::size_t end = std::min(text.find('\n', at), text.size());
    const std::string_view s = trim(std::string_view(text).substr(at, end - at));
    if (s.empty() || s[0] != '#') break;  // the body
    const std::size_t next = end + 1;
    const std::optional<HeaderLine> entry = splitHeaderLine(s);
    if (entry && entry->key == "BEGIN_STREAM") {
      h.keys["BEGIN_STREAM"] = "";
      h.lines["BEGIN_STREAM"] = line;
      at = next;
      ++line;
      break;
    }
    if (entry && entry->key == "ALTA" && (entry->value == "END HEADER" || entry->value == "HEADER END")) {
      at = next;
      ++line;
      break;
    }
    if (isAltaFunctionHeader(std::string(s)))
      throw Error(name + ":" + std::to_string(line) + ": an ALTA function file, not a data file");
    if (entry && entry->key != "ALTA") {
      h.keys[entry->key] = entry->value;
      h.lines[entry->key] = line;
    }
    at = next;
    ++line;
  }
  h.bodyOffset = std::min(at, text.size());
  h.bodyLine = line;
  return h;
}

double parseNumber(std::string_view token, const std::string& where) {
  double v = 0.0;
  const char* begin = token.data();
  if (!token.empty() && token[0] == '+') ++begin;
  const auto [end, ec] = std::from_chars(begin, token.data() + token.size(), v);
  if (ec != std::errc() || end != token.data() + token.size())
    throw Error(where + ": '" + printableExcerpt(token) + "' is not a number");
  return v;
}

int parseCount(const Header& h, const std::string& key, const std::string& name, int min, long long max) {
  const std::string& v = h.keys.at(key);
  long long n = 0;
  const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), n);
  const std::string where = name + ":" + std::to_string(h.lines.at(key));
  if (ec != std::errc() || end != v.data() + v.size() || n < min || n > max)
    throw Error(where + ": #" + key + " '" + printableExcerpt(v) + "' is not a count from " +
                std::to_string(min) + " to " + std::to_string(max));
  return int(n);
}

// CIE XYZ to linear sRGB (IEC 61966-2-1).
void xyzToRgb(const double xyz[3], double rgb[3]) {
  rgb[0] = 3.2404542 * xyz[0] - 1.5371385 * xyz[1] - 0.4985314 * xyz[2];
  rgb[1] = -0.9692660 * xyz[0] + 1.8760108 * xyz[1] + 0.0415560 * xyz[2];
  rgb[2] = 0.0556434 * xyz[0] - 0.2040259 * xyz[1] + 1.0572252 * xyz[2];
}

}  // namespace

std::string altaOutputName(AltaOutput output) {
  switch (output) {
    case AltaOutput::InvSteradian:
      return "INV_STERADIAN";
    case AltaOutput::InvSteradianCosine:
      return "INV_STERADIAN_COSINE_FACTOR";
    case AltaOutput::RgbColor:
      return "RGB_COLOR";
    case AltaOutput::XyzColor:
      return "XYZ_COLOR";
  }
  return "?";
}

bool altaParamIsTableParam(AltaParam param) {
  return param == AltaParam::RusinThTdPd || param == AltaParam::RusinThTd ||
         param == AltaParam::IsotropicTvTlDphi || param == AltaParam::SphericalTlPlTvPv;
}

AltaParam altaTableParam(AltaParam file) {
  switch (file) {
    case AltaParam::Cartesian:
    case AltaParam::RusinThPhTdPd:
    case AltaParam::Stereographic:
      return AltaParam::SphericalTlPlTvPv;
    case AltaParam::CosTh:  // theta_d's axis has one node: the values depend on theta_h alone
    case AltaParam::CosThTd:
    case AltaParam::Stark2d:  // |B~| = sin theta_d, |H~_p| = cos theta_d sin theta_h
      return AltaParam::RusinThTd;
    case AltaParam::IsotropicTvProjDphi:  // theta_L's axis has one node
    case AltaParam::IsotropicTlTvProjDphi:
    case AltaParam::SchlickTlTkProjDphi:
    case AltaParam::RetroTlTvlProjDphi:
    case AltaParam::Stark3d:
    case AltaParam::Neumann3d:
      return AltaParam::IsotropicTvTlDphi;
    default:  // the four table parametrisations themselves, and those whose functions none of them holds
      return file;
  }
}

bool looksLikeAltaData(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return false;
  // The first 64 header lines within the file's first 64 KiB: a file without a newline, however large, is
  // recognised (or not) from that much.
  std::string head;
  try {
    head = readFileHead(path, 64 << 10);
  } catch (const Error&) {
    return false;
  }
  bool dim = false, param = false;
  std::size_t at = 0;
  for (int k = 0; k < 64 && at < head.size(); ++k) {
    const std::size_t end = head.find('\n', at);
    if (end == std::string::npos && head.size() == (64u << 10)) break;  // a line longer than the head
    const std::string_view line = trim(std::string_view(head).substr(at, std::min(end, head.size()) - at));
    if (line.empty() || line[0] != '#') break;
    if (isAltaFunctionHeader(std::string(line))) return false;
    if (const auto entry = splitHeaderLine(line)) {
      dim = dim || entry->key == "DIM";
      param = param || entry->key == "PARAM_IN";
      if (entry->key == "BEGIN_STREAM") break;
    }
    if (end == std::string::npos) break;
    at = end + 1;
  }
  return dim && param;
}

AltaData loadAltaData(const fs::path& path) {
  const std::string name = path.string();
  const std::uint64_t size = checkInputFile(path);
  checkMemoryBudget(name, size);
  const std::string text = readInputText(path, kMaxAltaFileBytes);
  const Header h = readHeader(text, name);
  if (!h.keys.count("DIM")) throw Error(name + ":1: not an ALTA data file: no #DIM line in its header");
  int inputs = 0, outputs = 0;
  {
    std::istringstream dim(h.keys.at("DIM"));
    const std::string where = name + ":" + std::to_string(h.lines.at("DIM"));
    std::string a, b, extra;
    if (!(dim >> a >> b) || (dim >> extra))
      throw Error(where + ": #DIM needs two counts (inputs and outputs), not '" +
                  printableExcerpt(h.keys.at("DIM")) + "'");
    const auto count = [&](const std::string& token, const char* what) {
      int n = 0;
      const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), n);
      if (ec != std::errc() || end != token.data() + token.size() || n < 1 || n > 6)
        throw Error(where + ": #DIM's " + what + " '" + printableExcerpt(token) +
                    "' is not a whole count from 1 to 6");
      return n;
    };
    inputs = count(a, "input count"), outputs = count(b, "output count");
  }
  if (!h.keys.count("PARAM_IN"))
    throw Error(name + ":1: no #PARAM_IN line: the file does not say how its inputs are parametrised");
  AltaData data;
  const std::string& paramName = h.keys.at("PARAM_IN");
  const std::string paramWhere = name + ":" + std::to_string(h.lines.at("PARAM_IN"));
  const std::optional<AltaParam> param = findAltaParam(paramName);
  if (!param)
    throw Error(paramWhere + ": unknown #PARAM_IN '" + printableExcerpt(paramName) +
                "'; ALTA's parametrisations are " + supportedParams());
  data.param = *param;
  if (inputs != altaParamDimension(data.param))
    throw Error(name + ":" + std::to_string(h.lines.at("DIM")) + ": #DIM gives " + std::to_string(inputs) +
                " inputs, but " + paramName + " has " + std::to_string(altaParamDimension(data.param)));
  std::string outputName = h.keys.count("PARAM_OUT") ? h.keys.at("PARAM_OUT") : "INV_STERADIAN";
  const std::string outputWhere =
      name + ":" + std::to_string(h.keys.count("PARAM_OUT") ? h.lines.at("PARAM_OUT") : h.lines.at("DIM"));
  if (outputName == "INV_STERADIAN")
    data.output = AltaOutput::InvSteradian;
  else if (outputName == "INV_STERADIAN_COSINE_FACTOR")
    data.output = AltaOutput::InvSteradianCosine;
  else if (outputName == "RGB_COLOR")
    data.output = AltaOutput::RgbColor;
  else if (outputName == "XYZ_COLOR")
    data.output = AltaOutput::XyzColor;
  else if (outputName == "ENERGY")
    throw Error(outputWhere + ": #PARAM_OUT ENERGY has no unit iblx can render; it reads INV_STERADIAN, " +
                "INV_STERADIAN_COSINE_FACTOR, RGB_COLOR and XYZ_COLOR");
  else
    throw Error(outputWhere + ": unknown #PARAM_OUT '" + printableExcerpt(outputName) +
                "'; iblx reads INV_STERADIAN, INV_STERADIAN_COSINE_FACTOR, RGB_COLOR and XYZ_COLOR");
  const bool colour = data.output == AltaOutput::RgbColor || data.output == AltaOutput::XyzColor;
  if (colour ? outputs != 3 : (outputs != 1 && outputs != 3))
    throw Error(name + ":" + std::to_string(h.lines.at("DIM")) + ": #DIM gives " + std::to_string(outputs) +
                " outputs; " + outputName + (colour ? " has 3" : " has 1 (grey) or 3 (one per channel)"));
  int interval = 0;
  if (h.keys.count("VS")) interval = parseCount(h, "VS", name, 0, 2);
  const std::size_t width = std::size_t(inputs + outputs + interval);

  std::vector<double> values;
  const bool binary = h.keys.count("FORMAT") && h.keys.at("FORMAT") == "binary";
  if (h.keys.count("FORMAT") && !binary && h.keys.at("FORMAT") != "text")
    throw Error(name + ":" + std::to_string(h.lines.at("FORMAT")) + ": #FORMAT '" +
                printableExcerpt(h.keys.at("FORMAT")) + "' is neither text nor binary");
  if (binary) {
    const auto expect = [&](const std::string& key, const std::string& value) {
      if (!h.keys.count(key))
        throw Error(name + ": the binary stream's header has no #" + key + " (expected '" + value + "')");
      if (h.keys.at(key) != value)
        throw Error(name + ":" + std::to_string(h.lines.at(key)) + ": #" + key + " '" +
                    printableExcerpt(h.keys.at(key)) + "' is not supported (iblx reads " + value + ")");
    };
    expect("VERSION", "0");
    expect("PRECISION", "ieee754-double");
    expect("ENDIAN", "little");
    if (!h.keys.count("SAMPLE_COUNT"))
      throw Error(name + ": the binary stream's header has no #SAMPLE_COUNT");
    if (!h.keys.count("BEGIN_STREAM")) throw Error(name + ": the binary file has no #BEGIN_STREAM line");
    const std::uint64_t count = std::uint64_t(parseCount(h, "SAMPLE_COUNT", name, 1, 2000000000));
    const std::uint64_t bytes = count * width * 8;
    checkMemoryBudget(name + ": " + std::to_string(count) + " samples", bytes * 2);
    const std::string end = "\n#END_STREAM";
    const std::uint64_t available = text.size() - h.bodyOffset;
    if (available < bytes + end.size() || text.compare(h.bodyOffset + bytes, end.size(), end) != 0)
      throw Error(name + ": the binary stream holds " + std::to_string(available) +
                  " bytes after #BEGIN_STREAM, but #SAMPLE_COUNT " + std::to_string(count) + " x " +
                  std::to_string(width) + " doubles needs " + std::to_string(bytes) +
                  " followed by a line #END_STREAM");
    values.resize(count * width);
    for (std::size_t k = 0; k < values.size(); ++k) {
      std::uint64_t bits = 0;
      for (int b = 0; b < 8; ++b)
        bits |= std::uint64_t(static_cast<unsigned char>(text[h.bodyOffset + 8 * k + std::size_t(b)]))
                << (8 * b);
      values[k] = std::bit_cast<double>(bits);
    }
  } else {
    // The samples are counted before any is stored, so that a file whose values would outgrow the memory
    // budget (short lines hold several doubles' worth of values per byte) is refused before it is parsed.
    std::uint64_t sampleLines = 0;
    for (std::size_t at = h.bodyOffset; at < text.size();) {
      const std::size_t end = std::min(text.find('\n', at), text.size());
      const std::string_view s = trim(std::string_view(text).substr(at, end - at));
      if (!s.empty() && s[0] != '#') ++sampleLines;
      at = end + 1;
    }
    checkMemoryBudget(name + ": " + std::to_string(sampleLines) + " samples of " + std::to_string(width) +
                          " values, with the file's text",
                      text.size() + sampleLines * (width + std::size_t(inputs) + 3) * sizeof(double));
    values.reserve(std::size_t(sampleLines) * width);
    std::size_t at = h.bodyOffset;
    int line = h.bodyLine;
    while (at < text.size()) {
      const std::size_t end = std::min(text.find('\n', at), text.size());
      std::string_view s(text.data() + at, end - at);
      const std::string where = name + ":" + std::to_string(line);
      std::size_t count = 0, p = 0;
      if (!s.empty() && s[0] != '#') {
        while (p < s.size()) {
          while (p < s.size() && (s[p] == ' ' || s[p] == '\t' || s[p] == '\r')) ++p;
          if (p >= s.size()) break;
          std::size_t q = p;
          while (q < s.size() && s[q] != ' ' && s[q] != '\t' && s[q] != '\r') ++q;
          values.push_back(parseNumber(s.substr(p, q - p), where));
          ++count;
          p = q;
        }
        if (count != 0 && count != width)
          throw Error(where + ": a sample has " + std::to_string(count) + " values, but #DIM " +
                      std::to_string(inputs) + " " + std::to_string(outputs) +
                      (interval ? " and #VS " + std::to_string(interval) : std::string()) + " need " +
                      std::to_string(width));
      }
      at = end + 1;
      ++line;
    }
  }
  data.samples = values.size() / width;
  if (data.samples == 0) throw Error(name + ": no samples after the header");
  data.x.resize(data.samples * std::size_t(inputs));
  data.rgb.resize(data.samples * 3);
  for (std::size_t i = 0; i < data.samples; ++i) {
    const double* v = values.data() + i * width;
    for (int k = 0; k < inputs + outputs; ++k)
      if (!std::isfinite(v[k]) || std::abs(v[k]) > kMaxAltaValue)
        throw Error(name + ": sample " + std::to_string(i) + " holds " + std::to_string(v[k]) + " at value " +
                    std::to_string(k + 1) + ", which is not finite or above 1e15");
    for (int k = 0; k < inputs; ++k) data.x[i * std::size_t(inputs) + std::size_t(k)] = v[k];
    double rgb[3];
    const double* y = v + inputs;
    if (data.output == AltaOutput::XyzColor)
      xyzToRgb(y, rgb);
    else
      for (int c = 0; c < 3; ++c) rgb[c] = y[outputs == 3 ? c : 0];
    for (int c = 0; c < 3; ++c) {
      if (rgb[c] < 0.0) rgb[c] = 0.0, ++data.negativeEntries;
      data.rgb[3 * i + std::size_t(c)] = rgb[c];
    }
  }
  if (data.negativeEntries > 0)
    warn(name + ": " + std::to_string(data.negativeEntries) + " of " + std::to_string(3 * data.samples) +
         " values are negative; they are treated as 0");
  return data;
}

void writeAltaData(const fs::path& path, const AltaData& data, bool binary) {
  const int inputs = altaParamDimension(data.param);
  const int outputs = data.output == AltaOutput::RgbColor || data.output == AltaOutput::XyzColor ? 3 : 1;
  std::string out = "#DIM " + std::to_string(inputs) + " " + std::to_string(outputs) + "\n";
  out += "#PARAM_IN " + altaParamName(data.param) + "\n#PARAM_OUT " + altaOutputName(data.output) + "\n";
  std::vector<double> row;
  const auto sampleRow = [&](std::size_t i) {
    row.assign(data.x.begin() + std::ptrdiff_t(i * std::size_t(inputs)),
               data.x.begin() + std::ptrdiff_t((i + 1) * std::size_t(inputs)));
    const double* c = data.rgb.data() + 3 * i;
    if (outputs == 3)
      row.insert(row.end(), c, c + 3);
    else
      row.push_back((c[0] + c[1] + c[2]) / 3.0);
  };
  if (binary) {
    out += "#FORMAT binary\n#VERSION 0\n#PRECISION ieee754-double\n#SAMPLE_COUNT " +
           std::to_string(data.samples) + "\n#ENDIAN little\n#BEGIN_STREAM\n";
    for (std::size_t i = 0; i < data.samples; ++i) {
      sampleRow(i);
      for (double v : row) {
        const auto bits = std::bit_cast<std::uint64_t>(v);
        for (int b = 0; b < 8; ++b) out.push_back(static_cast<char>(bits >> (8 * b)));
      }
    }
    out += "\n#END_STREAM\n";
  } else {
    out += "#ALTA END HEADER\n";
    char buffer[32];
    for (std::size_t i = 0; i < data.samples; ++i) {
      sampleRow(i);
      for (std::size_t k = 0; k < row.size(); ++k) {
        std::snprintf(buffer, sizeof(buffer), "%.9g", row[k]);
        out.append(k ? " " : "").append(buffer);
      }
      out += "\n";
    }
  }
  writeFileAtomically(path, std::span(reinterpret_cast<const unsigned char*>(out.data()), out.size()));
}

}  // namespace iblx
