// Reading and validation of the nodelet's ~ parameters: one loop over the
// settings tables (eskf_settings.def, nodelet_params.def), so every table
// field is a parameter with the table's name and default, and a name under ~
// that is in no table is reported as unknown.
#include "hapi_eskf/ros/params.hpp"

#include <ros/node_handle.h>
#include <ros/param.h>

#include <set>
#include <type_traits>

namespace hapi_eskf {
namespace ros_glue {
namespace {

// Reads the present parameter `name` into *v; empty on success, else why not.
// A parameter of the wrong type is an error (ros::NodeHandle::param would
// silently use the default instead); doubles may be written as integers in
// YAML ("rate: 2"); enums are written by name ("backend: cuda").
template <typename T>
std::string readValue(const ros::NodeHandle& nh, const std::string& name, T* v) {
  if constexpr (std::is_enum<T>::value) {
    std::string s;
    if (!nh.getParam(name, s)) return "parameter ~" + name + " has the wrong type";
    if (!enumFromString(s, v)) return "~" + name + " must be " + enumChoices<T>() + ", got '" + s + "'";
  } else if constexpr (std::is_same<T, double>::value) {
    double d;
    int i;
    if (nh.getParam(name, d))
      *v = d;
    else if (nh.getParam(name, i))
      *v = i;
    else
      return "parameter ~" + name + " must be a number";
  } else {
    T tmp;
    if (!nh.getParam(name, tmp)) return "parameter ~" + name + " has the wrong type";
    *v = tmp;
  }
  return "";
}

}  // namespace

std::string NodeletParams::validate() const {
  const std::string f = filter.validate();
  if (!f.empty()) return f;
  std::string err;
  forEachField(*this, [&](const FieldInfo& field, const auto& v) {
    if (err.empty()) err = rangeError(field, v, "~");
  });
  if (!err.empty()) return err;
  // Rules the table's ranges cannot express.
  if (world_frame.empty()) return "~world_frame must not be empty";
  if (!camera_frame.empty() && camera_frame == world_frame) return "~camera_frame must differ from ~world_frame";
  if (!base_frame.empty() && (base_frame == world_frame || base_frame == camera_frame))
    return "~base_frame must differ from ~world_frame and ~camera_frame";
  if (use_imu && imu_topic.empty()) return "~imu_topic must not be empty when ~use_imu is true";
  if (output_dir.empty()) return "~output_dir must not be empty";
  return "";
}

std::string loadParams(const ros::NodeHandle& pnh, NodeletParams* out) {
  NodeletParams p;  // the tables' defaults
  std::set<std::string> known;
  std::string err;
  forEachParameter(p, [&](const FieldInfo& f, auto& v) {
    known.insert(f.name);
    if (err.empty() && pnh.hasParam(f.name)) err = readValue(pnh, f.name, &v);
  });
  if (!err.empty()) return err;
  // First path component of every parameter under ~ that no table names.
  std::vector<std::string> all;
  if (ros::param::getParamNames(all)) {
    const std::string prefix = pnh.getNamespace() + "/";
    std::set<std::string> unknown;
    for (const std::string& n : all) {
      if (n.compare(0, prefix.size(), prefix) != 0) continue;
      const std::string key = n.substr(prefix.size(), n.find('/', prefix.size()) - prefix.size());
      if (!known.count(key)) unknown.insert(key);
    }
    p.unknown.assign(unknown.begin(), unknown.end());
  }
  const std::string v = p.validate();
  if (!v.empty()) return v;
  *out = p;
  return "";
}

}  // namespace ros_glue
}  // namespace hapi_eskf
