// Entry points of the CUDA backend (src/covariance/cuda). Declared here so the ROS-free
// factory can call them when HAPI_ESKF_WITH_CUDA is defined; the header itself
// has no CUDA dependency.
#pragma once

#include "hapi_eskf/covariance/covariance_backend.hpp"

namespace hapi_eskf {
namespace cuda {

// The largest pose block the device's prediction kernel unrolls (P x P
// threads of one block, at most 1024): the inertial model with both
// calibrations and the frame error, or with the scene motion states; the
// scene motion with the extrinsic and the frame error (37 rows) is not
// supported on the device.
constexpr int kMaxCudaPoseDim = 31;

// A backend for `capacity` landmarks and a pose block of pose_dim rows (12
// or 18, types.hpp) with the device-side settings of `s`:
// precision, cuda_device, cuda_rank_update, cuda_solve, cuda_stage_times
// (the pool size is separate so that tests and the benchmark can size a pool
// without a complete filter configuration; makeBackend passes max_landmarks).
// nullptr and *error on failure (no device, out of memory ...).
std::unique_ptr<CovarianceBackend> makeCudaBackend(int capacity, int descriptor_length, int pose_dim,
                                                   const EskfSettings& s, std::string* error);
// The partitioned update on the device (docs/DESIGN.md "Partitioned update"):
// same results as the dense backend, per-update work in the active part, the
// rest of C deferred to a flush; max_active = s.partition_max_active. FP64
// only (s.precision must be fp64). nullptr and *error on failure.
std::unique_ptr<CovarianceBackend> makePartitionedCudaBackend(int capacity, int descriptor_length, int pose_dim,
                                                              const EskfSettings& s, std::string* error);
// Device usable? "CUDA device N: name + memory" in *info, else
// "CUDA device N ...: why not".
bool deviceAvailable(int device, std::string* info);
// Device memory that a backend allocates when it is created [bytes]: C, the
// update workspace, the descriptor pools. Frames add buffers sized by their
// measurements, small next to C.
std::size_t upFrontBytes(int capacity, int descriptor_length, int pose_dim, Precision precision);
// True when upFrontBytes fits in the free memory of device s.cuda_device;
// else false and *why "... needs X MiB, CUDA device N has Y MiB free of Z MiB".
bool poolFits(int capacity, int descriptor_length, int pose_dim, const EskfSettings& s, std::string* why);

}  // namespace cuda
}  // namespace hapi_eskf
