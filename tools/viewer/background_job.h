// Long work off the viewer's UI thread (renderer builds: tables and shader compiles; ground truths), with its
// progress and a cooperative cancel, so the window never freezes.
#pragma once

#include <atomic>
#include <chrono>
#include <exception>
#include <functional>
#include <memory>
#include <vector>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>

namespace iblx::viewer {

// Thrown from a job's progress callback after cancel(): the work unwinds at its next progress report.
struct JobCancelled : std::runtime_error {
  JobCancelled() : std::runtime_error("cancelled") {}
};

// How a job ended (status() after done()), or that it still runs.
enum class JobStatus { Running, Succeeded, Failed, Cancelled };

// What the viewer needs of any job it no longer wants: cancel it and drop it once it has stopped, without
// joining its thread on the UI thread.
class JobBase {
 public:
  virtual ~JobBase() = default;
  virtual bool done() const = 0;
  virtual void cancel() = 0;
};

template <typename T>
class BackgroundJob final : public JobBase {
 public:
  // work(progress) runs on its own thread; progress(fraction in [0, 1]) may be called at any rate.
  BackgroundJob(std::string what, std::function<T(const std::function<void(double)>&)> work)
      : what_(std::move(what)), thread_([this, work = std::move(work)] {
          try {
            result_ = work([this](double fraction) {
              progress_.store(fraction);
              if (cancelled_.load()) throw JobCancelled();
            });
            ended_ = JobStatus::Succeeded;
          } catch (const JobCancelled&) {
            ended_ = JobStatus::Cancelled;
          } catch (const std::exception& e) {
            error_ = e.what();
            ended_ = JobStatus::Failed;
          } catch (...) {
            error_ = "unknown error";
            ended_ = JobStatus::Failed;
          }
          done_.store(true, std::memory_order_release);
        }) {}
  ~BackgroundJob() override { cancel(); }  // std::jthread joins
  BackgroundJob(const BackgroundJob&) = delete;
  BackgroundJob& operator=(const BackgroundJob&) = delete;

  const std::string& what() const { return what_; }
  double secondsRunning() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
  }
  bool done() const override { return done_.load(std::memory_order_acquire); }
  double progress() const { return progress_.load(); }
  void cancel() override { cancelled_.store(true); }
  void wait() { thread_.join(); }
  JobStatus status() const { return done() ? ended_ : JobStatus::Running; }
  // After done(): the result when it succeeded; error() says why it failed.
  std::optional<T>& result() { return result_; }
  const std::string& error() const { return error_; }

 private:
  std::string what_;
  std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();
  std::atomic<double> progress_{0.0};
  std::atomic<bool> cancelled_{false}, done_{false};
  std::optional<T> result_;
  std::string error_;
  JobStatus ended_ = JobStatus::Running;  // written before done_ is released
  std::jthread thread_;                   // last: starts once everything above exists, joins before it goes
};

}  // namespace iblx::viewer

namespace iblx::viewer {

// Cancelled jobs wait here until their threads have stopped, so that dropping one never blocks the caller.
// The one poll of a job: when it has ended, hands its result to onResult if it succeeded, or sets `error` to
// `errorPrefix` and its error if it failed (a cancelled job ends silently), then drops it. onResult runs
// while the job still exists, so code it calls sees the work as not yet finished.
template <typename T, typename OnResult>
void finishJob(std::unique_ptr<BackgroundJob<T>>& job, std::string& error, const std::string& errorPrefix,
               OnResult&& onResult) {
  if (!job || !job->done()) return;
  if (job->status() == JobStatus::Succeeded)
    onResult(std::move(*job->result()));
  else if (job->status() == JobStatus::Failed)
    error = errorPrefix + job->error();
  job.reset();
}

class RetiredJobs {
 public:
  template <typename T>
  void retire(std::unique_ptr<BackgroundJob<T>>& job) {
    if (!job) return;
    job->cancel();
    jobs_.push_back(std::move(job));
  }
  void collect() {
    std::erase_if(jobs_, [](const std::unique_ptr<JobBase>& job) { return job->done(); });
  }

 private:
  std::vector<std::unique_ptr<JobBase>> jobs_;
};

}  // namespace iblx::viewer
