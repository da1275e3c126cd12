// The part of the filter whose cost grows with the pool: the dense error-state
// covariance C (n x n, n = P + 3K, P the motion model's pose block) and the landmark descriptors. Two
// implementations: the CPU (OpenBLAS or Eigen; dense or partitioned update,
// docs/DESIGN.md "Partitioned update"; the reference, CI) and CUDA (C resident on the
// GPU, cuBLAS/cuSOLVER + own kernels; dense, or partitioned in FP64). The nominal state and all O(1)-per-
// landmark algebra (Jacobians, innovations, injection) stay in Eskf on the host.
//
// Storage contract shared by both backends (and relied on by the tests):
//  * the pose block has poseDim() rows (fixed at construction: 12 for the
//    camera-state motion models, 18 for the inertial one, types.hpp); its
//    first 6 are [dp, dtheta], the columns a measurement or a new landmark
//    touches;
//  * landmarks occupy contiguous slots 0..K-1; slot k owns rows/columns
//    landmarkRow(k, poseDim()) .. +2; capacity is fixed at construction (max_landmarks);
//    a removal refills its holes from the tail (removal_plan.hpp);
//  * the LOWER triangle of C is authoritative (SYRK writes one triangle);
//    denseCovariance() returns the symmetrised matrix;
//  * every call completes before it returns (timings taken around a call are
//    honest, also on the GPU), and a call that returns anything but kOk has
//    left C and the descriptors unchanged. The one exception is work a
//    backend defers on purpose past frameCompleted() (a partitioned
//    backend's background flush shares): it changes where C is stored, not
//    the covariance any call reads, and every later call that reads the
//    stored C waits for it first.
//
// Input checks: the public methods are non-virtual. Each validates its inputs
// (src/covariance/covariance_backend.cpp, the Status for each fault documented
// below, checked in the order listed), answers the trivial cases (nothing to
// add, remove or match) itself, and only then calls the implementation's
// protected do*() method. So both backends reject the same inputs with the
// same Status before either touches its storage, and an implementation may
// assume valid, non-trivial input. Failures found during the computation (S
// not positive definite, a non-finite result, a device error) are the
// implementation's to report.
#pragma once

#include "hapi_eskf/backend/association_source.hpp"
#include "hapi_eskf/settings.hpp"
#include "hapi_eskf/status.hpp"
#include "hapi_eskf/types.hpp"

#include <Eigen/Core>

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace hapi_eskf {

// One 3-row block of the measurement Jacobian H (docs/DESIGN.md "Update"): it has
// non-zeros only in the 6 pose columns [dp, dtheta] and the 3 columns of `slot`.
struct MeasurementBlock {
  int slot = -1;
  Mat36 H_pose = Mat36::Zero();    // d h / d[dp, dtheta]
  Mat3 H_landmark = Mat3::Zero();  // d h / d dm_slot
  Mat3 R = Mat3::Identity();       // measurement noise covariance C_v
  Vec3 innovation = Vec3::Zero();  // z - h(x_hat)
};

// A landmark initialised from one measurement: m = p + R(q) z, so
// dm = G_pose [dp, dtheta] + G_z dz (docs/DESIGN.md "New landmark").
struct NewLandmarkBlock {
  Mat36 G_pose = Mat36::Zero();
  Mat3 G_z = Mat3::Identity();
  Mat3 Cz = Mat3::Identity();
  const uint8_t* descriptor = nullptr;  // descriptor_length bytes, copied by the backend
};

// The association reads descriptors and marginals through AssociationSource.
class CovarianceBackend : public AssociationSource {
 public:
  virtual ~CovarianceBackend() = default;
  virtual const char* name() const = 0;

  int poseDim() const { return pose_dim_; }  // P, rows of the pose block
  virtual int capacity() const = 0;        // max landmarks
  int numLandmarks() const override = 0;    // K
  virtual int descriptorLength() const = 0;  // bytes; fixed at construction
  virtual std::size_t memoryBytes() const = 0;  // C + work buffers + descriptors
  // The device call behind the last Status::kBackendError ("" when none or
  // the backend has no device).
  virtual std::string lastError() const { return {}; }

  // K := 0 and C := C_pose (P x P). kInvalidArgument (not P x P),
  // kNonFinite, kInvalidArgument (not symmetric), kNotPositiveDefinite
  // (covariance_checks.hpp).
  Status reset(const PoseMat& C_pose);

  // C_pp <- F C_pp F^T + Q, C_pm <- F C_pm (pose rows/columns only, O(K)).
  // kInvalidArgument (F or Q not P x P), kNonFinite for a non-finite F or Q.
  Status predict(const PoseMat& F, const PoseMat& Q);

  // Marginal covariance of [dp, dtheta, dm_slot] (9 x 9) for each slot (a
  // slot may repeat): the host builds S_j = H_j M_j H_j^T + R_j from it for
  // Mahalanobis gating. kInvalidArgument for a null `out` or a slot outside
  // [0, K).
  Status marginals(const std::vector<int>& slots, std::vector<Mat9>* out) const final;

  // Joint update with all blocks (docs/DESIGN.md "Update" steps 1-4): P = C H^T by gather,
  // S = H P + R, Cholesky S = L L^T, A = P L^-T, y = L^-1 innovation,
  // dx = A y (returned, length stateDim(K, P)), C <- C - A A^T.
  // Input: kEmptyInput (no blocks), kInvalidArgument (null dx),
  // kCapacityExceeded (more blocks than K), then per block kInvalidArgument
  // (slot outside [0, K)), kDuplicateId (slot used twice), kNonFinite.
  // Computation: kNonFinite or kNotPositiveDefinite (S not PD or numerically
  // singular), C unchanged. nis (optional) receives
  // innovation^T S^-1 innovation = |y|^2.
  Status update(const std::vector<MeasurementBlock>& blocks, Eigen::VectorXd* dx, double* nis = nullptr);

  // Appends landmarks at slots K..K+m-1 with their full cross-covariance:
  // C_new,x = G_pose C_[dp dtheta],x ; C_new,new = G_pose C_pp G_pose^T + G_z Cz G_z^T
  // (and G_i C_pp G_j^T between two new landmarks). O(n) per landmark.
  // No blocks: kOk, nothing done. kCapacityExceeded (K + m > capacity), then
  // per block kNonFinite, kNotPositiveDefinite (Cz not a covariance),
  // kInvalidArgument (no descriptor while descriptorLength() > 0).
  Status addLandmarks(const std::vector<NewLandmarkBlock>& blocks);

  // Removes the given slots (distinct, valid, any order). Slots stay dense:
  // the kept landmarks at slots >= K - r fill the removed slots below K - r
  // (removal_plan.hpp, "fill holes from the tail"); every other landmark keeps
  // its slot and its rows/columns of C bit for bit. O(n) per moved landmark.
  // No slots: kOk, nothing done. kInvalidArgument (slot outside [0, K)),
  // kDuplicateId.
  Status removeLandmarks(const std::vector<int>& slots);

  // Hamming matching of query descriptors (n_query * descriptorLength() bytes)
  // against every pool descriptor. kInvalidArgument for a null `out`, a
  // negative n_query or null queries with n_query > 0. With nothing to
  // compare (no query, no landmark, descriptorLength() 0) every match is
  // empty (slots -1).
  Status matchDescriptors(const uint8_t* queries, int n_query, std::vector<DescriptorMatch>* out) const final;

  // The caller has made a frame's last call (Eskf::processFrame's end): work
  // the backend defers to the time between frames may start now and run
  // until a later call needs it (docs/DESIGN.md "Background shares"; the
  // partitioned backends with partition_flush_background). kOk and nothing
  // done for every other backend; kBackendError when the work could not be
  // started on the device.
  virtual Status frameCompleted() { return Status::kOk; }

  // Read-back for tests, the map and diagnostics (not used in the filter loop).
  virtual PoseMat poseCovariance() const = 0;                 // P x P
  virtual std::vector<Mat3> landmarkCovariances() const = 0;  // K marginal 3x3 blocks
  virtual Eigen::MatrixXd denseCovariance() const = 0;        // symmetrised n x n
  virtual std::vector<uint8_t> descriptors() const = 0;      // K * descriptorLength()

 protected:
  // pose_dim in [6, kMaxPoseDim]; the factories check it.
  explicit CovarianceBackend(int pose_dim) : pose_dim_(pose_dim) {}

  // The implementations, called with checked, non-trivial input only: at
  // least one block or slot, every slot in [0, K); for marginals `out` is
  // already sized, for matchDescriptors `out` holds n_query empty matches
  // and n_query, K and descriptorLength() are all > 0.
  virtual Status doReset(const PoseMat& C_pose) = 0;
  virtual Status doPredict(const PoseMat& F, const PoseMat& Q) = 0;
  virtual Status doMarginals(const std::vector<int>& slots, std::vector<Mat9>* out) const = 0;
  virtual Status doUpdate(const std::vector<MeasurementBlock>& blocks, Eigen::VectorXd* dx, double* nis) = 0;
  virtual Status doAddLandmarks(const std::vector<NewLandmarkBlock>& blocks) = 0;
  virtual Status doRemoveLandmarks(const std::vector<int>& slots) = 0;
  virtual Status doMatchDescriptors(const uint8_t* queries, int n_query, std::vector<DescriptorMatch>* out) const = 0;

 private:
  int pose_dim_;
};

// Dense CPU backend. Always available; `la` picks OpenBLAS/LAPACK or Eigen
// (setting cpu_linear_algebra; Eigen in a build without OpenBLAS, the name
// says which: cpu-blas or cpu-eigen). pose_dim is P (types.hpp); nullptr
// outside [6, kMaxPoseDim].
std::unique_ptr<CovarianceBackend> makeCpuBackend(int capacity, int descriptor_length,
                                                  int pose_dim = kCameraMotionDim,
                                                  CpuLinearAlgebra la = CpuLinearAlgebra::kBlas);
// The partitioned CPU backend (docs/DESIGN.md "Partitioned update"): exact,
// per-update work in the active landmarks, the rest of C deferred to a flush
// when more than max_active landmarks are active, its passive part applied in
// flush_shares shares over the next updates (1: at once; "Staged flush"), or
// with flush_background over the times between frames, on a worker thread
// ("Background shares"). Same contract and results as makeCpuBackend's;
// nullptr on bad sizes (max_active < 1 or flush_shares < 1 too).
std::unique_ptr<CovarianceBackend> makePartitionedCpuBackend(int capacity, int descriptor_length, int pose_dim,
                                                             CpuLinearAlgebra la, int max_active, int flush_shares,
                                                             bool flush_background = false);
// Flush accounting of the partitioned backends (CPU and CUDA), read through
// partitionedFlushStats.
class PartitionedFlushCounter {
 public:
  virtual ~PartitionedFlushCounter() = default;
  virtual int flushes() const = 0;
  virtual double flushSeconds() const = 0;
};
// Flushes done so far by a partitioned backend (CPU or CUDA) and their wall
// time [s] (for the benchmark); false for any other backend.
bool partitionedFlushStats(const CovarianceBackend& b, int* flushes, double* seconds);

}  // namespace hapi_eskf
