// build/iblx: dispatches to a subcommand and turns every error into one line and a non-zero exit code.
#include "engine/core/error.h"
#include "engine/core/setting.h"
#include "tools/cli/cli_options.h"
#include "tools/cli/commands.h"

#include <vulkan/vulkan_raii.hpp>

#include <cstdio>
#include <cstring>
#include <string>

namespace {

using iblx::cli::Args;

// Every subcommand, in the order the usage lists them: the usage, the dispatch and the unknown-command error
// read this one list.
struct Command {
  const char* name;
  int (*run)(const Args&);
  const char* summary;  // may hold a newline and an indented continuation
};
constexpr Command kCommands[] = {
    {"render", iblx::cli::cmdRender,
     "render a scene progressively to .png/.exr, report speed (and error with --reference)"},
    {"view", iblx::cli::cmdView,
     "the desktop viewer: live progressive rendering, methods and parameters switched live"},
    {"reference", iblx::cli::cmdReference,
     "compute the ground truth of a scene (deterministic convolution) to .exr"},
    {"bench", iblx::cli::cmdBench, "samples per second of every method on one scene"},
    {"converge", iblx::cli::cmdConverge,
     "error against spp and time of methods on one scene: CSV, summary table, PNG plots"},
    {"study", iblx::cli::cmdStudy,
     "many converge runs from a plan file: listed, sharded over tasks, resumed, merged"},
    {"hardcases", iblx::cli::cmdHardCases,
     "the hard-case suite: every method on each hard scene, checked and ranked"},
    {"samples", iblx::cli::cmdSamples,
     "one pixel's samples as the integrator draws them (direction, uv, pdf, weight) to CSV"},
    {"otmap", iblx::cli::cmdOtMap,
     "solve (or read from the cache) an environment's OT map; report it, draw its warped grid"},
    {"devices", iblx::cli::cmdDevices, "list the Vulkan devices and whether iblx can use them"},
    {"make-sky", iblx::cli::cmdMakeSky, "write the procedural sky used as the default environment map"},
    {"make-teapot", iblx::cli::cmdMakeTeapot,
     "tessellate the Utah teapot's Bezier patches into an .obj (assets/teapot.obj)"},
    {"merl-synth", iblx::cli::cmdMerlSynth,
     "tabulate a BRDF into a MERL .binary file (synthetic measured materials)"},
    {"measured-synth", iblx::cli::cmdMeasuredSynth,
     "tabulate a BRDF into a measured format (UTIA .bin, MIT .dat, MERL .binary)\n"
     "                  or fit it as an ALTA function file (.func)"},
};

std::string usage() {
  std::string text =
      "iblx: progressive image-based-lighting renderer and importance-sampling laboratory\n"
      "usage: iblx COMMAND [flags]      (iblx COMMAND --help for the flags of one command)\n"
      "commands:\n";
  for (const Command& c : kCommands) {
    std::string name = c.name;
    name.resize(name.size() < 12 ? 12 : name.size() + 2, ' ');  // a column of 12, or two spaces past it
    text += "  " + name + c.summary + "\n";
  }
  return text;
}

}  // namespace

int iblx::cli::runCommand(const std::string& command, const Args& args) {
  for (const Command& c : kCommands)
    if (command == c.name) return c.run(args);
  return -1;
}

int main(int argc, char** argv) {
  using namespace iblx::cli;
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h")) {
    std::fputs(usage().c_str(), argc < 2 ? stderr : stdout);
    return argc < 2 ? 2 : 0;
  }
  const std::string command = argv[1];
  const Args args(argv + 2, argv + argc);
  try {
    const int status = runCommand(command, args);
    if (status >= 0) return status;
    // One line, as for every other error; the usage is one `iblx --help` away.
    std::string names;
    for (const Command& c : kCommands) names += (names.empty() ? "" : ", ") + std::string(c.name);
    std::fprintf(stderr, "iblx: unknown command '%s' (commands: %s; iblx --help)\n", command.c_str(),
                 names.c_str());
    return 2;
  } catch (const iblx::Interrupted& e) {
    std::fprintf(stderr, "iblx: interrupted: %s\n", e.what());
    return 130;
  } catch (const iblx::SettingError& e) {  // the engine names the setting; here it is the flag
    std::fprintf(stderr, "iblx: error: %s\n", e.named(iblx::cli::settingFlag(e.setting())).c_str());
    return 1;
  } catch (const iblx::Error& e) {
    std::fprintf(stderr, "iblx: error: %s\n", e.what());
    return 1;
  } catch (const vk::SystemError& e) {
    std::fprintf(stderr, "iblx: Vulkan error: %s\n", e.what());
    return 3;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "iblx: error: %s\n", e.what());
    return 1;
  }
}
