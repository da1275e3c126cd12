// Settings of the ImageFlowTracker and their declarations (name = the
// ImagingFlowNodelet's private parameter, range, unit, meaning:
// image_flow_params.cpp), the single source of every image-flow range: the
// tracker's constructor, the nodelet's parameter reader and
// imaging_flow_replay's name=value options all walk visit(). ROS-free.
#pragma once

#include "hapi_frontend/param_spec.hpp"

#include <string>
#include <vector>

namespace hapi_frontend {

struct ImageFlowParams {
  // [px] the measurement pixel (column, row; pixel centres at integers);
  // -1 = the image centre ((width - 1) / 2, (height - 1) / 2).
  double u = -1, v = -1;
  int search_radius = 48;          // [px] features are taken from the square of this half size about (u, v)
  int max_features = 120;          // strongest Shi-Tomasi corners kept
  double min_feature_distance = 5;  // [px] between two corners
  double feature_quality = 0.005;  // weakest corner kept, relative to the strongest
  int pyramid_levels = 3;          // LK pyramid levels (1 = no pyramid)
  int lk_window = 21;              // [px] LK window side (odd)
  int lk_iterations = 30;          // LK iterations per level
  double lk_epsilon = 0.001;       // [px] LK stops when the update is smaller
  double fb_threshold = 0.3;       // [px] forward-backward disagreement that drops a track
  int min_inliers = 10;            // fewer fitted tracks: STATUS_TOO_FEW_FEATURES
  double huber_k = 1.345;          // Huber threshold [residual sigmas] of the robust fit
  double outlier_sigmas = 4.0;     // residuals beyond this many sigmas are outliers
  double min_sigma = 0.005;        // [px] floor of the residual sigma behind the covariance
  double max_gap = 0.2;            // [s] a longer frame interval restarts (STATUS_FIRST_FRAME)
  bool use_gpu = false;            // CUDA backend; the CPU one (with the reason) without a device or CUDA build

  // Hands every field with its declaration to `v`.
  void visit(ParamVisitor& v);
  // Every violated declaration and relation, each starting with the
  // parameter's name; empty when valid.
  std::vector<std::string> problems() const;
  std::string validate() const;  // problems() joined with "; "
};

}  // namespace hapi_frontend
