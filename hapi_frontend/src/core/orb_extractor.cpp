#include "hapi_frontend/orb_extractor.hpp"

#ifdef HAPI_FRONTEND_WITH_CUDA
#include "hapi_frontend/cuda/orb_cuda.hpp"
#endif

#include <cstring>
#include <stdexcept>

namespace hapi_frontend {

FeatureSet orbResultToFeatureSet(const OrbResult& r) {
  FeatureSet fs;
  fs.type = DescriptorType::ORB;
  const int n = static_cast<int>(r.keypoints.size());
  fs.keypoints.resize(n);
  for (int i = 0; i < n; ++i) {
    const OrbKeypoint& k = r.keypoints[i];
    Feature& f = fs.keypoints[i];
    f.x = k.x;
    f.y = k.y;
    f.response = static_cast<float>(k.score);
    f.angle = k.angle;
    f.size = k.size;
    f.octave = k.level;
  }
  fs.descriptors.create(n, kOrbDescBytes, CV_8U);
  if (n > 0) std::memcpy(fs.descriptors.data, r.descriptors.data(), static_cast<size_t>(n) * kOrbDescBytes);
  return fs;
}

#ifdef HAPI_FRONTEND_WITH_CUDA
struct OrbExtractor::GpuCore {
  explicit GpuCore(const OrbParams& p) : core(p) {}
  OrbCudaCore core;
};
#else
struct OrbExtractor::GpuCore {};
#endif

OrbExtractor::OrbExtractor(const OrbParams& p, bool use_gpu) : cpu_(p) {
  if (!use_gpu) {
    gpu_status_ = "GPU not requested";
    return;
  }
#ifdef HAPI_FRONTEND_WITH_CUDA
  std::string info;
  if (!cudaDeviceAvailable(&info)) {
    gpu_status_ = "no usable CUDA device (" + info + "), using the CPU ORB core";
    return;
  }
  try {
    gpu_ = std::make_unique<GpuCore>(p);
    gpu_status_ = "CUDA ORB core on " + info;
  } catch (const std::exception& e) {
    gpu_status_ = std::string("CUDA ORB core failed (") + e.what() + "), using the CPU ORB core";
  }
#else
  gpu_status_ = "built without CUDA, using the CPU ORB core";
#endif
}

OrbExtractor::~OrbExtractor() = default;

bool OrbExtractor::usingGpu() const { return gpu_ != nullptr; }

FeatureSet OrbExtractor::extract(const cv::Mat& gray8) {
  if (gray8.type() != CV_8UC1 || gray8.empty()) throw std::invalid_argument("OrbExtractor: needs a non-empty CV_8UC1 image");
  ImageView8 v;
  v.data = gray8.data;
  v.width = gray8.cols;
  v.height = gray8.rows;
  v.stride = static_cast<int>(gray8.step[0]);
#ifdef HAPI_FRONTEND_WITH_CUDA
  if (gpu_) {
    try {
      return orbResultToFeatureSet(gpu_->core.extract(v));
    } catch (const std::runtime_error& e) {
      gpu_status_ = std::string("CUDA ORB core failed at run time (") + e.what() + "), switched to the CPU ORB core";
      gpu_.reset();
    }
  }
#endif
  return orbResultToFeatureSet(cpu_.extract(v));
}

}  // namespace hapi_frontend
