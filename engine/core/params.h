// BRDF parameter declarations and values: what a built-in BRDF declares in the registry and what a .brdf
// file's
// `::begin parameters` section declares, set from `--param`, .bparam files and (later) the viewer's sliders.
#pragma once

#include <array>
#include <map>
#include <string>

namespace iblx {

enum class ParamType { Float, Color, Bool };

struct ParamDecl {
  std::string name;
  ParamType type = ParamType::Float;
  double min = 0.0, max = 1.0;                  // bounds, inclusive (every channel for colors)
  std::array<double, 3> defaultValue{0, 0, 0};  // floats and bools use [0]
  std::string description;
};

using ParamValues = std::map<std::string, std::array<double, 3>>;

}  // namespace iblx
