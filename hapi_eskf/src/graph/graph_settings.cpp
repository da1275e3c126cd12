// Checks and text forms of GraphSettings, driven by graph_settings.def.
#include "hapi_eskf/graph/graph_settings.hpp"

#include "hapi_eskf/settings.hpp"
#include "hapi_eskf/settings_table.hpp"

namespace hapi_eskf {
namespace graph {

std::string GraphSettings::validate() const {
  const std::string err = fieldRangeError(*this);
  if (!err.empty()) return err;
  if (!(sigma_acceleration > 0.0) || !(sigma_angular_acceleration > 0.0))
    return "sigma_acceleration and sigma_angular_acceleration must be > 0";
  if (!frame_error_covariance.allFinite() || !(frame_error_covariance.diagonal().minCoeff() >= 0.0))
    return "frame_error_covariance must be finite with a non-negative diagonal";
  return "";
}

std::string setFieldFromText(GraphSettings* s, const std::string& name, const std::string& value) {
  return setTableFieldFromText(s, name, value);
}

GraphSettings graphSettings(const EskfSettings& s) {
  GraphSettings g;
  static_cast<GraphTable&>(g) = s.graph;
  g.sigma_acceleration = s.sigma_acceleration;
  g.sigma_angular_acceleration = s.sigma_angular_acceleration;
  g.frame_error_covariance = s.frameErrorCameraCovariance();
  return g;
}

}  // namespace graph
}  // namespace hapi_eskf
