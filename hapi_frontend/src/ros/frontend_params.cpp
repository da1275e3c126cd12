// Reading StereoFrontendNodelet's ~ parameters: walks the declarations of
// PipelineParams and FrontendNodeletParams with a ParamReader, then checks
// them against the same declarations.
#include "frontend_params.hpp"

#include "hapi_frontend/grey_convert.hpp"
#include "param_server_reader.hpp"

#include <hapi_nodelet_kit/time_jump_reset_param.hpp>

namespace hapi_frontend {

void FrontendNodeletParams::visit(ParamVisitor& v) {
  using R = NumberRange;
  using S = ParamSpec;
  static const S kApprox = S::flag("approximate_sync", "false: exact stamps (hardware-triggered pair)");
  static const S kQueue = S::number("queue_size", R::closed(1, 1000), "", "per-topic subscriber / synchroniser queue");
  static const S kSlop = S::number("approx_slop", R::open(0, 1), "s",
                                   "approximate mode: largest accepted |t_left - t_right|");
  static const S kTransport = S::text("image_transport", {}, "image_transport plugin of both images (raw, compressed)");
  // Self-checks (frontend_self_check.hpp). A calibrated pair leaves ~0.05 px
  // of median vertical disparity; the matcher still pairs keypoints up to
  // max_epipolar_px off, so a bad calibration shows between the two.
  static const S kCheckDisparity = S::number("check_max_vertical_disparity", R::above(0), "px",
                                             "self-check: median vertical disparity of the matches beyond this = "
                                             "stereo rectification off");
  // Rendered globe frames measure 0.02-0.2 sharp and 0.45-0.55 with 60 ms
  // of fast hand-held motion, where the landmarks fall from 200 to 5-20 per
  // frame (test/system/self_check/blur.test); EuRoC V1_01's still frames
  // (a room of straight edges) 0.30-0.31; a 5 px smear of an isotropic
  // texture 0.33, 9 px 0.64 (image_quality.hpp).
  static const S kCheckBlur = S::number("check_max_motion_blur", R::open(0, 1), "",
                                        "self-check: motion blur beyond this = images smeared (exposure too long)");
  // The back end keeps tracking down to ~20 matched landmarks per frame;
  // below 30 its pose noise grows quickly.
  static const S kCheckLandmarks = S::number("check_min_landmarks", R::atLeast(0), "",
                                             "self-check: fewer landmarks per frame (median) = low texture");
  v.visit(kApprox, approximate_sync);
  v.visit(kQueue, queue_size);
  v.visit(kSlop, approx_slop);
  v.visit(kTransport, image_transport);
  v.visit(mono16BitsSpec(), mono16_bits);
  v.visit(kCheckDisparity, self_check.max_vertical_disparity_px);
  v.visit(kCheckBlur, self_check.max_motion_blur);
  v.visit(kCheckLandmarks, self_check.min_landmarks);
}

void readFrontendParams(hapi_nodelet_kit::ParamReader& reader, FrontendNodeletParams* p) {
  ParamServerReader read(reader);
  p->pipeline.visit(read);
  p->visit(read);
  p->time_jump_reset = hapi_nodelet_kit::readTimeJumpReset(reader, kOldTimeJumpResetName);

  for (const std::string& e : rangeProblems(*p)) reader.error("~" + e);
  for (const std::string& e : p->pipeline.problems()) reader.error("~" + e);
  reader.warnAboutUnknown("config/frontend.yaml");
}

}  // namespace hapi_frontend
