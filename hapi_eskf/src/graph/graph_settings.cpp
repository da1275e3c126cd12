// Checks and text forms of GraphSettings, driven by graph_settings.def.
#include "hapi_eskf/graph/graph_settings.hpp"

#include "hapi_eskf/settings_table.hpp"

namespace hapi_eskf {
namespace graph {

std::string GraphSettings::validate() const { return fieldRangeError(*this); }

std::string setFieldFromText(GraphSettings* s, const std::string& name, const std::string& value) {
  return setTableFieldFromText(s, name, value);
}

}  // namespace graph
}  // namespace hapi_eskf
