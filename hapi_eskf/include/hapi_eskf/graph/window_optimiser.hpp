// The background thread of Graph SLAM (docs/DESIGN.md "Graph SLAM", online
// window): solves the newest window of the graph while the frame thread
// tracks. The frame thread hands over a copy of the window (submit) and
// picks up the newest solution when there is one (takeResult); neither call
// waits for a solve, only for the copy under this class's own lock. A window
// submitted while another is being solved replaces any still waiting one
// (newest wins: an old window is worth nothing once a newer one exists).
#pragma once

#include "hapi_eskf/graph/bundle_adjustment.hpp"
#include "hapi_eskf/graph/graph_map.hpp"
#include "hapi_eskf/graph/graph_settings.hpp"

#include <condition_variable>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

namespace hapi_eskf {
namespace graph {

// A part of the graph with its keyframes renumbered 0..n-1.
struct WindowJob {
  GraphMap map;
  std::vector<char> constant;      // per local keyframe
  std::vector<int> keyframe_index;  // local -> index in the whole graph
};

struct WindowResult {
  WindowJob solved;  // the job's map at the solution
  BundleReport report;
};

class WindowOptimiser {
 public:
  WindowOptimiser(const GraphSettings& settings);
  ~WindowOptimiser();  // finishes the solve under way, drops a waiting job
  WindowOptimiser(const WindowOptimiser&) = delete;
  WindowOptimiser& operator=(const WindowOptimiser&) = delete;

  void submit(WindowJob job);
  // The newest finished solution, if one arrived since the last call.
  std::optional<WindowResult> takeResult();
  // Blocks until no job waits and none is being solved (tests, shutdown, batch).
  void waitIdle();
  int solves() const;  // finished solves so far

 private:
  void run();

  const GraphSettings settings_;
  mutable std::mutex mutex_;
  std::condition_variable wake_, idle_;
  std::optional<WindowJob> job_;
  std::optional<WindowResult> result_;
  bool busy_ = false, stop_ = false;
  int solves_ = 0;
  std::thread thread_;  // last: starts after the members it uses
};

}  // namespace graph
}  // namespace hapi_eskf
