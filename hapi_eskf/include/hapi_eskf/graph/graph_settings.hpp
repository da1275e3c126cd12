// Settings of the Graph SLAM back end (docs/DESIGN.md "Graph SLAM"), declared
// once in graph_settings.def; in the filter's settings
// (EskfSettings::graph; as ROS parameters graph_<name>) they are the table
// GraphTable, and graphSettings() adds the motion prior and frame error of
// the shared parts.
#pragma once

#include "hapi_eskf/backend/measurement_settings.hpp"
#include "hapi_eskf/backend/motion_settings.hpp"
#include "hapi_eskf/field_table.hpp"
#include "hapi_eskf/graph/robust_loss.hpp"

#include <string>
#include <type_traits>

namespace hapi_eskf {

struct EskfSettings;

namespace graph {

// The table: what the user sets.
struct GraphTable {
#define HAPI_GRAPH_FIELD(type, name, default_value, range, unit, doc) type name = default_value;
#include "hapi_eskf/graph/graph_settings.def"
#undef HAPI_GRAPH_FIELD
};

HAPI_SETTINGS_VISITOR(GraphTable) {
#define HAPI_GRAPH_FIELD(type, name, default_value, range, unit, doc) visit(FieldInfo{#name, range, unit, doc}, s.name);
#include "hapi_eskf/graph/graph_settings.def"
#undef HAPI_GRAPH_FIELD
}

// What the algorithm runs with: its table and what it takes from the
// shared parts.
struct GraphSettings : GraphTable {
  // The velocity random walks of the motion prior: the filter's own
  // settings (backend/motion_settings.def), not a second copy.
  double sigma_acceleration = MotionSettings().sigma_acceleration;
  double sigma_angular_acceleration = MotionSettings().sigma_angular_acceleration;
  // The frame-shared vision error, Sigma_f in the camera frame [dp, dtheta]
  // (frame_error_block.hpp; the filter's frame_* settings): the tracked
  // pose's floor (docs/DESIGN.md "Graph SLAM", covariances).
  Mat6 frame_error_covariance = MeasurementSettings().frameErrorCameraCovariance();

  std::string validate() const;  // empty when valid
};

// The table's fields of GraphSettings (the shared parts' are not settings of
// this algorithm).
HAPI_SETTINGS_VISITOR(GraphSettings) {
  forEachField(asPart<GraphTable>(s), visit);
}

std::string setFieldFromText(GraphSettings* s, const std::string& name, const std::string& value);

// The algorithm's part of the filter's settings (EskfSettings::graph) with the
// motion prior and the frame error of the shared parts.
GraphSettings graphSettings(const EskfSettings& s);

}  // namespace graph
}  // namespace hapi_eskf
