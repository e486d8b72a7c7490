// The shared flags of docs/DESIGN.md §8, parsed once into one RenderSpec for every subcommand that renders.
#pragma once

#include "engine/io/image_write.h"
#include "engine/scene/scene.h"

#include <cstdint>
#include <functional>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace iblx::cli {

struct RenderSpec {
  SceneSpec scene;
  MethodSpec method;
  uint32_t samplesPerPass = 32;
  uint32_t passes = 32;
  std::optional<double> timeBudgetSeconds;  // --time: run passes until this much wall time has passed
  uint32_t seed = 1;
  std::string out;
  DisplaySettings display;  // .png output
  bool reference = false;
  std::filesystem::path referenceFile;  // --reference-file: a ground truth written by `iblx reference`
  bool json = false;
  bool listMethods = false;
  std::filesystem::path saveBparam;  // render: write the BRDF's parameter values as a .bparam
  std::string device;
  bool validation = false;
};

// A tiny flag parser: each subcommand registers what it accepts, so an unknown flag is an error that lists
// them.
class ArgParser {
 public:
  explicit ArgParser(std::string command) : command_(std::move(command)) {}
  void value(const std::string& flag, const std::string& metavar, const std::string& help,
             std::function<void(const std::string&)> apply);
  void toggle(const std::string& flag, const std::string& help, std::function<void()> apply);
  void parse(const std::vector<std::string>& args) const;  // throws iblx::Error
  // Registers --help, parses, and prints the usage when --help was given; true then (the command returns).
  bool parseOrShowHelp(const std::vector<std::string>& args);
  std::string usage() const;

 private:
  struct Option {
    std::string flag, metavar, help;
    std::function<void(const std::string&)> apply;
    bool takesValue;
  };
  std::string command_;
  std::vector<Option> options_;
};

// Registers the shared flags; `rendering` adds the method/pass/output flags.
void addSceneFlags(ArgParser& parser, RenderSpec& spec);
// --param NAME=VALUE (repeatable) into `params`.
void addParamFlag(ArgParser& parser, std::vector<std::pair<std::string, std::string>>& params);
void addMethodFlags(ArgParser& parser, RenderSpec& spec);
// --spp and --seed: which samples a pass draws.
void addSampleFlags(ArgParser& parser, RenderSpec& spec);
// --exposure, --auto-exposure, --tonemap and --gamma: how radiance becomes display bytes.
void addDisplayFlags(ArgParser& p, DisplaySettings& display);
// addSampleFlags plus --passes, --time, --out, the display flags, --reference, --reference-file and --json.
void addRunFlags(ArgParser& parser, RenderSpec& spec);
void addDeviceFlags(ArgParser& parser, RenderSpec& spec);
// --list-methods: the registry, and the parameters of a --brdf file.
void printRegistry(const RenderSpec& spec);

// The flag that sets an engine setting (engine/core/setting.h), e.g. "--mis-split": how the CLI words a
// SettingError.
std::string_view settingFlag(Setting setting);
// resolveMethod, warning once per flag the method does not use ("--env-sampler is ignored by --method
// brdf").
ResolvedMethod resolveMethodAndWarn(const MethodSpec& spec, const BrdfInfo& brdf);

// Number parsing with the flag's name in every error.
uint32_t parseUint(const std::string& flag, const std::string& text, uint32_t min, uint32_t max);
double parseDouble(const std::string& flag, const std::string& text, double min, double max);
// "X,Y" in whole pixels from the top-left corner (range checks are the caller's: they need the image size).
std::pair<long long, long long> parsePixel(const std::string& flag, const std::string& text);
void parseSize(const std::string& flag, const std::string& text, int& width, int& height);

}  // namespace iblx::cli
