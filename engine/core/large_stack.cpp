// A thread with a chosen stack size (engine/core/large_stack.h). std::thread cannot set one, so POSIX
// threads.
#include "engine/core/large_stack.h"

#include "engine/core/error.h"

#include <pthread.h>

#include <cstring>
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

void runWithStack(std::size_t stackBytes, const std::function<void()>& work) {
  pthread_attr_t attributes;
  if (pthread_attr_init(&attributes) != 0) throw Error("cannot create a thread (pthread_attr_init failed)");
  pthread_attr_setstacksize(&attributes, stackBytes);
  Job job{&work, nullptr};
  pthread_t thread;
  const int created = pthread_create(&thread, &attributes, &runJob, &job);
  pthread_attr_destroy(&attributes);
  if (created != 0) throw Error(std::string("cannot create a thread: ") + std::strerror(created));
  pthread_join(thread, nullptr);
  if (job.error) std::rethrow_exception(job.error);
}

}  // namespace iblx
