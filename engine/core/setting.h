// The settings of a scene and method that the engine checks. The engine names a setting in its own words;
// the front ends say which flag (tools/cli/cli_options.h, settingFlag) or control (the viewer) sets it, so an
// engine message never quotes a command-line flag.
#pragma once

#include "engine/core/error.h"

#include <string>
#include <string_view>

namespace iblx {

enum class Setting {
  Environment,
  EnvRotation,
  Brdf,
  BrdfParam,
  Object,
  Orbit,
  Zoom,
  ImageSize,
  Method,
  EnvSampler,
  BrdfSampler,
  Sequence,
  MisHeuristic,
  MisSplit,
  RisCandidates,
  MisCompensation,
  Device,
};

// The engine's name: "image size", "BRDF technique", ...
std::string_view settingName(Setting setting);

// An invalid setting. The message is `before` + the setting's name + `after`: what() reads it with the
// engine's name ("unknown method 'bogus'; valid: ..."), a front end with its own (named("--method")).
class SettingError : public Error {
 public:
  SettingError(Setting setting, std::string before, std::string after);
  Setting setting() const { return setting_; }
  std::string named(std::string_view name) const { return before_ + std::string(name) + after_; }

 private:
  Setting setting_;
  std::string before_, after_;
};

}  // namespace iblx
