// Per-stage device timing of CudaBackend::update() for the benchmark: account
// for the update's time at large K. A backend created with the
// cuda_stage_times setting records events around each stage and files the
// spans here; without it, no events are recorded. Times are spans between
// events on the filter's stream, in ms, so the host round trips (read-back of
// the factor's info and diagonal, of y and dx) show up as the host_check spans.
#pragma once

#include <vector>

namespace hapi_eskf {
namespace cuda {

struct UpdateStageTimes {
  double upload = 0;          // H, R, slots, innovation to the device
  double gather = 0;          // P = C H^T
  double innovation_cov = 0;  // S = H P + R and its finiteness check
  double factor = 0;          // potrf of S, info and diagonals back to the host
  double host_check1 = 0;     // host waits for them and checks (bubble)
  double trsm = 0;            // A = P L^-T
  double solve = 0;           // y = L^-1 z, dx = A y, both back to the host
  double host_check2 = 0;     // host waits and checks finiteness (bubble)
  double rank_update = 0;     // C <- C - A A^T
};

void recordUpdateStageTimes(const UpdateStageTimes& t);
// Every update recorded since the last call, then cleared.
std::vector<UpdateStageTimes> takeUpdateStageTimes();

}  // namespace cuda
}  // namespace hapi_eskf
