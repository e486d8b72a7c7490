// `iblx devices`: every Vulkan device, its type and why iblx would reject it.
#include "engine/vk/context.h"
#include "tools/cli/cli_options.h"
#include "tools/cli/commands.h"

#include <cstdio>

namespace iblx::cli {

int cmdDevices(const Args& args) {
  ArgParser parser("devices");
  if (parser.parseOrShowHelp(args)) return 0;
  const auto devices = VulkanContext::describeDevices();
  if (devices.empty()) std::puts("no Vulkan devices (install mesa-vulkan-drivers for lavapipe)");
  for (const auto& d : devices)
    std::printf("[%u] %s (%s): %s\n", d.index, d.name.c_str(), d.type.c_str(),
                d.rejectedBecause.empty() ? "usable" : d.rejectedBecause.c_str());
  return 0;
}

}  // namespace iblx::cli
