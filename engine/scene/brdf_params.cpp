// BRDF parameters: resolution, packing and the GLSL block (brdf_params.h).
#include "engine/scene/brdf_params.h"

#include "engine/core/setting.h"
#include "engine/core/join.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <sstream>

namespace iblx {

std::string formatParamValue(const ParamDecl& p, const std::array<double, 3>& v) {
  std::ostringstream s;
  if (p.type == ParamType::Color)
    s << v[0] << "," << v[1] << "," << v[2];
  else
    s << v[0];
  return s.str();
}

ParamValues resolveParams(const BrdfInfo& brdf,
                          const std::vector<std::pair<std::string, std::string>>& given) {
  ParamValues values;
  for (const auto& p : brdf.params) values[p.name] = p.defaultValue;
  for (const auto& [name, text] : given) {
    const auto invalid = [&](const std::string& problem) {
      return SettingError(Setting::BrdfParam, "", " " + name + "=" + text + ": " + problem);
    };
    auto decl = std::find_if(brdf.params.begin(), brdf.params.end(),
                             [&](const ParamDecl& p) { return p.name == name; });
    if (decl == brdf.params.end()) {
      throw SettingError(
          Setting::BrdfParam, "",
          " " + name + ": BRDF '" + brdf.name + "' has no parameter '" + name +
              (brdf.params.empty() ? "'; it has no parameters"
                                   : "'; its parameters: " + joinNames(brdf.params, &ParamDecl::name)));
    }
    std::array<double, 3> v{0, 0, 0};
    const int count = decl->type == ParamType::Color ? 3 : 1;
    std::string rest = text;
    if (decl->type == ParamType::Bool && (rest == "true" || rest == "false"))
      rest.assign(1, rest == "true"
                         ? '1'
                         : '0');  // assign(count, char): GCC 12 warns falsely on operator=(const char*)
    int parsed = 0;
    std::istringstream in(rest);
    std::string item;
    if (!rest.empty() && rest.back() == ',') throw invalid("trailing comma");
    while (std::getline(in, item, ',')) {
      if (parsed >= 3) throw invalid("too many values");
      char* end = nullptr;
      v[parsed] = std::strtod(item.c_str(), &end);
      if (item.empty() || end != item.c_str() + item.size() || !std::isfinite(v[parsed]))
        throw invalid("'" + item + "' is not a number");
      ++parsed;
    }
    if (decl->type == ParamType::Color && parsed == 1) v = {v[0], v[0], v[0]}, parsed = 3;  // grey shorthand
    if (parsed != count)
      throw invalid(std::string("expected ") + (count == 3 ? "a color r,g,b" : "one value"));
    if (decl->type == ParamType::Bool && v[0] != 0.0 && v[0] != 1.0)
      throw invalid("expected 0, 1, true or false");
    for (int c = 0; c < count; ++c)
      if (v[c] < decl->min || v[c] > decl->max) {
        std::ostringstream range;
        range << "out of range [" << decl->min << ", " << decl->max << "]";
        throw invalid(range.str());
      }
    values[name] = v;
  }
  return values;
}

std::vector<float> packParams(const BrdfInfo& brdf, const ParamValues& values) {
  std::vector<float> packed(4 * std::max<size_t>(brdf.params.size(), 1), 0.0f);
  for (size_t i = 0; i < brdf.params.size(); ++i) {
    const auto& p = brdf.params[i];
    const auto& v = values.at(p.name);
    if (p.type == ParamType::Bool) {
      const uint32_t bit = v[0] != 0.0 ? 1u : 0u;  // GLSL bool in a buffer is a 32-bit integer
      std::memcpy(&packed[4 * i], &bit, sizeof bit);
    } else {
      for (int c = 0; c < (p.type == ParamType::Color ? 3 : 1); ++c) packed[4 * i + c] = float(v[c]);
    }
  }
  return packed;
}

std::string paramBlockGlsl(const BrdfInfo& brdf) {
  std::ostringstream s;
  s << "layout(std430, set = 3, binding = 0) readonly buffer BrdfParamBlock {\n";
  if (brdf.params.empty()) s << "  vec4 iblxUnusedParam;\n";
  for (size_t i = 0; i < brdf.params.size(); ++i) {
    const auto& p = brdf.params[i];
    // One 16-byte slot per parameter (std430: float arrays have a 4-byte stride).
    if (p.type == ParamType::Color)
      s << "  vec3 " << p.name << "; float iblxPad" << i << ";\n";
    else
      s << "  " << (p.type == ParamType::Bool ? "bool " : "float ") << p.name << "; float iblxPad" << i
        << "[3];\n";
  }
  s << "};\n";
  return s.str();
}

}  // namespace iblx
