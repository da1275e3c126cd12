#include "hapi_eskf/surface_motion/rts_smoother.hpp"

#include <Eigen/Cholesky>

#include <algorithm>

namespace hapi_eskf {
namespace surface_motion {

std::vector<SmoothedState> smoothInterval(const std::deque<FilterStep>& steps, double start, double end) {
  std::vector<SmoothedState> out;
  if (steps.empty() || start > end) return out;
  // e_k|N = e_k + C_k (e_k+1|N - e_pred,k+1), P_k|N = P_k + C_k (P_k+1|N - P_pred,k+1) C_k^T,
  // C_k = P_k F_k+1^T P_pred,k+1^-1.
  std::size_t k = steps.size() - 1;
  Vec3 e = steps[k].e;
  Mat3 P = steps[k].P;
  for (;;) {
    if (steps[k].t >= start && steps[k].t <= end) out.push_back({steps[k].t, e, P, k});
    if (k == 0 || steps[k - 1].t < start) break;
    const FilterStep& next = steps[k];
    const FilterStep& cur = steps[k - 1];
    const Mat3 C = next.P_pred.llt().solve(next.F * cur.P).transpose();
    e = cur.e + C * (e - next.e_pred);
    P = cur.P + C * (P - next.P_pred) * C.transpose();
    P = 0.5 * (P + P.transpose()).eval();
    --k;
  }
  std::reverse(out.begin(), out.end());
  return out;
}

}  // namespace surface_motion
}  // namespace hapi_eskf
