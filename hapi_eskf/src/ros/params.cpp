// Reading and validation of the nodelet's ~ parameters: one loop over the
// settings tables (settings.hpp, nodelet_params.def) through a
// hapi_nodelet_kit::ParamReader, so every table field is a parameter with the
// table's name and default, its type is checked by the reader, and a name
// under ~ that nothing asked the reader for is reported as unknown.
#include "hapi_eskf/ros/params.hpp"

#include "hapi_eskf/so3.hpp"

#include <hapi_nodelet_kit/time_jump_reset_param.hpp>

#include <utility>

namespace hapi_eskf {
namespace ros_glue {
namespace {

// Reads ~name into *v when it is set. Numbers, flags and text are the
// reader's typed reads (an integer is accepted for a double, "rate: 2");
// enums are written by name ("backend: cuda").
template <typename T>
void readField(hapi_nodelet_kit::ParamReader& reader, const std::string& name, T* v) {
  if constexpr (std::is_enum<T>::value) {
    std::string s;
    if (reader.read(name, &s) && !enumFromString(s, v))
      reader.error("~" + name + " must be " + enumChoices<T>() + ", got '" + s + "'");
  } else {
    reader.read(name, v);
  }
}

}  // namespace

std::vector<std::string> NodeletParams::problems() const {
  std::vector<std::string> out;
  const std::string f = filter.validate();
  if (!f.empty()) out.push_back(f);
  forEachField(*this, [&](const FieldInfo& field, const auto& v) {
    std::string e = rangeError(field, v, "~");
    if (!e.empty()) out.push_back(std::move(e));
  });
  // Rules the table's ranges cannot express.
  const auto rule = [&](bool broken, const char* message) {
    if (broken) out.emplace_back(message);
  };
  rule(world_frame.empty(), "~world_frame must not be empty");
  rule(!camera_frame.empty() && camera_frame == world_frame, "~camera_frame must differ from ~world_frame");
  rule(!base_frame.empty() && (base_frame == world_frame || base_frame == camera_frame),
       "~base_frame must differ from ~world_frame and ~camera_frame");
  rule(usesImu() && imu_topic.empty(), "~imu_topic must not be empty with ~motion_model gyro or inertial");
  rule(output_dir.empty(), "~output_dir must not be empty");
  return out;
}

void readParams(hapi_nodelet_kit::ParamReader& reader, NodeletParams* out) {
  NodeletParams p;  // the tables' defaults
  forEachParameter(p, [&](const FieldInfo& f, auto& v) { readField(reader, f.name, &v); });
  p.time_jump_reset = hapi_nodelet_kit::readTimeJumpReset(reader);
  if (reader.read("T_cam_imu", &p.T_cam_imu) && !p.T_cam_imu.empty()) {
    std::string why;
    if (!cameraInImuFromKalibr(p.T_cam_imu, nullptr, &why)) reader.error("~T_cam_imu " + why);
  }
  // ~use_imu: true was the gyro model before ~motion_model existed.
  bool use_imu = false;
  if (reader.read("use_imu", &use_imu)) {
    reader.warn("~use_imu is deprecated: set ~motion_model (gyro or inertial) instead");
    if (use_imu && p.filter.motion_model == MotionModelKind::kConstantVelocity)
      p.filter.motion_model = MotionModelKind::kGyro;
  }
  for (const std::string& e : p.problems()) reader.error(e);
  p.unknown = reader.warnAboutUnknown("config/eskf.yaml");
  *out = std::move(p);
}

bool cameraInImuFromKalibr(const std::vector<double>& T_cam_imu, CameraExtrinsic* out, std::string* why) {
  if (T_cam_imu.size() != 16) {
    *why = "must hold 16 numbers (a row-major 4x4), got " + std::to_string(T_cam_imu.size());
    return false;
  }
  Eigen::Matrix4d T;
  for (int i = 0; i < 16; ++i) T(i / 4, i % 4) = T_cam_imu[static_cast<std::size_t>(i)];
  const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
  if (!T.allFinite() || (T.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-9 ||
      !isRotation(R)) {
    *why = "must be a rigid transform (rotation, translation, last row 0 0 0 1)";
    return false;
  }
  if (out != nullptr) {
    out->R_imu_cam = R.transpose();
    out->p_imu_cam = -R.transpose() * T.topRightCorner<3, 1>();
  }
  return true;
}

std::string loadParams(const ros::NodeHandle& pnh, NodeletParams* out) {
  hapi_nodelet_kit::ParamReader reader(pnh);
  NodeletParams p;
  readParams(reader, &p);
  if (reader.ok()) {
    *out = std::move(p);
    return "";
  }
  std::string joined;
  for (const std::string& e : reader.errors()) joined += (joined.empty() ? "" : "; ") + e;
  return joined;
}

}  // namespace ros_glue
}  // namespace hapi_eskf
