// Settings of the Graph SLAM back end (docs/DESIGN.md "Graph SLAM"), declared
// once in graph_settings.def; in the filter's table (EskfSettings, the ROS
// parameters) they are graph_<name>, and graphSettings() reads them there.
#pragma once

#include "hapi_eskf/eskf/frame_error_block.hpp"
#include "hapi_eskf/field_table.hpp"
#include "hapi_eskf/graph/robust_loss.hpp"
#include "hapi_eskf/settings.hpp"

#include <string>
#include <type_traits>

namespace hapi_eskf {
namespace graph {

struct GraphSettings {
#define HAPI_GRAPH_FIELD(type, name, default_value, range, unit, doc) type name = default_value;
#include "hapi_eskf/graph/graph_settings.def"
#undef HAPI_GRAPH_FIELD
  // The velocity random walks of the motion prior: the filter's own
  // settings (eskf_settings.def), not a second copy.
  double sigma_acceleration = EskfSettings().sigma_acceleration;
  double sigma_angular_acceleration = EskfSettings().sigma_angular_acceleration;
  // The frame-shared vision error, Sigma_f in the camera frame [dp, dtheta]
  // (frame_error_block.hpp; the filter's frame_* settings): the tracked
  // pose's floor (docs/DESIGN.md "Graph SLAM", covariances).
  Mat6 frame_error_covariance = frameErrorCameraCovariance(EskfSettings());

  std::string validate() const;  // empty when valid
};

template <typename Settings, typename Visitor,
          typename = std::enable_if_t<std::is_same<std::remove_const_t<Settings>, GraphSettings>::value>>
void forEachField(Settings& s, Visitor&& visit) {
#define HAPI_GRAPH_FIELD(type, name, default_value, range, unit, doc) \
  visit(FieldInfo{#name, range, unit, doc}, s.name);
#include "hapi_eskf/graph/graph_settings.def"
#undef HAPI_GRAPH_FIELD
}

std::string setFieldFromText(GraphSettings* s, const std::string& name, const std::string& value);

// The graph_* fields and the motion prior of the filter's settings.
GraphSettings graphSettings(const EskfSettings& s);

}  // namespace graph
}  // namespace hapi_eskf
