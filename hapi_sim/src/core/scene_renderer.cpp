// SceneRenderer: ray casting of a Scene with motion blur and 2x2 sub-pixel
// anti-aliasing spread over the sub-frames.
#include <opencv2/core/utility.hpp>

#include "hapi_sim/image_formation.hpp"

// ThreadSanitizer cannot see the join of cv::parallel_for_: its threads are
// TBB's, an uninstrumented library, so the caller's next use of the stack
// the stripes read looked like a race. Each stripe releases on `out`'s data
// as it ends and the caller acquires it after parallel_for_ returns: the
// order the join guarantees, stated where TSan can see it (docs/RELIABILITY.md
// "ThreadSanitizer"). No code without TSan.
#if defined(__SANITIZE_THREAD__)
extern "C" void __tsan_acquire(void* addr);
extern "C" void __tsan_release(void* addr);
#define HAPI_JOINED_BY_CALLER(addr) __tsan_release(addr)
#define HAPI_JOIN_SEEN(addr) __tsan_acquire(addr)
#else
#define HAPI_JOINED_BY_CALLER(addr) static_cast<void>(addr)
#define HAPI_JOIN_SEEN(addr) static_cast<void>(addr)
#endif

namespace hapi_sim {
namespace {
// 2x2 pattern of sub-pixel offsets (pixel centres at integers).
const double kDx[SceneRenderer::kOffsets] = {-0.25, 0.25, 0.25, -0.25};
const double kDy[SceneRenderer::kOffsets] = {-0.25, 0.25, -0.25, 0.25};
}  // namespace

SceneRenderer::SceneRenderer(const Scene& scene, const CameraModel& cam) : scene_(scene), cam_(cam) {
  for (int k = 0; k < kOffsets; ++k) {
    rays_[k].resize(static_cast<size_t>(cam.width) * cam.height);
    for (int v = 0; v < cam.height; ++v)
      for (int u = 0; u < cam.width; ++u)
        rays_[k][static_cast<size_t>(v) * cam.width + u] =
            pixelToRay(cam, Eigen::Vector2d(u + kDx[k], v + kDy[k])).cast<float>();
  }
}

cv::Mat SceneRenderer::radiance(const std::vector<Pose>& T_sc) const {
  const int W = cam_.width, H = cam_.height;
  cv::Mat out(H, W, CV_32FC1, cv::Scalar(0.0f));
  const float inv = 1.0f / static_cast<float>(T_sc.size());
  std::vector<Eigen::Matrix3d> R;
  for (const Pose& P : T_sc) R.push_back(P.q.toRotationMatrix());
  cv::parallel_for_(cv::Range(0, H), [&](const cv::Range& rows) {
    for (int v = rows.start; v < rows.end; ++v) {
      float* row = out.ptr<float>(v);
      for (int u = 0; u < W; ++u) {
        float acc = 0.f;
        for (size_t j = 0; j < T_sc.size(); ++j) {
          const Eigen::Vector3d d = R[j] * rays_[j % kOffsets][static_cast<size_t>(v) * W + u].cast<double>();
          double t;
          float g;
          acc += scene_.trace(T_sc[j].p, d.normalized(), &t, &g) ? g : Renderer::background(u, v);
        }
        row[u] = acc * inv;
      }
    }
    HAPI_JOINED_BY_CALLER(out.data);
  });
  HAPI_JOIN_SEEN(out.data);
  return out;
}

}  // namespace hapi_sim
