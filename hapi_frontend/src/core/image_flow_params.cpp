// The declaration of every image-flow setting (image_flow_params.hpp). The
// only place an image-flow range is written.
#include "hapi_frontend/image_flow_params.hpp"


namespace hapi_frontend {

void ImageFlowParams::visit(ParamVisitor& vis) {
  using R = NumberRange;
  using S = ParamSpec;
  static const S kU = S::number("u", R::atLeast(-1), "px", "measurement pixel column; -1 = image centre");
  static const S kV = S::number("v", R::atLeast(-1), "px", "measurement pixel row; -1 = image centre");
  // An affine fit needs features spread around the pixel: below ~8 px a
  // window holds too few corners; above 400 px the affine model of a curved
  // surface no longer holds (and the cost grows with the area).
  static const S kRadius = S::number("search_radius", R::closed(8, 400), "px",
                                     "half size of the square about (u, v) that features are taken from");
  static const S kMax = S::number("max_features", R::closed(3, 5000), "", "strongest corners tracked");
  static const S kDist = S::number("min_feature_distance", R::closed(1, 100), "px", "smallest distance of two corners");
  static const S kQuality = S::number("feature_quality", R::open(0, 1), "",
                                      "weakest corner kept, relative to the strongest (Shi-Tomasi)");
  // Each level halves the image: 6 levels track 60 px motions with a 21 px
  // window, far beyond a frame's motion at 40 Hz.
  static const S kLevels = S::number("pyramid_levels", R::closed(1, 6), "", "LK pyramid levels (1 = none)");
  static const S kWindow = S::number("lk_window", R::closed(5, 61), "px", "LK window side (odd)");
  static const S kIter = S::number("lk_iterations", R::closed(1, 200), "", "LK iterations per level").coreOnly();
  static const S kEps = S::number("lk_epsilon", R::open(0, 1), "px", "LK stops below this update").coreOnly();
  static const S kFb = S::number("fb_threshold", R::above(0), "px",
                                 "forward-backward disagreement that drops a track");
  // Three points determine an affine flow; the residual sigma needs more.
  static const S kMin = S::number("min_inliers", R::closed(4, 5000), "", "fewest fitted tracks for a flow");
  static const S kHuber = S::number("huber_k", R::above(0), "sigmas", "Huber threshold of the fit").coreOnly();
  static const S kOut = S::number("outlier_sigmas", R::above(1), "sigmas", "residual beyond which a track is an outlier")
                            .coreOnly();
  static const S kFloor = S::number("min_sigma", R::above(0), "px", "floor of the residual sigma of the covariance");
  static const S kGap = S::number("max_gap", R::above(0), "s", "longer frame intervals restart the tracker");
  static const S kGpu = S::flag("use_gpu", "CUDA backend (the CPU one, with an error, without a CUDA device)");
  vis.visit(kU, u);
  vis.visit(kV, v);
  vis.visit(kRadius, search_radius);
  vis.visit(kMax, max_features);
  vis.visit(kDist, min_feature_distance);
  vis.visit(kQuality, feature_quality);
  vis.visit(kLevels, pyramid_levels);
  vis.visit(kWindow, lk_window);
  vis.visit(kIter, lk_iterations);
  vis.visit(kEps, lk_epsilon);
  vis.visit(kFb, fb_threshold);
  vis.visit(kMin, min_inliers);
  vis.visit(kHuber, huber_k);
  vis.visit(kOut, outlier_sigmas);
  vis.visit(kFloor, min_sigma);
  vis.visit(kGap, max_gap);
  vis.visit(kGpu, use_gpu);
}

std::vector<std::string> ImageFlowParams::problems() const {
  std::vector<std::string> out = rangeProblems(*this);
  if (lk_window % 2 == 0) out.push_back("lk_window must be odd, got " + std::to_string(lk_window));
  checkRelation(min_inliers <= max_features, "min_inliers", min_inliers, "<=", "max_features", max_features, &out);
  checkRelation(outlier_sigmas >= huber_k, "outlier_sigmas", outlier_sigmas, ">=", "huber_k", huber_k, &out);
  return out;
}

std::string ImageFlowParams::validate() const { return joinProblems(problems()); }

}  // namespace hapi_frontend
