// The content rules of a map (map_checks.hpp).
#include "hapi_eskf/map_file/map_checks.hpp"

#include "hapi_eskf/map_file/map_format.hpp"

#include <Eigen/Cholesky>

#include <cmath>
#include <string>
#include <unordered_set>

namespace hapi_eskf {
namespace map_file {
namespace {

std::string at(std::size_t index) { return "landmark " + std::to_string(index); }

// Symmetric (to 1e-9 of its largest diagonal) and positive definite with a
// smallest Cholesky pivot above 1e-9 of that diagonal's square root.
template <int N>
bool symmetricPositiveDefinite(const Eigen::Matrix<double, N, N>& C) {
  const double scale = C.diagonal().cwiseAbs().maxCoeff();
  const Eigen::LLT<Eigen::Matrix<double, N, N>> llt(C);
  return scale > 0 && (C - C.transpose()).cwiseAbs().maxCoeff() <= 1e-9 * scale && llt.info() == Eigen::Success &&
         llt.matrixLLT().diagonal().minCoeff() > 1e-9 * std::sqrt(scale);
}

// A rotation to 1e-6 in |R^T R - I| (the calibration's R_imu_cam, a keyframe's R_map_cam).
bool isRotation(const Mat3& R) {
  return (R.transpose() * R - Mat3::Identity()).norm() <= 1e-6 && R.determinant() > 0;
}

bool relativelyDifferent(double a, double b) {
  return std::abs(a - b) > kCalibrationTolerance * std::max(std::abs(a), std::abs(b));
}

}  // namespace

uint32_t descriptorLengthOf(uint8_t descriptor_type) {
  switch (descriptor_type) {
    case kDescriptorOrb: return 32;
    case kDescriptorAkaze: return 61;
    default: return 0;
  }
}

MapError checkCalibration(const MapCalibration& c) {
  const double numbers[] = {c.fx, c.fy, c.cx, c.cy, c.baseline};
  for (double v : numbers)
    if (!std::isfinite(v)) return mapError(MapFault::kNotFinite, "calibration intrinsics or baseline");
  if (!c.imu_cam.R_imu_cam.allFinite() || !c.imu_cam.p_imu_cam.allFinite())
    return mapError(MapFault::kNotFinite, "calibration T_imu_cam");
  if (c.width == 0 || c.height == 0 || c.fx <= 0 || c.fy <= 0 || c.baseline <= 0)
    return mapError(MapFault::kBadValue, "calibration needs width, height, fx, fy and baseline > 0");
  if (!isRotation(c.imu_cam.R_imu_cam)) return mapError(MapFault::kBadValue, "calibration R_imu_cam is not a rotation");
  return {};
}

MapError checkLandmark(const MapLandmark& l, uint32_t descriptor_length, std::size_t index) {
  if (l.id == 0) return mapError(MapFault::kBadValue, at(index) + " has id 0");
  if (!l.position.allFinite()) return mapError(MapFault::kNotFinite, at(index) + " position");
  if (!l.covariance.allFinite()) return mapError(MapFault::kNotFinite, at(index) + " covariance");
  if (l.times_observed == 0) return mapError(MapFault::kBadValue, at(index) + " observed 0 times");
  if (l.descriptor.size() != descriptor_length)
    return mapError(MapFault::kDescriptorType, at(index) + " descriptor of " + std::to_string(l.descriptor.size()) +
                                                   " bytes, map's length " + std::to_string(descriptor_length));
  if (!symmetricPositiveDefinite(l.covariance))
    return mapError(MapFault::kCovarianceNotPd, at(index) + " covariance is not symmetric positive definite");
  return {};
}

MapError checkKeyframe(const Keyframe& k, uint32_t descriptor_length, std::size_t index) {
  const std::string name = "keyframe " + std::to_string(index);
  if (k.id == 0) return mapError(MapFault::kBadValue, name + " has id 0");
  if (!k.T_map_cam.matrix().allFinite() || !k.pose_covariance.allFinite() || !std::isfinite(k.stamp))
    return mapError(MapFault::kNotFinite, name + " pose, covariance or stamp");
  if (!isRotation(k.T_map_cam.linear())) return mapError(MapFault::kBadValue, name + " R_map_cam is not a rotation");
  if (!symmetricPositiveDefinite(k.pose_covariance))
    return mapError(MapFault::kCovarianceNotPd, name + " pose covariance is not symmetric positive definite");
  if (k.descriptor_length != static_cast<int>(descriptor_length) || k.point_covariances.size() != k.size() ||
      k.descriptors.size() != k.size() * descriptor_length)
    return mapError(MapFault::kDescriptorType, name + " has descriptors of " + std::to_string(k.descriptor_length) +
                                                   " bytes or arrays of other sizes; the map's length " +
                                                   std::to_string(descriptor_length));
  for (std::size_t i = 0; i < k.size(); ++i) {
    if (!k.points[i].allFinite() || !k.point_covariances[i].allFinite())
      return mapError(MapFault::kNotFinite, name + " point " + std::to_string(i));
    if (!symmetricPositiveDefinite(k.point_covariances[i]))
      return mapError(MapFault::kCovarianceNotPd,
                      name + " point " + std::to_string(i) + " covariance is not symmetric positive definite");
  }
  return {};
}

MapError checkMapData(const MapData& map) {
  if (map.map_frame.empty() || map.map_frame.size() > kMaxNameBytes || map.camera_frame.size() > kMaxNameBytes)
    return mapError(MapFault::kBadValue,
                    "map frame name empty or frame names longer than " + std::to_string(kMaxNameBytes) + " bytes");
  if (!map.gravity_direction.allFinite() || !std::isfinite(map.created))
    return mapError(MapFault::kNotFinite, "gravity direction or creation time");
  const double g = map.gravity_direction.norm();
  if (g != 0.0 && std::abs(g - 1.0) > 1e-6)
    return mapError(MapFault::kBadValue, "gravity direction has norm " + std::to_string(g) + " (1, or 0 for none)");
  if (MapError e = checkCalibration(map.calibration)) return e;
  const uint32_t expected = descriptorLengthOf(map.descriptor_type);
  if (expected == 0 || map.descriptor_length != expected)
    return mapError(MapFault::kDescriptorType, "descriptor type " + std::to_string(map.descriptor_type) +
                                                   " with length " + std::to_string(map.descriptor_length));
  std::unordered_set<uint64_t> ids;
  ids.reserve(map.landmarks.size());
  for (std::size_t i = 0; i < map.landmarks.size(); ++i) {
    if (MapError e = checkLandmark(map.landmarks[i], map.descriptor_length, i)) return e;
    if (!ids.insert(map.landmarks[i].id).second)
      return mapError(MapFault::kBadValue, at(i) + " repeats id " + std::to_string(map.landmarks[i].id));
  }
  ids.clear();
  for (std::size_t i = 0; i < map.keyframes.size(); ++i) {
    if (MapError e = checkKeyframe(map.keyframes[i], map.descriptor_length, i)) return e;
    if (!ids.insert(map.keyframes[i].id).second)
      return mapError(MapFault::kBadValue,
                      "keyframe " + std::to_string(i) + " repeats id " + std::to_string(map.keyframes[i].id));
  }
  return {};
}

MapError checkSameCamera(const MapCalibration& map, const MapCalibration& running) {
  auto differs = [](const std::string& what, double m, double r) {
    return mapError(MapFault::kCalibrationMismatch,
                    what + " " + std::to_string(m) + " in the map, " + std::to_string(r) + " running");
  };
  if (map.width != running.width || map.height != running.height)
    return differs("image width*height", double(map.width) * map.height, double(running.width) * running.height);
  if (relativelyDifferent(map.fx, running.fx)) return differs("fx", map.fx, running.fx);
  if (relativelyDifferent(map.fy, running.fy)) return differs("fy", map.fy, running.fy);
  if (std::abs(map.cx - running.cx) > kCalibrationTolerance * map.width) return differs("cx", map.cx, running.cx);
  if (std::abs(map.cy - running.cy) > kCalibrationTolerance * map.height) return differs("cy", map.cy, running.cy);
  if (relativelyDifferent(map.baseline, running.baseline)) return differs("baseline", map.baseline, running.baseline);
  if (map.has_imu && running.has_imu) {
    const double dr = (map.imu_cam.R_imu_cam.transpose() * running.imu_cam.R_imu_cam - Mat3::Identity()).norm();
    const double dp = (map.imu_cam.p_imu_cam - running.imu_cam.p_imu_cam).norm();
    if (dr > kExtrinsicRotationTolerance) return differs("R_imu_cam (|R_map^T R_running - I|)", dr, 0.0);
    if (dp > kExtrinsicTranslationTolerance) return differs("p_imu_cam difference [m]", dp, 0.0);
  }
  return {};
}

}  // namespace map_file
}  // namespace hapi_eskf
