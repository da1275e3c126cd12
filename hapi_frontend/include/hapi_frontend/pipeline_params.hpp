// Settings of the StereoPipeline and their declarations (name, range, unit,
// meaning: pipeline_params.cpp), the single source of every front-end range:
// StereoPipeline's constructor and the nodelet's parameter reader both use
// them. The defaults are the field initialisers below; config/frontend.yaml
// repeats them for users. ROS-free.
#pragma once

#include "hapi_frontend/features.hpp"
#include "hapi_frontend/param_spec.hpp"

#include <string>
#include <vector>

namespace hapi_frontend {

struct PipelineParams {
  std::string detector = "orb";     // "orb" (project's own ORB core, CPU or CUDA) | "akaze" (OpenCV)
  bool use_gpu = false;             // ORB only; falls back to CPU (with a warning) without a device
  int landmarks_per_frame = 200;    // N strongest matched landmarks kept per frame
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

  // Hands every field with its declaration to `v`, in the order of
  // config/frontend.yaml (the internal refine_* values last).
  void visit(ParamVisitor& v);
  // Every violated declaration and relation between fields (min < max ...),
  // each message starting with the parameter's name; empty when valid.
  std::vector<std::string> problems() const;
  std::string validate() const;  // problems() joined with "; ", empty when valid
};

}  // namespace hapi_frontend
