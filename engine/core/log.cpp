// Warning sink implementation.
#include "engine/core/log.h"

#include <cstdio>
#include <mutex>

namespace iblx {
namespace {
std::mutex gSinkMutex;
LogSink gSink = [](const std::string& m) { std::fprintf(stderr, "iblx: warning: %s\n", m.c_str()); };
}  // namespace

LogSink setWarningSink(LogSink sink) {
  std::lock_guard lock(gSinkMutex);
  std::swap(gSink, sink);
  return sink;
}

void warn(const std::string& message) {
  std::lock_guard lock(gSinkMutex);
  if (gSink) gSink(message);
}

}  // namespace iblx
