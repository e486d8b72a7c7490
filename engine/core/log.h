// Warnings and progress messages: one sink, so the CLI, the viewer and tests decide where they go.
#pragma once

#include <functional>
#include <string>

namespace iblx {

using LogSink = std::function<void(const std::string&)>;

// Replaces the sink for warnings (default: stderr with an "iblx: warning:" prefix). Returns the old sink.
LogSink setWarningSink(LogSink sink);
void warn(const std::string& message);

}  // namespace iblx
