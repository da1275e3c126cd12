// The part of the filter whose cost grows with the pool: the dense error-state
// covariance C (n x n, n = 12 + 3K) and the landmark descriptors. Two
// implementations: Eigen on the CPU (reference, CI) and CUDA (C resident on the
// GPU, cuBLAS/cuSOLVER + own kernels). The nominal state and all O(1)-per-
// landmark algebra (Jacobians, innovations, injection) stay in Eskf on the host.
//
// Storage contract shared by both backends (and relied on by the tests):
//  * landmarks occupy contiguous slots 0..K-1; slot k owns rows/columns
//    landmarkRow(k) .. +2; capacity is fixed at construction (max_landmarks);
//    a removal refills its holes from the tail (removal_plan.hpp);
//  * the LOWER triangle of C is authoritative (SYRK writes one triangle);
//    denseCovariance() returns the symmetrised matrix;
//  * every call completes before it returns (timings taken around a call are
//    honest, also on the GPU), and a call that returns anything but kOk has
//    left C and the descriptors unchanged.
#pragma once

#include "hapi_eskf/settings.hpp"
#include "hapi_eskf/status.hpp"
#include "hapi_eskf/types.hpp"

#include <Eigen/Core>

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace hapi_eskf {

// One 3-row block of the measurement Jacobian H (DESIGN.md "Update"): it has
// non-zeros only in the 6 pose columns [dp, dtheta] and the 3 columns of `slot`.
struct MeasurementBlock {
  int slot = -1;
  Mat36 H_pose = Mat36::Zero();    // d h / d[dp, dtheta]
  Mat3 H_landmark = Mat3::Zero();  // d h / d dm_slot
  Mat3 R = Mat3::Identity();       // measurement noise covariance C_v
  Vec3 innovation = Vec3::Zero();  // z - h(x_hat)
};

// A landmark initialised from one measurement: m = p + R(q) z, so
// dm = G_pose [dp, dtheta] + G_z dz (DESIGN.md "New landmark").
struct NewLandmarkBlock {
  Mat36 G_pose = Mat36::Zero();
  Mat3 G_z = Mat3::Identity();
  Mat3 Cz = Mat3::Identity();
  const uint8_t* descriptor = nullptr;  // descriptor_length bytes, copied by the backend
};

// Best and second-best pool landmark for one query descriptor.
struct DescriptorMatch {
  int best_slot = -1, best_distance = 1 << 30;
  int second_slot = -1, second_distance = 1 << 30;
};

class CovarianceBackend {
 public:
  virtual ~CovarianceBackend() = default;
  virtual const char* name() const = 0;

  virtual int capacity() const = 0;        // max landmarks
  virtual int numLandmarks() const = 0;    // K
  virtual int descriptorLength() const = 0;  // bytes; fixed at construction
  virtual std::size_t memoryBytes() const = 0;  // C + work buffers + descriptors

  // K := 0 and C := C_pose (12 x 12, symmetric PD).
  virtual Status reset(const Mat12& C_pose) = 0;

  // C_pp <- F C_pp F^T + Q, C_pm <- F C_pm (pose rows/columns only, O(K)).
  virtual Status predict(const Mat12& F, const Mat12& Q) = 0;

  // Marginal covariance of [dp, dtheta, dm_slot] (9 x 9) for each slot: the
  // host builds S_j = H_j M_j H_j^T + R_j from it for Mahalanobis gating.
  virtual Status marginals(const std::vector<int>& slots, std::vector<Mat9>* out) const = 0;

  // Joint update with all blocks (DESIGN.md steps 1-4): P = C H^T by gather,
  // S = H P + R, Cholesky S = L L^T, A = P L^-T, y = L^-1 innovation,
  // dx = A y (returned, length stateDim(K)), C <- C - A A^T.
  // Distinct slots required. On a non-PD S: kNotPositiveDefinite, C unchanged.
  // nis (optional) receives innovation^T S^-1 innovation = |y|^2.
  virtual Status update(const std::vector<MeasurementBlock>& blocks, Eigen::VectorXd* dx,
                        double* nis = nullptr) = 0;

  // Appends landmarks at slots K..K+m-1 with their full cross-covariance:
  // C_new,x = G_pose C_[dp dtheta],x ; C_new,new = G_pose C_pp G_pose^T + G_z Cz G_z^T
  // (and G_i C_pp G_j^T between two new landmarks). O(n) per landmark.
  virtual Status addLandmarks(const std::vector<NewLandmarkBlock>& blocks) = 0;

  // Removes the given slots (distinct, valid, any order). Slots stay dense:
  // the kept landmarks at slots >= K - r fill the removed slots below K - r
  // (removal_plan.hpp, "fill holes from the tail"); every other landmark keeps
  // its slot and its rows/columns of C bit for bit. O(n) per moved landmark.
  virtual Status removeLandmarks(const std::vector<int>& slots) = 0;

  // Hamming matching of query descriptors (n_query * descriptorLength() bytes)
  // against every pool descriptor.
  virtual Status matchDescriptors(const uint8_t* queries, int n_query, std::vector<DescriptorMatch>* out) const = 0;

  // Read-back for tests, the map and diagnostics (not used in the filter loop).
  virtual Mat12 poseCovariance() const = 0;
  virtual std::vector<Mat3> landmarkCovariances() const = 0;  // K marginal 3x3 blocks
  virtual Eigen::MatrixXd denseCovariance() const = 0;        // symmetrised n x n
  virtual std::vector<uint8_t> descriptors() const = 0;      // K * descriptorLength()
};

// Eigen reference backend. Always available.
std::unique_ptr<CovarianceBackend> makeCpuBackend(int capacity, int descriptor_length);

// The backend named in settings; nullptr (and *error set) when it cannot be
// created, e.g. CUDA not compiled in or no device.
std::unique_ptr<CovarianceBackend> makeBackend(const EskfSettings& s, int descriptor_length, std::string* error);

// True when the CUDA backend is compiled in and a device is usable; *why says why not.
bool cudaBackendAvailable(std::string* why);

}  // namespace hapi_eskf
