// Recorder behind stage_times.hpp: a process-wide list the bench drains.
#include "stage_times.hpp"

#include <mutex>

namespace hapi_eskf {
namespace cuda {
namespace {
std::mutex g_mu;
std::vector<UpdateStageTimes> g_times;
}  // namespace

void recordUpdateStageTimes(const UpdateStageTimes& t) {
  std::lock_guard<std::mutex> lock(g_mu);
  g_times.push_back(t);
}

std::vector<UpdateStageTimes> takeUpdateStageTimes() {
  std::lock_guard<std::mutex> lock(g_mu);
  std::vector<UpdateStageTimes> out;
  out.swap(g_times);
  return out;
}

}  // namespace cuda
}  // namespace hapi_eskf
