// build/iblx: dispatches to a subcommand and turns every error into one line and a non-zero exit code.
#include "engine/core/error.h"
#include "engine/core/setting.h"
#include "tools/cli/cli_options.h"
#include "tools/cli/commands.h"

#include <vulkan/vulkan_raii.hpp>

#include <cstdio>
#include <cstring>

namespace {

constexpr const char* kUsage =
    "iblx: progressive image-based-lighting renderer and importance-sampling laboratory\n"
    "usage: iblx COMMAND [flags]      (iblx COMMAND --help for the flags of one command)\n"
    "commands:\n"
    "  render      render a scene progressively to .png/.exr, report speed (and error with --reference)\n"
    "  view        the desktop viewer: live progressive rendering, methods and parameters switched live\n"
    "  reference   compute the ground truth of a scene (deterministic convolution) to .exr\n"
    "  bench       samples per second of every method on one scene\n"
    "  converge    error against spp and time of methods on one scene: CSV, summary table, PNG plots\n"
    "  study       many converge runs from a plan file: listed, sharded over tasks, resumed, merged\n"
    "  hardcases   the hard-case suite: every method on each hard scene, checked and ranked\n"
    "  samples     one pixel's samples as the integrator draws them (direction, uv, pdf, weight) to CSV\n"
    "  otmap       solve (or read from the cache) an environment's OT map; report it, draw its warped grid\n"
    "  devices     list the Vulkan devices and whether iblx can use them\n"
    "  make-sky    write the procedural sky used as the default environment map\n"
    "  make-teapot tessellate the Utah teapot's Bezier patches into an .obj (assets/teapot.obj)\n"
    "  merl-synth  tabulate a BRDF into a MERL .binary file (synthetic measured materials)\n"
    "  measured-synth  tabulate a BRDF into a measured format (UTIA .bin, MIT .dat, MERL .binary)\n"
    "                  or fit it as an ALTA function file (.func)\n";

}  // namespace

int iblx::cli::runCommand(const std::string& command, const Args& args) {
  if (command == "render") return cmdRender(args);
  if (command == "view") return cmdView(args);
  if (command == "reference") return cmdReference(args);
  if (command == "bench") return cmdBench(args);
  if (command == "converge") return cmdConverge(args);
  if (command == "study") return cmdStudy(args);
  if (command == "hardcases") return cmdHardCases(args);
  if (command == "samples") return cmdSamples(args);
  if (command == "otmap") return cmdOtMap(args);
  if (command == "devices") return cmdDevices(args);
  if (command == "make-sky") return cmdMakeSky(args);
  if (command == "make-teapot") return cmdMakeTeapot(args);
  if (command == "merl-synth") return cmdMerlSynth(args);
  if (command == "measured-synth") return cmdMeasuredSynth(args);
  return -1;
}

int main(int argc, char** argv) {
  using namespace iblx::cli;
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h")) {
    std::fputs(kUsage, argc < 2 ? stderr : stdout);
    return argc < 2 ? 2 : 0;
  }
  const std::string command = argv[1];
  const Args args(argv + 2, argv + argc);
  try {
    const int status = runCommand(command, args);
    if (status >= 0) return status;
    std::fprintf(stderr, "iblx: unknown command '%s'\n%s", command.c_str(), kUsage);
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
