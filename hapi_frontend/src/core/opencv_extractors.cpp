#include "hapi_frontend/opencv_extractors.hpp"

namespace hapi_frontend {
namespace {
FeatureSet toFeatureSet(const std::vector<cv::KeyPoint>& kps, const cv::Mat& desc, DescriptorType type) {
  FeatureSet fs;
  fs.type = type;
  fs.descriptors = desc;
  fs.keypoints.reserve(kps.size());
  for (const auto& k : kps) {
    Feature f;
    f.x = k.pt.x;
    f.y = k.pt.y;
    f.response = k.response;
    f.angle = k.angle;
    f.size = k.size;
    f.octave = k.octave;
    fs.keypoints.push_back(f);
  }
  return fs;
}
}  // namespace

OpenCvOrbExtractor::OpenCvOrbExtractor(int n_features, int fast_threshold)
    : orb_(cv::ORB::create(n_features, 1.2f, 8, 31, 0, 2, cv::ORB::HARRIS_SCORE, 31, fast_threshold)) {}

FeatureSet OpenCvOrbExtractor::extract(const cv::Mat& gray8) {
  std::vector<cv::KeyPoint> kps;
  cv::Mat desc;
  orb_->detectAndCompute(gray8, cv::noArray(), kps, desc);
  return toFeatureSet(kps, desc, DescriptorType::ORB);
}

AkazeExtractor::AkazeExtractor(float threshold)
    : akaze_(cv::AKAZE::create(cv::AKAZE::DESCRIPTOR_MLDB, 0, 3, threshold)) {}

FeatureSet AkazeExtractor::extract(const cv::Mat& gray8) {
  std::vector<cv::KeyPoint> kps;
  cv::Mat desc;
  akaze_->detectAndCompute(gray8, cv::noArray(), kps, desc);
  return toFeatureSet(kps, desc, DescriptorType::AKAZE);
}

}  // namespace hapi_frontend
