// A thread with a chosen stack size (engine/core/large_stack.h). std::thread cannot set one, so POSIX
// threads.
#include "engine/core/large_stack.h"

#include "engine/core/error.h"

#include <pthread.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <exception>

namespace iblx {
namespace {

struct Job {
  const std::function<void()>* work = nullptr;
  std::exception_ptr error;
};

extern "C" void* runJob(void* argument) {
  auto* job = static_cast<Job*>(argument);
  try {
    (*job->work)();
  } catch (...) {
    job->error = std::current_exception();
  }
  return nullptr;
}

}  // namespace

void runWithStack(std::size_t stackBytes, const std::function<void()>& work, double timeoutSeconds,
                  const std::function<void()>& onTimeout) {
  pthread_attr_t attributes;
  if (pthread_attr_init(&attributes) != 0) throw Error("cannot create a thread (pthread_attr_init failed)");
  if (pthread_attr_setstacksize(&attributes, stackBytes) != 0) {
    pthread_attr_destroy(&attributes);
    throw Error("cannot create a thread with a " + std::to_string(stackBytes >> 20) + " MiB stack");
  }
  Job job{&work, nullptr};
  pthread_t thread;
  const int created = pthread_create(&thread, &attributes, &runJob, &job);
  pthread_attr_destroy(&attributes);
  if (created != 0) throw Error(std::string("cannot create a thread: ") + std::strerror(created));
  if (timeoutSeconds > 0.0) {
    // The monotonic clock: a step of the wall clock must not end a compile that is within its budget.
    timespec deadline{};
    clock_gettime(CLOCK_MONOTONIC, &deadline);
    const double whole = std::floor(timeoutSeconds);
    deadline.tv_sec += time_t(whole);
    deadline.tv_nsec += long((timeoutSeconds - whole) * 1e9);
    if (deadline.tv_nsec >= 1000000000L) deadline.tv_sec += 1, deadline.tv_nsec -= 1000000000L;
    const int joined = pthread_clockjoin_np(thread, nullptr, CLOCK_MONOTONIC, &deadline);
    if (joined == ETIMEDOUT) {
      if (onTimeout) onTimeout();
      std::fflush(stderr);
      std::_Exit(4);
    }
    if (joined != 0) pthread_join(thread, nullptr);  // never leave the thread running on `job`
  } else {
    pthread_join(thread, nullptr);
  }
  if (job.error) std::rethrow_exception(job.error);
}

}  // namespace iblx
