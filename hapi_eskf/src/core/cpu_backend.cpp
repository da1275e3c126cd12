// Eigen reference backend (docs/DESIGN.md "CPU reference backend", "Update", "New landmark", "Removal").
// Storage: one capacity-sized column-major buffer (N = P + 3*capacity square);
// the live state is its top-left n x n corner, landmarks in contiguous slots,
// and only the LOWER triangle of that corner is authoritative (the SYRK-style
// rank update writes just that triangle). The inputs arrive checked
// (CovarianceBackend's public methods, src/core/covariance_backend.cpp); the
// failures found while computing are returned before C is touched, so an
// error return leaves the state bit-for-bit unchanged.
#include "hapi_eskf/covariance_backend.hpp"
#include "hapi_eskf/descriptor_pool.hpp"
#include "hapi_eskf/jacobians.hpp"
#include "hapi_eskf/removal_plan.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace hapi_eskf {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

class CpuBackend final : public CovarianceBackend {
 public:
  CpuBackend(int capacity, int descriptor_length, int pose_dim)
      : CovarianceBackend(pose_dim),
        capacity_(capacity),
        desc_len_(descriptor_length),
        N_(stateDim(capacity, pose_dim)),
        C_(MatrixXd::Zero(N_, N_)),
        desc_(static_cast<std::size_t>(capacity) * descriptor_length, 0) {}

  const char* name() const override { return "cpu"; }
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
    const int n = dim();
    const int L = static_cast<int>(blocks.size());
    const int m = 3 * L;

    // 1. P = C H^T by gathering: the 6 pose columns once, then 3 landmark
    //    columns per measurement (full columns rebuilt from the lower triangle).
    const MatrixXd Cx6 = gatherColumns(0, 6, n);  // n x 6
    MatrixXd P(n, m);
    MatrixXd G3(n, 3);
    for (int j = 0; j < L; ++j) {
      const auto& b = blocks[j];
      gatherColumnsInto(row(b.slot), 3, n, &G3);
      P.middleCols<3>(3 * j).noalias() = Cx6 * b.H_pose.transpose();
      P.middleCols<3>(3 * j).noalias() += G3 * b.H_landmark.transpose();
    }
    // 2. S = H P + R (only the rows of P that H touches), symmetrised.
    MatrixXd S(m, m);
    VectorXd z(m);
    for (int i = 0; i < L; ++i) {
      const auto& b = blocks[i];
      const int r = row(b.slot);
      S.middleRows<3>(3 * i).noalias() = b.H_pose * P.topRows<6>();
      S.middleRows<3>(3 * i).noalias() += b.H_landmark * P.middleRows<3>(r);
      z.segment<3>(3 * i) = b.innovation;
    }
    for (int i = 0; i < L; ++i) S.block<3, 3>(3 * i, 3 * i) += blocks[i].R;
    S = (0.5 * (S + S.transpose())).eval();
    if (!S.allFinite()) return Status::kNonFinite;
    Eigen::LLT<MatrixXd> llt(S);
    if (llt.info() != Eigen::Success) return Status::kNotPositiveDefinite;
    {
      // Eigen's LLT only fails on a non-positive pivot; also refuse a
      // numerically singular factor, which would blow up the gain.
      const VectorXd d = llt.matrixLLT().diagonal();
      if (!(d.minCoeff() > 1e-12 * std::sqrt(std::max(1e-300, S.diagonal().maxCoeff()))))
        return Status::kNotPositiveDefinite;
    }
    // 3. A = P L^-T (triangular solve from the right), y = L^-1 z, dx = A y.
    llt.matrixU().solveInPlace<Eigen::OnTheRight>(P);
    const VectorXd y = llt.matrixL().solve(z);
    VectorXd dxn = P * y;
    if (!dxn.allFinite()) return Status::kNonFinite;
    // 4. C <- C - A A^T on the lower triangle only (SYRK).
    C_.topLeftCorner(n, n).selfadjointView<Eigen::Lower>().rankUpdate(P, -1.0);
    *dx = std::move(dxn);
    if (nis) *nis = y.squaredNorm();
    return Status::kOk;
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

  // Fill holes from the tail (removal_plan.hpp): each moved landmark's 3 rows
  // and columns are copied into its new slot, nothing else moves. Every source
  // element has an index >= n_new (the movers sit in slots >= K - r) and every
  // destination both indices < n_new, so the copies cannot overwrite a source.
  Status doRemoveLandmarks(const std::vector<int>& slots) override {
    const int K_new = K_ - static_cast<int>(slots.size());
    const int P = poseDim(), n_new = stateDim(K_new, P);
    const std::vector<SlotMove> moves = tailFillMoves(K_, slots);
    const std::vector<int> old_slot = oldSlotOfNew(K_new, moves);
    auto oldIndex = [&](int j) {
      return j < P ? j : row(old_slot[(j - P) / 3]) + (j - P) % 3;
    };
    auto at = [&](int i, int j) -> double& { return i >= j ? C_(i, j) : C_(j, i); };  // lower triangle
    for (const SlotMove& mv : moves) {
      for (int r = 0; r < 3; ++r) {
        const int dst = row(mv.to) + r, src = row(mv.from) + r;
        for (int j = 0; j < n_new; ++j) at(dst, j) = at(src, oldIndex(j));
      }
      if (desc_len_ > 0)
        std::memcpy(&desc_[static_cast<std::size_t>(mv.to) * desc_len_],
                    &desc_[static_cast<std::size_t>(mv.from) * desc_len_], desc_len_);
    }
    K_ = K_new;
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

  // Full columns c0..c0+w-1 of the symmetric C (rows 0..n-1) from its lower
  // triangle: entries above the diagonal come from row c (strided), those on
  // and below from column c (contiguous). O(n w).
  void gatherColumnsInto(int c0, int w, int n, MatrixXd* G) const {
    for (int t = 0; t < w; ++t) {
      const int c = c0 + t;
      auto g = G->col(t);
      g.head(c) = C_.row(c).head(c).transpose();
      g.tail(n - c) = C_.col(c).segment(c, n - c);
    }
  }

  int capacity_;
  int desc_len_;
  int N_;
  int K_ = 0;
  MatrixXd C_;
  std::vector<uint8_t> desc_;
};

}  // namespace

std::unique_ptr<CovarianceBackend> makeCpuBackend(int capacity, int descriptor_length, int pose_dim) {
  if (capacity < 0 || descriptor_length < 0 || pose_dim < 6 || pose_dim > kMaxPoseDim) return nullptr;
  return std::make_unique<CpuBackend>(capacity, descriptor_length, pose_dim);
}

}  // namespace hapi_eskf
