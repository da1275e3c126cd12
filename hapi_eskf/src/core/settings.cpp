#include "hapi_eskf/settings.hpp"

#include <cmath>
#include <sstream>

namespace hapi_eskf {
namespace {

bool finitePositive(double x) { return std::isfinite(x) && x > 0.0; }

}  // namespace

std::string EskfSettings::validate() const {
  std::ostringstream e;
  if (max_landmarks < 1 || max_landmarks > 200000)
    e << "max_landmarks must be in [1, 200000], got " << max_landmarks;
  else if (max_new_landmarks < 0 || max_new_landmarks > max_landmarks)
    e << "max_new_landmarks must be in [0, max_landmarks], got " << max_new_landmarks;
  else if (max_update_landmarks < 1)
    e << "max_update_landmarks must be >= 1, got " << max_update_landmarks;
  else if (max_frame_measurements < 1)
    e << "max_frame_measurements must be >= 1, got " << max_frame_measurements;
  else if (!(full_pool_add_fraction >= 0.0 && full_pool_add_fraction <= 1.0))
    e << "full_pool_add_fraction must be in [0, 1], got " << full_pool_add_fraction;
  else if (cuda_device < 0)
    e << "cuda_device must be >= 0, got " << cuda_device;
  else if (max_hamming < 0)
    e << "max_hamming must be >= 0, got " << max_hamming;
  else if (!(match_ratio > 0.0 && match_ratio <= 1.0))
    e << "match_ratio must be in (0, 1], got " << match_ratio;
  else if (!finitePositive(gate_chi2))
    e << "gate_chi2 must be > 0, got " << gate_chi2;
  else if (!(velocity_damping > 0.0 && velocity_damping <= 1.0))
    e << "velocity_damping must be in (0, 1], got " << velocity_damping;
  else if (!(angular_velocity_damping > 0.0 && angular_velocity_damping <= 1.0))
    e << "angular_velocity_damping must be in (0, 1], got " << angular_velocity_damping;
  else if (!finitePositive(sigma_acceleration))
    e << "sigma_acceleration must be > 0, got " << sigma_acceleration;
  else if (!finitePositive(sigma_angular_acceleration))
    e << "sigma_angular_acceleration must be > 0, got " << sigma_angular_acceleration;
  else if (bootstrap_landmarks < 0 || bootstrap_landmarks > max_landmarks)
    e << "bootstrap_landmarks must be in [0, max_landmarks], got " << bootstrap_landmarks;
  else if (ransac_iterations < 0 || ransac_iterations > 100000)
    e << "ransac_iterations must be in [0, 100000], got " << ransac_iterations;
  else if (!(std::isfinite(relocalise_gap) && relocalise_gap >= 0.0))
    e << "relocalise_gap must be >= 0 s (0 = off), got " << relocalise_gap;
  else if (!(std::isfinite(measurement_angular_sigma) && measurement_angular_sigma >= 0.0 &&
             measurement_angular_sigma < 0.1))
    e << "measurement_angular_sigma must be in [0, 0.1) rad, got " << measurement_angular_sigma;
  else if (!finitePositive(initial_sigma_position))
    e << "initial_sigma_position must be > 0, got " << initial_sigma_position;
  else if (!finitePositive(initial_sigma_orientation))
    e << "initial_sigma_orientation must be > 0, got " << initial_sigma_orientation;
  else if (!finitePositive(initial_sigma_velocity))
    e << "initial_sigma_velocity must be > 0, got " << initial_sigma_velocity;
  else if (!finitePositive(initial_sigma_angular_velocity))
    e << "initial_sigma_angular_velocity must be > 0, got " << initial_sigma_angular_velocity;
  return e.str();
}

const char* toString(BackendKind b) { return b == BackendKind::kCuda ? "cuda" : "cpu"; }
const char* toString(Precision p) { return p == Precision::kFp32 ? "fp32" : "fp64"; }

bool parseBackendKind(const std::string& s, BackendKind* out) {
  if (s == "cpu") { *out = BackendKind::kCpu; return true; }
  if (s == "cuda") { *out = BackendKind::kCuda; return true; }
  return false;
}

bool parsePrecision(const std::string& s, Precision* out) {
  if (s == "fp64") { *out = Precision::kFp64; return true; }
  if (s == "fp32") { *out = Precision::kFp32; return true; }
  return false;
}

}  // namespace hapi_eskf
