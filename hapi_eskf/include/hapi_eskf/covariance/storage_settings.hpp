// Where and how the ES-EKF keeps its covariance, one part of the settings
// (settings.hpp composes them): the storages (covariance/) and the
// storage factory read it. Declared once in storage_settings.def.
#pragma once

#include "hapi_eskf/field_table.hpp"

#include <string>
#include <type_traits>

namespace hapi_eskf {

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

inline const char* toString(BackendKind b) { return enumToString(b); }
inline const char* toString(Precision p) { return enumToString(p); }
// Parse "cpu"/"cuda" and "fp64"/"fp32"; false on anything else.
inline bool parseBackendKind(const std::string& s, BackendKind* out) { return enumFromString(s, out); }
inline bool parsePrecision(const std::string& s, Precision* out) { return enumFromString(s, out); }

struct StorageSettings {
#define HAPI_FIELD(type, name, default_value, range, unit, doc) type name = default_value;
#include "hapi_eskf/covariance/storage_settings.def"
#undef HAPI_FIELD
};

HAPI_SETTINGS_VISITOR(StorageSettings) {
#define HAPI_FIELD(type, name, default_value, range, unit, doc) visit(FieldInfo{#name, range, unit, doc}, s.name);
#include "hapi_eskf/covariance/storage_settings.def"
#undef HAPI_FIELD
}

}  // namespace hapi_eskf
