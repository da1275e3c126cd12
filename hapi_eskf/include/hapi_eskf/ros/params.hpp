// Private (~) parameters of hapi_eskf/EskfNodelet, read and validated once at
// start-up. The nodelet's own parameters are declared once in
// nodelet_params.def, the filter's in its parts' tables (settings.hpp) (names, defaults,
// ranges, units: hapi_eskf/field_table.hpp); ~time_jump_reset belongs to the
// stamp guard and is declared in hapi_nodelet_kit (stamp_guard.hpp), the same
// in every nodelet. config/eskf.yaml documents every one of them with its
// default (checked by test/ros/params_rostest.cpp).
#pragma once

#include "hapi_eskf/eskf/motion_model.hpp"
#include "hapi_eskf/settings.hpp"

#include <hapi_nodelet_kit/param_reader.hpp>
#include <hapi_nodelet_kit/stamp_guard.hpp>

#include <string>
#include <type_traits>
#include <vector>

namespace hapi_eskf {
namespace ros_glue {

struct NodeletParams {
  EskfSettings filter;  // same names as the EskfSettings fields

#define HAPI_FIELD(type, name, default_value, range, unit, doc) type name = default_value;
#include "hapi_eskf/ros/nodelet_params.def"
#undef HAPI_FIELD

  // [s] the stamp guard's threshold (landmarks and IMU inputs).
  double time_jump_reset = hapi_nodelet_kit::TimeJumpResetParam::kDefault;

  // ~T_cam_imu: the IMU frame in the camera frame, X_cam = T X_imu, 16 numbers
  // row-major (Kalibr's T_cam_imu). Empty (the default): the extrinsic comes
  // from TF. A list of numbers is not a table type (field_table.hpp), so it
  // is read and checked here (readParams).
  std::vector<double> T_cam_imu;

  // Set by readParams: names under ~ that no parameter reads (typos such as
  // ~max_landmark would otherwise be silently ignored).
  std::vector<std::string> unknown;

  // Every violated rule, each naming its parameter: the filter's settings,
  // every field against its table range, then the rules between parameters
  // (distinct frames, imu_topic with an IMU model). Empty when valid.
  std::vector<std::string> problems() const;

  // The motion model reads the IMU (gyro, inertial): subscribe to imu_topic.
  bool usesImu() const { return filter.motion_model != MotionModelKind::kConstantVelocity; }
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

// Calls visit(const FieldInfo&, field) for every table parameter: the
// filter's settings, then the nodelet's own.
template <typename Params, typename Visitor,
          typename = std::enable_if_t<std::is_same<std::remove_const_t<Params>, NodeletParams>::value>>
void forEachParameter(Params& p, Visitor&& visit) {
  hapi_eskf::forEachField(p.filter, visit);
  forEachField(p, visit);
}

// Reads every ~ parameter through `reader` into *out (the defaults above for
// absent ones). A wrong type, an unknown enum name, a value out of range or a
// broken rule between parameters is recorded as an error of `reader` (the
// field keeps its default); names under ~ that nothing reads are named in a
// warning of `reader` and listed in out->unknown.
void readParams(hapi_nodelet_kit::ParamReader& reader, NodeletParams* out);

// The camera in the IMU frame from Kalibr's T_cam_imu (16 numbers,
// row-major, X_cam = T X_imu): false and *why for a wrong count or a matrix
// that is not a rigid transform; *out may be null (check only).
bool cameraInImuFromKalibr(const std::vector<double>& T_cam_imu, CameraExtrinsic* out, std::string* why);

// readParams on the parameter server below `pnh`. Returns "" and sets *out
// when every parameter is valid, else the errors joined by "; " (*out
// untouched).
std::string loadParams(const ros::NodeHandle& pnh, NodeletParams* out);

}  // namespace ros_glue
}  // namespace hapi_eskf
