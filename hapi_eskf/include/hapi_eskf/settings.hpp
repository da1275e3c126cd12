// Filter settings. The fields, their defaults, ranges, units and one-line docs
// are declared once, in eskf_settings.def (see field_table.hpp for why); this
// header generates the struct and the visitor from that list. Field names are
// the ROS parameter names used by the nodelet (config/eskf.yaml), so a user
// sees one vocabulary everywhere.
#pragma once

#include "hapi_eskf/field_table.hpp"
#include "hapi_eskf/graph/robust_loss.hpp"

#include <string>
#include <type_traits>

namespace hapi_eskf {

// The SLAM algorithm behind the back-end interface (slam_backend.hpp).
enum class BackendAlgorithm { kEskf, kSeif, kGraph, kFastSlam2 };
enum class BackendKind { kCpu, kCuda };
enum class Precision { kFp64, kFp32 };  // storage/compute precision of C (CUDA backend)
// CUDA backend variants (src/covariance/cuda/blas_traits.hpp): kAuto chooses by size.
enum class CudaRankUpdate { kAuto, kSyrk, kPanelGemm, kRecursive };
enum class CudaSolve { kAuto, kTrsm, kInverse };
// Dense linear algebra of the CPU backend (src/covariance/cpu_linear_algebra.hpp):
// OpenBLAS/LAPACK (DSYRK, DGEMM, DPOTRF, DTRSM) or Eigen alone.
enum class CpuLinearAlgebra { kBlas, kEigen };
// How the covariance absorbs an update (docs/DESIGN.md "Partitioned update"):
// the whole C every frame, or the active part now and the rest deferred.
enum class CovarianceUpdate { kDense, kPartitioned };
// The motion model of the pose block (motion_model.hpp).
enum class MotionModelKind { kConstantVelocity, kGyro, kInertial };

template <>
struct EnumNames<BackendAlgorithm> {
  static constexpr EnumName<BackendAlgorithm> kNames[] = {{BackendAlgorithm::kEskf, "eskf"},
                                                          {BackendAlgorithm::kSeif, "seif"},
                                                          {BackendAlgorithm::kGraph, "graph"},
                                                          {BackendAlgorithm::kFastSlam2, "fastslam2"}};
};
template <>
struct EnumNames<BackendKind> {
  static constexpr EnumName<BackendKind> kNames[] = {{BackendKind::kCpu, "cpu"}, {BackendKind::kCuda, "cuda"}};
};
template <>
struct EnumNames<Precision> {
  static constexpr EnumName<Precision> kNames[] = {{Precision::kFp64, "fp64"}, {Precision::kFp32, "fp32"}};
};
template <>
struct EnumNames<CudaRankUpdate> {
  static constexpr EnumName<CudaRankUpdate> kNames[] = {{CudaRankUpdate::kAuto, "auto"},
                                                        {CudaRankUpdate::kSyrk, "syrk"},
                                                        {CudaRankUpdate::kPanelGemm, "gemm"},
                                                        {CudaRankUpdate::kRecursive, "recursive"}};
};
template <>
struct EnumNames<MotionModelKind> {
  static constexpr EnumName<MotionModelKind> kNames[] = {{MotionModelKind::kConstantVelocity, "constant_velocity"},
                                                         {MotionModelKind::kGyro, "gyro"},
                                                         {MotionModelKind::kInertial, "inertial"}};
};
template <>
struct EnumNames<CudaSolve> {
  static constexpr EnumName<CudaSolve> kNames[] = {
      {CudaSolve::kAuto, "auto"}, {CudaSolve::kTrsm, "trsm"}, {CudaSolve::kInverse, "inverse"}};
};

template <>
struct EnumNames<CpuLinearAlgebra> {
  static constexpr EnumName<CpuLinearAlgebra> kNames[] = {{CpuLinearAlgebra::kBlas, "blas"},
                                                          {CpuLinearAlgebra::kEigen, "eigen"}};
};
template <>
struct EnumNames<CovarianceUpdate> {
  static constexpr EnumName<CovarianceUpdate> kNames[] = {{CovarianceUpdate::kDense, "dense"},
                                                          {CovarianceUpdate::kPartitioned, "partitioned"}};
};

// Smallest RANSAC inlier set that may relocalise the pose (relocalise_gap):
// 12 pairs pin 6 dof with a wide margin against a chance fit of wrong matches.
constexpr int kRelocaliseMinInliers = 6;
// How long after an outage frames without such a fit are held back
// (prediction only: updating or adding landmarks at an unknown pose would
// corrupt the map) before the filter carries on without relocalising (the
// camera may look at unmapped ground only) [s].
constexpr double kRelocaliseWaitS = 2.0;

struct EskfSettings {
#define HAPI_FIELD(type, name, default_value, range, unit, doc) type name = default_value;
#include "hapi_eskf/eskf_settings.def"
#undef HAPI_FIELD

  // Empty when valid, else a message naming the offending field and its
  // range: every field against its table range, then the rules between
  // fields (max_new_landmarks and bootstrap_landmarks <= max_landmarks).
  std::string validate() const;

  // The gyro white noise the prediction assumes [rad/s/sqrt(Hz)]: the
  // sensor's density times the inflation (eskf_settings.def says why).
  double gyroProcessNoiseDensity() const { return gyro_noise_density * gyro_noise_inflation; }
  // A frame-shared vision error is modelled (frame_error_block.hpp): by the
  // ES-EKF with a model that predicts from an IMU (gyro, inertial), whose
  // tight frame-to-frame link would otherwise take the frames' shared errors
  // as information. constant_velocity's angular-velocity random walk absorbs
  // them (consistent without, conservative with it: docs/ACCURACY.md
  // "Consistency"). Not the SEIF: its information-form motion update
  // inverts the transition, and the frame error's (a copy, a restore) are
  // singular.
  bool frameErrorModelled() const {
    return backend_algorithm != BackendAlgorithm::kSeif && motion_model != MotionModelKind::kConstantVelocity &&
           (frame_rotation_sigma > 0.0 || frame_optical_axis_sigma > 0.0 || frame_translation_sigma > 0.0);
  }
};

// Calls visit(const FieldInfo&, field) for every field of `s` in table order;
// the field is `const T&` or `T&` as `s` is const or not.
template <typename Settings, typename Visitor,
          typename = std::enable_if_t<std::is_same<std::remove_const_t<Settings>, EskfSettings>::value>>
void forEachField(Settings& s, Visitor&& visit) {
#define HAPI_FIELD(type, name, default_value, range, unit, doc) visit(FieldInfo{#name, range, unit, doc}, s.name);
#include "hapi_eskf/eskf_settings.def"
#undef HAPI_FIELD
}

// Sets the field called `name` from its text form (tool command lines,
// "ransac_iterations=0"). Empty on success, else why not (unknown name,
// unparsable value); the range is checked by validate(), not here.
std::string setFieldFromText(EskfSettings* s, const std::string& name, const std::string& value);

const char* toString(BackendAlgorithm a);
const char* toString(BackendKind b);
const char* toString(Precision p);
const char* toString(MotionModelKind m);
// Parses "cpu"/"cuda" and "fp64"/"fp32"; false on anything else.
bool parseBackendKind(const std::string& s, BackendKind* out);
bool parsePrecision(const std::string& s, Precision* out);

}  // namespace hapi_eskf
