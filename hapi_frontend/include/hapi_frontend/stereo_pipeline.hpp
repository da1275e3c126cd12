// The whole ROS-free front end for one stereo pair: detect + describe in both
// images, undistort keypoints, match left<->right, keep the N strongest, MMSE
// 3D estimate with covariance, colour. The nodelet only converts messages to
// and from these types.
#pragma once

#include "hapi_frontend/camera_model.hpp"
#include "hapi_frontend/features.hpp"

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace hapi_frontend {

struct PipelineParams {
  std::string detector = "orb";     // "orb" (project's own ORB core, CPU or CUDA) | "akaze" (OpenCV)
  bool use_gpu = false;             // ORB only; falls back to CPU (with a warning) without a device
  int max_landmarks = 200;          // N strongest matched landmarks kept per frame
  int detector_features = 1000;     // features detected per image before matching
  int fast_threshold = 15;          // 20 leaves < 150 landmarks on the globe's low-texture views
  int pyramid_levels = 4;
  double downscale = 1.0;           // >= 1: images are shrunk by this factor before detection;
                                    // pixel outputs are reported in full-resolution coordinates
  bool rectified_input = false;     // images already rectified (use P, no distortion)
  // Keypoint noise [px, 1 sigma per axis] used by the MMSE estimate. Estimated
  // from data, not assumed: on rendered globe pairs (hapi_frontend_globe_test,
  // 30 frames, refined matches) the right pixel's residual against the
  // ground-truth projection of the left ray's sphere point has RMS
  // sqrt(2) * 0.24 px per axis, and sigma = 0.24 gives mean landmark NEES
  // 2.9-3.1 on held-out frames. The error tail is heavier than Gaussian
  // (median NEES ~1.0 instead of 2.37): slanted surfaces bias the patch
  // alignment. Without refine_subpixel, sigma is scaled by the keypoint's
  // pyramid level and about 0.37 px fits.
  double pixel_sigma = 0.24;
  double min_depth = 0.05, max_depth = 20.0;  // [m] accepted landmark depth range
  StereoMatchParams match;
  // Sub-pixel ZNCC refinement of the right keypoint (stereo_refine.hpp);
  // matches whose correlation peak is weak or off-centre are dropped.
  bool refine_subpixel = true;
  int refine_half_patch = 5;        // [px]
  int refine_radius = 3;            // [px]
  double refine_min_zncc = 0.9;     // 0.8 lets ~1.7 % wrong matches through on the globe, 0.9 ~0.8 %
  std::string validate() const;     // empty when valid
};

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
  StageTimesMs times;
  bool used_gpu = false;
};

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
