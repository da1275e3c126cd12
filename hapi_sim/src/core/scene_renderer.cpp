// SceneRenderer: ray casting of a Scene with motion blur and 2x2 sub-pixel
// anti-aliasing spread over the sub-frames.
#include <opencv2/core/utility.hpp>

#include "hapi_sim/image_formation.hpp"

#if defined(__SANITIZE_THREAD__)
extern "C" void __tsan_acquire(void* addr);
extern "C" void __tsan_release(void* addr);
#endif

namespace hapi_sim {
namespace {

#if defined(__SANITIZE_THREAD__)
void syncAcquire(const void* key) { __tsan_acquire(const_cast<void*>(key)); }
void syncRelease(const void* key) { __tsan_release(const_cast<void*>(key)); }
#else
void syncAcquire(const void*) {}
void syncRelease(const void*) {}
#endif

// Rows [0, rows) of `body` in parallel stripes (cv::parallel_for_, on TBB's
// threads). ThreadSanitizer sees neither TBB's fork nor its join (an
// uninstrumented library), so the stripes' reads of the caller's stack and
// the caller's next use of it looked like races. The caller releases before
// the loop and acquires after it, each stripe acquires first and releases
// last: the order fork and join guarantee, stated where TSan sees it
// (docs/RELIABILITY.md "ThreadSanitizer"). No code without TSan.
template <typename Body>
void parallelRows(int rows, const Body& body) {
  struct Stripes final : cv::ParallelLoopBody {
    explicit Stripes(const Body& b) : body(b) {}
    void operator()(const cv::Range& r) const override {
      syncAcquire(this);
      body(r);
      syncRelease(this);
    }
    const Body& body;
  } stripes(body);
  syncRelease(&stripes);
  cv::parallel_for_(cv::Range(0, rows), stripes);
  syncAcquire(&stripes);
}

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
  parallelRows(H, [&](const cv::Range& rows) {
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
  });
  return out;
}

}  // namespace hapi_sim
