// The subcommands of build/iblx, one file each.
#pragma once

#include <string>
#include <vector>

namespace iblx::cli {

using Args = std::vector<std::string>;
int cmdRender(const Args& args);
int cmdView(const Args& args);
int cmdReference(const Args& args);
int cmdBench(const Args& args);
int cmdDevices(const Args& args);
int cmdMakeSky(const Args& args);
int cmdMakeTeapot(const Args& args);
int cmdMerlSynth(const Args& args);
int cmdMeasuredSynth(const Args& args);
int cmdConverge(const Args& args);
int cmdHardCases(const Args& args);
int cmdSamples(const Args& args);
int cmdOtMap(const Args& args);
int cmdStudy(const Args& args);

// Runs the subcommand `command` (e.g. "render") with its flags; -1 when there is no such command. `iblx
// study` generates its inputs with it.
int runCommand(const std::string& command, const Args& args);

}  // namespace iblx::cli
