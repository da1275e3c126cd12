// The whole ROS-free front end for one stereo pair: detect + describe in both
// images, undistort keypoints, match left<->right, keep the N strongest, MMSE
// 3D estimate with covariance, colour. The nodelet only converts messages to
// and from these types.
#pragma once

#include "hapi_frontend/camera_model.hpp"
#include "hapi_frontend/features.hpp"
#include "hapi_frontend/pipeline_params.hpp"

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace hapi_frontend {

struct StereoLandmarkOut {
  Eigen::Vector2d uv_left = Eigen::Vector2d::Zero(), uv_right = Eigen::Vector2d::Zero();  // undistorted px
  Eigen::Vector3d position = Eigen::Vector3d::Zero();   // left optical frame [m]
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  // [m^2]
  float response = 0.f;
  std::array<uint8_t, 3> rgb{{0, 0, 0}};
  int hamming = 0;                                      // left/right descriptor distance
};

struct StageTimesMs {
  double convert = 0, detect_left = 0, detect_right = 0, undistort = 0, match = 0, triangulate = 0, total = 0;
  double refine = 0;  // sub-pixel refinement of the kept matches (not in triangulate)
};

struct StereoFrameResult {
  std::vector<StereoLandmarkOut> landmarks;  // sorted by response, strongest first
  cv::Mat descriptors;                       // landmarks.size() rows, left-image descriptors
  DescriptorType descriptor_type = DescriptorType::ORB;
  int n_left = 0, n_right = 0, n_matches = 0;  // before the N-strongest cut
  int n_refine_rejected = 0;                  // matches dropped by the sub-pixel refinement
  // Self-check measures (image_quality.hpp), NaN when not measurable: the
  // median vertical disparity of the kept landmarks [px] and the left
  // image's motion blur.
  double vertical_disparity_px = std::numeric_limits<double>::quiet_NaN();
  double motion_blur = std::numeric_limits<double>::quiet_NaN();
  StageTimesMs times;
  bool used_gpu = false;
};

// Empty when `result` can travel as hapi_msgs/StereoLandmarks (a descriptor
// row per landmark, finite positions, covariances and pixels), else why not.
// The one check of the nodelet's message and of the ROS-free link
// (tools/latency).
std::string publishProblem(const StereoFrameResult& result);

class StereoPipeline {
 public:
  // Throws std::invalid_argument on invalid params (checked once at start-up).
  explicit StereoPipeline(const PipelineParams& params);
  ~StereoPipeline();

  // (Re)builds the camera models; returns a non-empty reason when the
  // calibration is unusable (zero K, unknown model, size mismatch ...).
  std::string setCalibration(const CameraCalib& left, const CameraCalib& right);
  bool hasCalibration() const;

  // left_gray/right_gray: CV_8UC1 of the calibrated size. left_colour:
  // CV_8UC3 BGR of the same size, or empty (grey then gives the colour).
  // Returns a non-empty reason on bad input (sizes, types, no calibration);
  // never throws for bad images.
  std::string process(const cv::Mat& left_gray, const cv::Mat& right_gray, const cv::Mat& left_colour,
                      StereoFrameResult* out);

  const PipelineParams& params() const;
  const StereoRig& rig() const;  // valid after setCalibration

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hapi_frontend
