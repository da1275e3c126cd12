// Reading ImagingFlowNodelet's ~ parameters (imaging_flow_params.hpp).
#include "imaging_flow_params.hpp"

#include "hapi_frontend/grey_convert.hpp"
#include "param_server_reader.hpp"

namespace hapi_frontend {

void ImagingFlowNodeletParams::visit(ParamVisitor& v) {
  static const ParamSpec kTransport =
      ParamSpec::text("image_transport", {}, "image_transport plugin of the image (raw, compressed)");
  v.visit(kTransport, image_transport);
  v.visit(mono16BitsSpec(), mono16_bits);
}

void readImagingFlowParams(hapi_nodelet_kit::ParamReader& reader, ImagingFlowNodeletParams* p) {
  ParamServerReader read(reader);
  p->flow.visit(read);
  p->visit(read);
  for (const std::string& e : rangeProblems(*p)) reader.error("~" + e);
  for (const std::string& e : p->flow.problems()) reader.error("~" + e);
  reader.warnAboutUnknown("docs/RUNNING.md (image flow)");
}

}  // namespace hapi_frontend
