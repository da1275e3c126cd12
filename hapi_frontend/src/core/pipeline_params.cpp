// The declaration of every StereoPipeline setting (name = ROS private
// parameter, range, unit, meaning) and the relations between them. The only
// place a front-end range is written.
#include "hapi_frontend/pipeline_params.hpp"


namespace hapi_frontend {

void PipelineParams::visit(ParamVisitor& v) {
  using R = NumberRange;
  using S = ParamSpec;
  // --- features
  static const S kDetector = S::text("detector", {"orb", "akaze"}, "orb (own ORB core, CPU or CUDA) | akaze (OpenCV)");
  static const S kUseGpu = S::flag("use_gpu", "ORB on the GPU; the CPU path (announced) without a device");
  static const S kLandmarks = S::number("landmarks_per_frame", R::atLeast(1), "",
                                        "N strongest matched landmarks published per frame")
                                  .renamedFrom("max_landmarks");
  static const S kFeatures = S::number("detector_features", R::atLeast(1), "",
                                       "keypoints detected per image before matching");
  // FAST compares 8-bit grey levels: a threshold outside [1, 254] accepts
  // every pixel or none.
  static const S kFast = S::number("fast_threshold", R::closed(1, 254), "grey levels", "FAST threshold (ORB)");
  // Both ORB cores accept any count >= 1 (the CUDA rank key has room for
  // 65535 levels), so the bound guards against typos, not memory. It is the
  // range the front end accepted so far. With the fixed scale factor 1.2,
  // level 11 (the 12th) is 1/7.4 of the image: 65 px high on a 640x480 frame,
  // little more than the 40 px a level needs to hold any detection (2 * edge
  // + 2, orb_core); with downscale 2 it is already below. Further levels
  // would only take a share of detector_features and return nothing.
  static const S kLevels = S::number("pyramid_levels", R::closed(1, 12), "",
                                     "ORB scale pyramid levels (scale factor 1.2 per level)");
  static const S kDownscale = S::number("downscale", R::closed(1, 16), "",
                                        "shrink images by this factor before detection");
  // --- camera model
  static const S kRectified = S::flag("rectified_input", "images are already rectified (P used, D ignored)");
  static const S kSigma = S::number("pixel_sigma", R::above(0), "px", "keypoint noise (1 sigma) of the MMSE estimate");
  static const S kMinDepth = S::number("min_depth", R::above(0), "m", "nearest accepted landmark depth");
  static const S kMaxDepth = S::number("max_depth", R::above(0), "m", "farthest accepted landmark depth");
  // --- left/right matching
  static const S kEpipolar = S::number("max_epipolar_px", R::above(0), "px",
                                       "distance of the right keypoint to the epipolar line");
  static const S kMinDisp = S::number("min_disparity", R::atLeast(0), "px",
                                      "smallest x_left - x_right (> 0: points in front)");
  static const S kMaxDisp = S::number("max_disparity", R::above(0), "px",
                                      "largest x_left - x_right (bounds the closest depth)");
  static const S kRatio = S::number("match_ratio", R::openClosed(0, 1), "", "Lowe ratio: best < ratio * second best");
  static const S kHamming = S::number("match_max_hamming", R::atLeast(0), "bits", "absolute descriptor distance bound");
  static const S kCross = S::flag("match_cross_check", "keep only mutual best matches");
  // --- sub-pixel refinement (core tuning values, not ROS parameters, except
  // the correlation threshold: faint textures such as skin need it lower,
  // config/frontend_skin.yaml)
  static const S kRefine = S::flag("refine_subpixel", "ZNCC refinement of the right keypoint").coreOnly();
  static const S kHalfPatch =
      S::number("refine_half_patch", R::closed(1, 30), "px", "half size of the correlated patch").coreOnly();
  static const S kRadius = S::number("refine_radius", R::closed(1, 30), "px", "search radius").coreOnly();
  static const S kZncc = S::number("refine_min_zncc", R::closed(-1, 1), "", "weakest correlation peak kept");

  v.visit(kDetector, detector);
  v.visit(kUseGpu, use_gpu);
  v.visit(kLandmarks, landmarks_per_frame);
  v.visit(kFeatures, detector_features);
  v.visit(kFast, fast_threshold);
  v.visit(kLevels, pyramid_levels);
  v.visit(kDownscale, downscale);
  v.visit(kRectified, rectified_input);
  v.visit(kSigma, pixel_sigma);
  v.visit(kMinDepth, min_depth);
  v.visit(kMaxDepth, max_depth);
  v.visit(kEpipolar, match.max_epipolar_px);
  v.visit(kMinDisp, match.min_disparity);
  v.visit(kMaxDisp, match.max_disparity);
  v.visit(kRatio, match.ratio);
  v.visit(kHamming, match.max_hamming);
  v.visit(kCross, match.cross_check);
  v.visit(kRefine, refine_subpixel);
  v.visit(kHalfPatch, refine_half_patch);
  v.visit(kRadius, refine_radius);
  v.visit(kZncc, refine_min_zncc);
}

std::vector<std::string> PipelineParams::problems() const {
  std::vector<std::string> out = rangeProblems(*this);
  // Not enough keypoints could never give N landmarks.
  checkRelation(detector_features >= landmarks_per_frame, "detector_features", detector_features, ">=",
                "landmarks_per_frame", landmarks_per_frame, &out);
  checkRelation(min_depth < max_depth, "min_depth", min_depth, "<", "max_depth", max_depth, &out);
  checkRelation(match.min_disparity < match.max_disparity, "min_disparity", match.min_disparity, "<",
                "max_disparity", match.max_disparity, &out);
  return out;
}

std::string PipelineParams::validate() const { return joinProblems(problems()); }

}  // namespace hapi_frontend
