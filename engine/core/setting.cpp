// Setting names (setting.h).
#include "engine/core/setting.h"

namespace iblx {

std::string_view settingName(Setting setting) {
  switch (setting) {
    case Setting::Environment:
      return "environment";
    case Setting::EnvRotation:
      return "environment rotation";
    case Setting::Brdf:
      return "BRDF";
    case Setting::BrdfParam:
      return "BRDF parameter";
    case Setting::Object:
      return "object";
    case Setting::Orbit:
      return "camera orbit";
    case Setting::Zoom:
      return "zoom";
    case Setting::ImageSize:
      return "image size";
    case Setting::Method:
      return "method";
    case Setting::EnvSampler:
      return "env technique";
    case Setting::BrdfSampler:
      return "BRDF technique";
    case Setting::Sequence:
      return "sequence";
    case Setting::MisHeuristic:
      return "MIS heuristic";
    case Setting::MisSplit:
      return "MIS split";
    case Setting::RisCandidates:
      return "RIS candidates";
    case Setting::MisCompensation:
      return "MIS compensation";
    case Setting::Device:
      return "device";
  }
  return "setting";
}

SettingError::SettingError(Setting setting, std::string before, std::string after)
    : Error(before + std::string(settingName(setting)) + after),
      setting_(setting),
      before_(std::move(before)),
      after_(std::move(after)) {}

}  // namespace iblx
