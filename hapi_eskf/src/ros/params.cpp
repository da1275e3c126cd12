#include "hapi_eskf/ros/params.hpp"

#include <ros/node_handle.h>
#include <ros/param.h>

#include <cmath>
#include <set>
#include <sstream>

namespace hapi_eskf {
namespace ros_glue {
namespace {

// Names asked for by the current loadParams() on this thread (every read goes
// through read()/readDouble(), so the list cannot drift from the code).
thread_local std::set<std::string>* t_known = nullptr;

// Reads `name` into *v when present. A present parameter of the wrong type is
// an error (ros::NodeHandle::param would silently use the default instead).
template <typename T>
bool read(const ros::NodeHandle& nh, const std::string& name, T* v, std::string* err) {
  if (t_known) t_known->insert(name);
  if (!nh.hasParam(name)) return true;
  T tmp;
  if (!nh.getParam(name, tmp)) {
    *err = "parameter ~" + name + " has the wrong type";
    return false;
  }
  *v = tmp;
  return true;
}

// Doubles may be written as integers in YAML ("rate: 2").
bool readDouble(const ros::NodeHandle& nh, const std::string& name, double* v, std::string* err) {
  if (t_known) t_known->insert(name);
  if (!nh.hasParam(name)) return true;
  double d;
  int i;
  if (nh.getParam(name, d)) {
    *v = d;
  } else if (nh.getParam(name, i)) {
    *v = i;
  } else {
    *err = "parameter ~" + name + " must be a number";
    return false;
  }
  return true;
}

}  // namespace

std::string NodeletParams::validate() const {
  std::ostringstream e;
  const std::string f = filter.validate();
  if (!f.empty()) return f;
  if (world_frame.empty()) return "~world_frame must not be empty";
  if (!camera_frame.empty() && camera_frame == world_frame) return "~camera_frame must differ from ~world_frame";
  if (!base_frame.empty() && (base_frame == world_frame || base_frame == camera_frame))
    return "~base_frame must differ from ~world_frame and ~camera_frame";
  if (!(map_publish_rate > 0.0 && map_publish_rate <= 100.0) || !std::isfinite(map_publish_rate))
    return "~map_publish_rate must be in (0, 100] Hz";
  if (path_max_length < 1) return "~path_max_length must be >= 1";
  if (max_measurements_per_msg < 1 || max_measurements_per_msg > 1000000)
    return "~max_measurements_per_msg must be in [1, 1000000]";
  if (!(time_jump_reset > 0.0) || !std::isfinite(time_jump_reset)) return "~time_jump_reset must be > 0 s";
  if (!(diagnostics_period > 0.0) || !std::isfinite(diagnostics_period)) return "~diagnostics_period must be > 0 s";
  if (use_imu && imu_topic.empty()) return "~imu_topic must not be empty when ~use_imu is true";
  if (!(gyro_noise_density > 0.0) || !std::isfinite(gyro_noise_density)) return "~gyro_noise_density must be > 0";
  if (imu_buffer_size < 1) return "~imu_buffer_size must be >= 1";
  if (output_dir.empty()) return "~output_dir must not be empty";
  return "";
}

std::string loadParams(const ros::NodeHandle& pnh, NodeletParams* out) {
  NodeletParams p;  // defaults
  std::set<std::string> known;
  t_known = &known;
  struct Reset {
    ~Reset() { t_known = nullptr; }
  } reset;
  EskfSettings& s = p.filter;
  std::string err;
  std::string backend = toString(s.backend), precision = toString(s.precision);
  const bool ok =
      read(pnh, "max_landmarks", &s.max_landmarks, &err) && read(pnh, "max_new_landmarks", &s.max_new_landmarks, &err) &&
      read(pnh, "bootstrap_landmarks", &s.bootstrap_landmarks, &err) &&
      read(pnh, "max_update_landmarks", &s.max_update_landmarks, &err) &&
      readDouble(pnh, "full_pool_add_fraction", &s.full_pool_add_fraction, &err) &&
      read(pnh, "backend", &backend, &err) && read(pnh, "precision", &precision, &err) &&
      read(pnh, "cuda_device", &s.cuda_device, &err) && read(pnh, "max_hamming", &s.max_hamming, &err) &&
      readDouble(pnh, "match_ratio", &s.match_ratio, &err) && readDouble(pnh, "gate_chi2", &s.gate_chi2, &err) &&
      read(pnh, "ransac_iterations", &s.ransac_iterations, &err) &&
      readDouble(pnh, "measurement_angular_sigma", &s.measurement_angular_sigma, &err) &&
      readDouble(pnh, "relocalise_gap", &s.relocalise_gap, &err) &&
      readDouble(pnh, "velocity_damping", &s.velocity_damping, &err) &&
      readDouble(pnh, "angular_velocity_damping", &s.angular_velocity_damping, &err) &&
      readDouble(pnh, "sigma_acceleration", &s.sigma_acceleration, &err) &&
      readDouble(pnh, "sigma_angular_acceleration", &s.sigma_angular_acceleration, &err) &&
      readDouble(pnh, "initial_sigma_position", &s.initial_sigma_position, &err) &&
      readDouble(pnh, "initial_sigma_orientation", &s.initial_sigma_orientation, &err) &&
      readDouble(pnh, "initial_sigma_velocity", &s.initial_sigma_velocity, &err) &&
      readDouble(pnh, "initial_sigma_angular_velocity", &s.initial_sigma_angular_velocity, &err) &&
      read(pnh, "allow_cpu_fallback", &p.allow_cpu_fallback, &err) && read(pnh, "world_frame", &p.world_frame, &err) &&
      read(pnh, "camera_frame", &p.camera_frame, &err) && read(pnh, "base_frame", &p.base_frame, &err) &&
      read(pnh, "publish_tf", &p.publish_tf, &err) && readDouble(pnh, "map_publish_rate", &p.map_publish_rate, &err) &&
      read(pnh, "path_max_length", &p.path_max_length, &err) &&
      read(pnh, "max_measurements_per_msg", &p.max_measurements_per_msg, &err) &&
      readDouble(pnh, "time_jump_reset", &p.time_jump_reset, &err) &&
      readDouble(pnh, "diagnostics_period", &p.diagnostics_period, &err) && read(pnh, "use_imu", &p.use_imu, &err) &&
      read(pnh, "imu_topic", &p.imu_topic, &err) &&
      readDouble(pnh, "gyro_noise_density", &p.gyro_noise_density, &err) &&
      read(pnh, "imu_buffer_size", &p.imu_buffer_size, &err) && read(pnh, "output_dir", &p.output_dir, &err);
  if (!ok) return err;
  // First path component of every parameter under ~ that nothing read.
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
  if (!parseBackendKind(backend, &s.backend)) return "~backend must be 'cpu' or 'cuda', got '" + backend + "'";
  if (!parsePrecision(precision, &s.precision)) return "~precision must be 'fp64' or 'fp32', got '" + precision + "'";
  const std::string v = p.validate();
  if (!v.empty()) return v;
  *out = p;
  return "";
}

}  // namespace ros_glue
}  // namespace hapi_eskf
