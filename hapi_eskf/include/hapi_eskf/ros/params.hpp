// Private (~) parameters of hapi_eskf/EskfNodelet, read and validated once at
// start-up. The nodelet's own parameters are declared once in
// nodelet_params.def, the filter's in eskf_settings.def (names, defaults,
// ranges, units: hapi_eskf/field_table.hpp); config/eskf.yaml documents every
// one of them with its default (checked by test/ros/params_yaml_rostest.cpp).
#pragma once

#include "hapi_eskf/settings.hpp"

#include <string>
#include <type_traits>
#include <vector>

namespace ros {
class NodeHandle;
}

namespace hapi_eskf {
namespace ros_glue {

struct NodeletParams {
  EskfSettings filter;  // same names as the EskfSettings fields

#define HAPI_FIELD(type, name, default_value, range, unit, doc) type name = default_value;
#include "hapi_eskf/ros/nodelet_params.def"
#undef HAPI_FIELD

  // Set by loadParams: names under ~ that no parameter reads (typos such as
  // ~max_landmark would otherwise be silently ignored); the nodelet warns.
  std::vector<std::string> unknown;

  // Empty when valid, else a message naming the offending parameter: the
  // filter's settings, every field against its table range, then the rules
  // between parameters (distinct frames, imu_topic with use_imu).
  std::string validate() const;
};

// Calls visit(const FieldInfo&, field) for every nodelet parameter of `p`
// (not the filter's: forEachField(p.filter, ...)) in table order.
template <typename Params, typename Visitor,
          typename = std::enable_if_t<std::is_same<std::remove_const_t<Params>, NodeletParams>::value>>
void forEachField(Params& p, Visitor&& visit) {
#define HAPI_FIELD(type, name, default_value, range, unit, doc) visit(FieldInfo{#name, range, unit, doc}, p.name);
#include "hapi_eskf/ros/nodelet_params.def"
#undef HAPI_FIELD
}

// Calls visit(const FieldInfo&, field) for every ~ parameter: the filter's
// settings, then the nodelet's own.
template <typename Params, typename Visitor,
          typename = std::enable_if_t<std::is_same<std::remove_const_t<Params>, NodeletParams>::value>>
void forEachParameter(Params& p, Visitor&& visit) {
  hapi_eskf::forEachField(p.filter, visit);
  forEachField(p, visit);
}

// Reads every parameter from `pnh` (defaults above). Returns an empty string on
// success, else the error (wrong type, unknown enum value, out of range). A
// present parameter of the wrong type is an error (ints are accepted for
// doubles); names under ~ that no parameter reads are listed in out->unknown.
std::string loadParams(const ros::NodeHandle& pnh, NodeletParams* out);

}  // namespace ros_glue
}  // namespace hapi_eskf
