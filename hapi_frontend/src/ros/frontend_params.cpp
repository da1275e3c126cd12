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
  v.visit(kApprox, approximate_sync);
  v.visit(kQueue, queue_size);
  v.visit(kSlop, approx_slop);
  v.visit(kTransport, image_transport);
  v.visit(mono16BitsSpec(), mono16_bits);
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
