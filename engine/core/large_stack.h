// Running a deeply recursive library call (the GLSL compiler) on a thread whose stack size iblx chooses,
// so that an input that recurses deeply fails inside a known budget instead of overflowing the main stack.
#pragma once

#include <cstddef>
#include <functional>

namespace iblx {

// Runs work on a new thread with a stack of stackBytes and waits for it; an exception thrown by work is
// rethrown here. When it runs longer than timeoutSeconds (> 0), the thread cannot be stopped safely, so the
// process ends: `onTimeout` prints why, then it exits with status 4.
void runWithStack(std::size_t stackBytes, const std::function<void()>& work, double timeoutSeconds = 0.0,
                  const std::function<void()>& onTimeout = {});

}  // namespace iblx
