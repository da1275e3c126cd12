// Shared plain types of the front end: keypoints + binary descriptors, and the
// two interfaces that have a CPU and a CUDA implementation each
// (FeatureExtractor, StereoMatcher). ROS-free.
#pragma once

#include <opencv2/core.hpp>
#include <Eigen/Core>

#include <memory>
#include <string>
#include <vector>

namespace hapi_frontend {

// One detected keypoint in *distorted* (raw image) pixel coordinates.
struct Feature {
  float x = 0.f, y = 0.f;   // pixel position, level-0 coordinates [px]
  float response = 0.f;     // detector score, larger = stronger
  float angle = 0.f;        // orientation [deg], 0..360, OpenCV convention
  float size = 31.f;        // patch diameter at level 0 [px]
  int octave = 0;           // pyramid level
};

// Descriptor encodings; values match hapi_msgs/StereoLandmarks DESCRIPTOR_*.
enum class DescriptorType : int { ORB = 0, AKAZE = 1 };

struct FeatureSet {
  std::vector<Feature> keypoints;
  cv::Mat descriptors;  // keypoints.size() rows x bytes, CV_8U, row i <-> keypoints[i]
  DescriptorType type = DescriptorType::ORB;
};

// Detect + describe on one 8-bit single-channel image.
class FeatureExtractor {
 public:
  virtual ~FeatureExtractor() = default;
  virtual FeatureSet extract(const cv::Mat& gray8) = 0;
  virtual std::string name() const = 0;
  // True while extract() runs on the GPU (a GPU implementation that fell back
  // to the CPU answers false from then on).
  virtual bool usingGpu() const = 0;
};

// Left/right association constraints, in *undistorted* pixel coordinates.
struct StereoMatchParams {
  double max_epipolar_px = 2.0;   // distance of the right point to the epipolar line of the left one [px]
  double min_disparity = 0.5;     // x_left - x_right lower bound [px] (point in front of both cameras)
  double max_disparity = 256.0;   // upper bound [px] (closest depth accepted)
  double ratio = 0.8;             // Lowe ratio: best < ratio * second best (among candidates passing geometry)
  int max_hamming = 64;           // absolute descriptor distance bound [bits]
  bool cross_check = true;        // keep only mutual best matches
};

struct StereoMatch {
  int left = -1;      // index into the left FeatureSet
  int right = -1;     // index into the right FeatureSet
  int distance = 0;   // Hamming distance [bits]
};

// Brute-force Hamming matching restricted by the epipolar and disparity
// constraints. F maps undistorted left pixels to epipolar lines in the
// undistorted right image: l_r = F * [xl, yl, 1]^T.
class StereoMatcher {
 public:
  virtual ~StereoMatcher() = default;
  virtual std::vector<StereoMatch> match(const FeatureSet& left, const std::vector<Eigen::Vector2d>& left_undist,
                                         const FeatureSet& right, const std::vector<Eigen::Vector2d>& right_undist,
                                         const Eigen::Matrix3d& F, const StereoMatchParams& params) = 0;
  virtual std::string name() const = 0;
  // True while match() runs on the GPU (as FeatureExtractor::usingGpu()).
  virtual bool usingGpu() const = 0;
};

}  // namespace hapi_frontend
