// Background window solver (window_optimiser.hpp).
#include "hapi_eskf/graph/window_optimiser.hpp"

#include <utility>

namespace hapi_eskf {
namespace graph {

WindowOptimiser::WindowOptimiser(const GraphSettings& settings)
    : settings_(settings), thread_([this] { run(); }) {}

WindowOptimiser::~WindowOptimiser() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
    job_.reset();
  }
  wake_.notify_all();
  thread_.join();
}

void WindowOptimiser::submit(WindowJob job) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    job_ = std::move(job);
  }
  wake_.notify_one();
}

std::optional<WindowResult> WindowOptimiser::takeResult() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::optional<WindowResult> out = std::move(result_);
  result_.reset();
  return out;
}

void WindowOptimiser::waitIdle() {
  std::unique_lock<std::mutex> lock(mutex_);
  idle_.wait(lock, [this] { return !busy_ && !job_; });
}

int WindowOptimiser::solves() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return solves_;
}

void WindowOptimiser::run() {
  BundleOptions options;
  options.max_iterations = settings_.window_max_iterations;
  options.covariances = settings_.window_covariance;
  for (;;) {
    WindowJob job;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [this] { return stop_ || job_.has_value(); });
      if (stop_) return;
      job = std::move(*job_);
      job_.reset();
      busy_ = true;
    }
    WindowResult result;
    const Status st = adjustBundle(settings_, options, job.constant, &job.map, &result.report);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (st == Status::kOk && result.report.usable) {
        result.solved = std::move(job);
        result_ = std::move(result);
      }
      ++solves_;
      busy_ = false;
    }
    idle_.notify_all();
  }
}

}  // namespace graph
}  // namespace hapi_eskf
