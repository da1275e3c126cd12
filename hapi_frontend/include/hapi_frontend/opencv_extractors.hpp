// OpenCV detectors wrapped as FeatureExtractor: cv::ORB (default front end
// detector until the project's own ORB is selected) and cv::AKAZE (option).
#pragma once

#include "hapi_frontend/features.hpp"

#include <opencv2/features2d.hpp>

namespace hapi_frontend {

class OpenCvOrbExtractor : public FeatureExtractor {
 public:
  explicit OpenCvOrbExtractor(int n_features = 1000, int fast_threshold = 20);
  FeatureSet extract(const cv::Mat& gray8) override;
  std::string name() const override { return "opencv_orb"; }
  bool usingGpu() const override { return false; }

 private:
  cv::Ptr<cv::ORB> orb_;
};

class AkazeExtractor : public FeatureExtractor {
 public:
  explicit AkazeExtractor(float threshold = 0.0005f);
  FeatureSet extract(const cv::Mat& gray8) override;
  std::string name() const override { return "akaze"; }
  bool usingGpu() const override { return false; }

 private:
  cv::Ptr<cv::AKAZE> akaze_;
};

}  // namespace hapi_frontend
