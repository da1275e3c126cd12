// Dense CPU backend (docs/DESIGN.md "CPU backend", "Update", "New landmark", "Removal"): the
// large products and factorisations on OpenBLAS/LAPACK or Eigen (cpu_linear_algebra.hpp,
// setting cpu_linear_algebra), the small blocks in Eigen. Storage: one capacity-sized column-major buffer (N = P + 3*capacity square);
// the live state is its top-left n x n corner, landmarks in contiguous slots,
// and only the LOWER triangle of that corner is authoritative (the SYRK-style
// rank update writes just that triangle). The inputs arrive checked
// (CovarianceBackend's public methods, src/covariance/covariance_backend.cpp); the
// failures found while computing are returned before C is touched, so an
// error return leaves the state bit-for-bit unchanged.
#include "cpu_linear_algebra.hpp"
#include "cpu_update_steps.hpp"
#include "lower_triangle.hpp"
#include "hapi_eskf/backend/descriptor_pool.hpp"
#include "hapi_eskf/backend/pose_kinematics.hpp"
#include "hapi_eskf/backend/removal_plan.hpp"
#include "hapi_eskf/covariance/covariance_backend.hpp"

#include <algorithm>
#include <cstring>

namespace hapi_eskf {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

class CpuBackend final : public CovarianceBackend {
 public:
  CpuBackend(int capacity, int descriptor_length, int pose_dim, CpuLinearAlgebra la)
      : CovarianceBackend(pose_dim),
        la_(cpu_la::effective(la)),
        capacity_(capacity),
        desc_len_(descriptor_length),
        N_(stateDim(capacity, pose_dim)),
        C_(MatrixXd::Zero(N_, N_)),
        desc_(static_cast<std::size_t>(capacity) * descriptor_length, 0) {}

  const char* name() const override { return la_ == CpuLinearAlgebra::kBlas ? "cpu-blas" : "cpu-eigen"; }
  int capacity() const override { return capacity_; }
  int numLandmarks() const override { return K_; }
  int descriptorLength() const override { return desc_len_; }
  std::size_t memoryBytes() const override {
    return sizeof(double) * static_cast<std::size_t>(N_) * N_ + desc_.size();
  }

  PoseMat poseCovariance() const override { return symPose(); }

  std::vector<Mat3> landmarkCovariances() const override {
    std::vector<Mat3> out(K_);
    for (int k = 0; k < K_; ++k) out[k] = symBlock3(row(k));
    return out;
  }

  MatrixXd denseCovariance() const override {
    const int n = dim();
    MatrixXd D = C_.topLeftCorner(n, n).triangularView<Eigen::Lower>();
    D.triangularView<Eigen::StrictlyUpper>() = D.transpose().triangularView<Eigen::StrictlyUpper>();
    return D;
  }

  std::vector<uint8_t> descriptors() const override {
    return std::vector<uint8_t>(desc_.begin(), desc_.begin() + static_cast<std::size_t>(K_) * desc_len_);
  }

 protected:
  Status doReset(const PoseMat& C_pose) override {
    K_ = 0;
    C_.topLeftCorner(poseDim(), poseDim()) = C_pose;
    return Status::kOk;
  }

  Status doPredict(const PoseMat& F, const PoseMat& Q) override {
    const int n = dim(), P = poseDim();
    C_.topLeftCorner(P, P) = predictPoseCovariance(symPose(), F, Q);
    if (n > P) {
      // C_mp (stored in the lower triangle, rows P..n) <- C_mp F^T: O(K).
      auto Cmp = C_.block(P, 0, n - P, P);
      const MatrixXd tmp = Cmp * F.transpose();
      Cmp = tmp;
    }
    return Status::kOk;
  }

  Status doMarginals(const std::vector<int>& slots, std::vector<Mat9>* out) const override {
    const PoseMat Cpp = symPose();
    for (std::size_t i = 0; i < slots.size(); ++i) {
      const int r = row(slots[i]);
      Mat9& M = (*out)[i];
      M.topLeftCorner<6, 6>() = Cpp.topLeftCorner<6, 6>();
      M.block<3, 6>(6, 0) = C_.block<3, 6>(r, 0);
      M.block<6, 3>(0, 6) = C_.block<3, 6>(r, 0).transpose();
      M.block<3, 3>(6, 6) = symBlock3(r);
    }
    return Status::kOk;
  }

  Status doUpdate(const std::vector<MeasurementBlock>& blocks, VectorXd* dx, double* nis) override {
    return cpu_update::denseUpdateLower(la_, &C_, dim(), poseDim(), blocks, dx, nis);
  }

  Status doAddLandmarks(const std::vector<NewLandmarkBlock>& blocks) override {
    const int n = dim();
    // Rows [dp, dtheta] of the old state, as columns (n x 6), from before the addition.
    const MatrixXd Cx6 = gatherColumns(0, 6, n);
    const Eigen::Matrix<double, 6, 6> Cpp6 = Cx6.topRows<6>();
    const int M = static_cast<int>(blocks.size());
    for (int i = 0; i < M; ++i) {
      const auto& b = blocks[i];
      const int r = n + 3 * i;
      // Cross-covariance with the whole old state (lower triangle: row r > every old column).
      C_.block(r, 0, 3, n).noalias() = b.G_pose * Cx6.transpose();
      // With the landmarks added earlier in this call: G_i C_pp G_j^T.
      for (int j = 0; j < i; ++j)
        C_.block<3, 3>(r, n + 3 * j).noalias() = b.G_pose * Cpp6 * blocks[j].G_pose.transpose();
      Mat3 Cmm = b.G_pose * Cpp6 * b.G_pose.transpose() + b.G_z * b.Cz * b.G_z.transpose();
      C_.block<3, 3>(r, r) = 0.5 * (Cmm + Cmm.transpose());
      if (desc_len_ > 0)
        std::memcpy(&desc_[static_cast<std::size_t>(K_ + i) * desc_len_], b.descriptor, desc_len_);
    }
    K_ += M;
    return Status::kOk;
  }

  // Fill holes from the tail (lower_triangle.hpp, removal_plan.hpp); nothing else moves.
  Status doRemoveLandmarks(const std::vector<int>& slots) override {
    const std::vector<SlotMove> moves = lower_triangle::fillHolesFromTail(&C_, K_, slots, poseDim());
    if (desc_len_ > 0)
      for (const SlotMove& mv : moves)
        std::memcpy(&desc_[static_cast<std::size_t>(mv.to) * desc_len_],
                    &desc_[static_cast<std::size_t>(mv.from) * desc_len_], desc_len_);
    K_ -= static_cast<int>(slots.size());
    return Status::kOk;
  }

  Status doMatchDescriptors(const uint8_t* queries, int n_query, std::vector<DescriptorMatch>* out) const override {
    matchHamming(queries, n_query, desc_.data(), K_, desc_len_, out);
    return Status::kOk;
  }

 private:
  int dim() const { return stateDim(K_, poseDim()); }
  int row(int slot) const { return landmarkRow(slot, poseDim()); }

  PoseMat symPose() const {
    PoseMat P = C_.topLeftCorner(poseDim(), poseDim()).triangularView<Eigen::Lower>();
    P.triangularView<Eigen::StrictlyUpper>() = P.transpose().triangularView<Eigen::StrictlyUpper>();
    return P;
  }

  Mat3 symBlock3(int r) const {
    Mat3 B = C_.block<3, 3>(r, r).triangularView<Eigen::Lower>();
    B.triangularView<Eigen::StrictlyUpper>() = B.transpose().triangularView<Eigen::StrictlyUpper>();
    return B;
  }

  MatrixXd gatherColumns(int c0, int w, int n) const {
    MatrixXd G(n, w);
    gatherColumnsInto(c0, w, n, &G);
    return G;
  }

  void gatherColumnsInto(int c0, int w, int n, MatrixXd* G) const {
    lower_triangle::gatherColumns(C_, c0, w, n, *G);
  }

  CpuLinearAlgebra la_;
  int capacity_;
  int desc_len_;
  int N_;
  int K_ = 0;
  MatrixXd C_;
  std::vector<uint8_t> desc_;
};

}  // namespace

std::unique_ptr<CovarianceBackend> makeCpuBackend(int capacity, int descriptor_length, int pose_dim,
                                                  CpuLinearAlgebra la) {
  if (capacity < 0 || descriptor_length < 0 || pose_dim < 6 || pose_dim > kMaxPoseDim) return nullptr;
  return std::make_unique<CpuBackend>(capacity, descriptor_length, pose_dim, la);
}

}  // namespace hapi_eskf
