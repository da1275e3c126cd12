// Partitioned CPU backend (docs/DESIGN.md "Partitioned update"): the same
// results as the dense backend, with the work of an update proportional to the
// ACTIVE part of the state (the pose and the landmarks used or added since the
// last flush) and the correction of the rest of C deferred, exactly, to one
// flush (a rank-a0 product over the whole C) when the active part grows past
// max_active landmarks, before a removal of a basis landmark, and before a
// read-back of the whole map.
//
// Representation between flushes (names as in DESIGN.md): the stored C (lower
// triangle, capacity-sized as in the dense backend) holds C^0, the covariance
// at the last flush, for every entry not involving the active part; A is the
// active index set, A0 (the basis) the pose plus the landmarks that joined A
// from the passive set B since the flush. Then
//   C_AA = Caa_ (current, both triangles), C_AB = Phi C^0_{A0,B},
//   C_BB = C^0_BB - C^0_{B,A0} Psi C^0_{A0,B},
// and X_ caches C^0_{.,A0} (the basis columns of the stored C). The means are
// never deferred: every update returns the full dx (dx_B = C^0_{B,A0} W y).
//
// Staged flush (flush_shares > 1, docs/DESIGN.md "Staged flush"): a flush
// writes the active rows and leaves C_BB's correction pending (Xp_, Psip_),
// applied in row shares by the next updates (staged_flush.hpp); every read of
// the stored C in between (joins, passive marginals) subtracts what its
// entries still owe, and removals keep the debt where slot moves take it.
// Background shares (flush_background, docs/DESIGN.md "Background shares"):
// frameCompleted() starts the next share on a worker thread; it writes only
// rows of the stored C (reading Xp_ and Psip_), and every method that reads
// or changes those waits for it first (finishShare). The prediction, the
// pose block, the descriptors and their matching do not touch them and run
// beside it.
#include "cpu_linear_algebra.hpp"
#include "cpu_update_steps.hpp"
#include "lower_triangle.hpp"
#include "hapi_eskf/backend/descriptor_pool.hpp"
#include "hapi_eskf/backend/pose_kinematics.hpp"
#include "hapi_eskf/covariance/covariance_backend.hpp"
#include "hapi_eskf/covariance/partition_epoch.hpp"
#include "hapi_eskf/covariance/staged_flush.hpp"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <future>
#include <utility>

namespace hapi_eskf {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

class PartitionedCpuBackend final : public CovarianceBackend, public PartitionedFlushCounter {
 public:
  PartitionedCpuBackend(int capacity, int descriptor_length, int pose_dim, CpuLinearAlgebra la, int max_active,
                        int flush_shares, bool flush_background)
      : CovarianceBackend(pose_dim),
        la_(cpu_la::effective(la)),
        capacity_(capacity),
        desc_len_(descriptor_length),
        max_active_(max_active),
        flush_shares_(flush_shares),
        background_(flush_background),
        N_(stateDim(capacity, pose_dim)),
        C_(MatrixXd::Zero(N_, N_)),
        desc_(static_cast<std::size_t>(capacity) * descriptor_length, 0),
        active_pos_(capacity, -1),
        in_basis_(capacity, 0) {
    startEpoch();
  }
  ~PartitionedCpuBackend() override {
    if (share_.valid()) share_.wait();  // the worker writes C_
  }

  const char* name() const override {
    return la_ == CpuLinearAlgebra::kBlas ? "cpu-blas-partitioned" : "cpu-eigen-partitioned";
  }
  int capacity() const override { return capacity_; }
  int numLandmarks() const override { return K_; }
  int descriptorLength() const override { return desc_len_; }
  std::size_t memoryBytes() const override {
    return sizeof(double) * (static_cast<std::size_t>(N_) * N_ + X_.size() + Caa_.size() + Phi_.size() + Psi_.size() +
                             Xp_.size() + Psip_.size()) +
           desc_.size();
  }

  // Read-backs of the whole map flush first (the represented covariance does
  // not change, only where it is stored), so they cost one flush when anything
  // is pending; the pose block is current without one.
  PoseMat poseCovariance() const override { return Caa_.topLeftCorner(poseDim(), poseDim()); }
  std::vector<Mat3> landmarkCovariances() const override {
    finishShare();
    flush(true);
    std::vector<Mat3> out(K_);
    for (int k = 0; k < K_; ++k) out[k] = lower_triangle::symmetricBlock(C_, row(k), 3);
    return out;
  }
  MatrixXd denseCovariance() const override {
    finishShare();
    flush(true);
    return lower_triangle::symmetricBlock(C_, 0, dim());
  }
  std::vector<uint8_t> descriptors() const override {
    return std::vector<uint8_t>(desc_.begin(), desc_.begin() + static_cast<std::size_t>(K_) * desc_len_);
  }

  // Flush count and time, for the benchmark (partitionedFlushStats).
  int flushes() const override { return flushes_; }
  double flushSeconds() const override { return flush_seconds_; }
  int activeLandmarks() const { return static_cast<int>(active_.size()); }

  // The next share of a pending correction on the worker thread, unless the
  // last one still runs (a frame without a call that waited for it): that
  // one goes on, the next starts at a later frame's end.
  Status frameCompleted() override {
    if (!background_ || !pending()) return Status::kOk;
    if (share_.valid()) {
      if (share_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return Status::kOk;
      share_.get();
    }
    const std::pair<int, int> rows = takeShare();
    share_ = std::async(std::launch::async, [this, rows] { correctRows(Xp_, Psip_, rows.first, rows.second); });
    return Status::kOk;
  }

 protected:
  Status doReset(const PoseMat& C_pose) override {
    finishShare();
    K_ = 0;
    std::fill(active_pos_.begin(), active_pos_.end(), -1);
    std::fill(in_basis_.begin(), in_basis_.end(), 0);
    C_.topLeftCorner(poseDim(), poseDim()) = C_pose;
    pend_left_ = 0;
    startEpoch();
    return Status::kOk;
  }

  // Only the pose rows change: C_pp <- F C_pp F^T + Q, C_xp <- C_xp F^T for
  // the active rows, and Phi's pose rows <- F Phi (the passive C_pB).
  Status doPredict(const PoseMat& F, const PoseMat& Q) override {
    const int P = poseDim(), a = activeDim();
    const PoseMat Cpp = Caa_.topLeftCorner(P, P);
    Caa_.topLeftCorner(P, P) = predictPoseCovariance(Cpp, F, Q);
    if (a > P) {
      const MatrixXd Cxp = Caa_.block(P, 0, a - P, P) * F.transpose();
      Caa_.block(P, 0, a - P, P) = Cxp;
      Caa_.block(0, P, P, a - P) = Cxp.transpose();
    }
    const MatrixXd Phi_p = F * Phi_.topRows(P);
    Phi_.topRows(P) = Phi_p;
    return Status::kOk;
  }

  // Passive slots in one batch: with c = C^0(A0, slots) (rows of X),
  // C(pose, j) = (Phi_p c_j)^T and C_jj = C^0_jj - c_j^T Psi c_j, the
  // a0 x a0 product done once for all of them (one DGEMM).
  Status doMarginals(const std::vector<int>& slots, std::vector<Mat9>* out) const override {
    finishShare();
    std::vector<std::size_t> passive;
    for (std::size_t i = 0; i < slots.size(); ++i)
      if (active_pos_[slots[i]] < 0) passive.push_back(i);
    MatrixXd Cb(3 * passive.size(), basisDim()), CbPsi, CbPhi;
    for (std::size_t u = 0; u < passive.size(); ++u) Cb.middleRows(3 * u, 3) = X_.middleRows(row(slots[passive[u]]), 3);
    if (!passive.empty()) {
      cpu_la::gemm(la_, false, false, 1.0, Cb, Psi_, 0.0, &CbPsi);
      CbPhi = Cb * Phi_.topRows<6>().transpose();
    }
    std::size_t u = 0;
    for (std::size_t i = 0; i < slots.size(); ++i) {
      Mat9& M = (*out)[i];
      M.topLeftCorner<6, 6>() = Caa_.topLeftCorner<6, 6>();
      const int ia = active_pos_[slots[i]];
      if (ia >= 0) {
        M.block<3, 6>(6, 0) = Caa_.block<3, 6>(ia, 0);
        M.block<3, 3>(6, 6) = Caa_.block<3, 3>(ia, ia);
      } else {
        const int r = row(slots[i]);
        M.block<3, 6>(6, 0) = CbPhi.middleRows<3>(3 * u);
        const Mat3 Cjj = storedBlock(r) -
                         CbPsi.middleRows<3>(3 * u) * Cb.middleRows<3>(3 * u).transpose();
        M.block<3, 3>(6, 6) = 0.5 * (Cjj + Cjj.transpose());
        ++u;
      }
      M.block<6, 3>(0, 6) = M.block<3, 6>(6, 0).transpose();
    }
    return Status::kOk;
  }

  Status doUpdate(const std::vector<MeasurementBlock>& blocks, VectorXd* dx, double* nis) override {
    finishShare();
    const partition::EpochStep step = partition::planEpochStep(blocks, active_pos_, join_view_);
    join_view_ = false;
    if (step.new_epoch) {
      flush(true);
      const Status st = cpu_update::denseUpdateLower(la_, &C_, dim(), poseDim(), blocks, dx, nis);
      if (st != Status::kOk) return st;
      startEpoch();
      join(step.join);
      return Status::kOk;
    }
    join(step.join);

    const int n = dim(), a = activeDim(), a0 = basisDim();
    const int L = static_cast<int>(blocks.size()), m = 3 * L;
    // 1. P_A = C_AA H_A^T (a x m) from the active block only.
    MatrixXd PA(a, m);
    for (int j = 0; j < L; ++j) {
      const int ia = active_pos_[blocks[j].slot];
      PA.middleCols<3>(3 * j).noalias() = Caa_.leftCols<6>() * blocks[j].H_pose.transpose();
      PA.middleCols<3>(3 * j).noalias() += Caa_.middleCols<3>(ia) * blocks[j].H_landmark.transpose();
    }
    // 2. S = H_A P_A + R, symmetrised, factorised as in the dense backend.
    MatrixXd S(m, m);
    VectorXd z(m);
    MatrixXd V(m, a0);  // H_A Phi
    for (int i = 0; i < L; ++i) {
      const auto& b = blocks[i];
      const int ia = active_pos_[b.slot];
      S.middleRows<3>(3 * i).noalias() = b.H_pose * PA.topRows<6>();
      S.middleRows<3>(3 * i).noalias() += b.H_landmark * PA.middleRows<3>(ia);
      V.middleRows<3>(3 * i).noalias() = b.H_pose * Phi_.topRows<6>();
      V.middleRows<3>(3 * i).noalias() += b.H_landmark * Phi_.middleRows<3>(ia);
      z.segment<3>(3 * i) = b.innovation;
    }
    for (int i = 0; i < L; ++i) S.block<3, 3>(3 * i, 3 * i) += blocks[i].R;
    S = (0.5 * (S + S.transpose())).eval();
    MatrixXd Lf;
    const Status st = cpu_update::factorInnovationCovariance(la_, S, &Lf);
    if (st != Status::kOk) return st;
    // 3. A_A = P_A L^-T, W^T = L^-1 H_A Phi, y = L^-1 z; dx_A = A_A y and the
    //    passive part dx_B = C^0_{B,A0} W y (the full dx, never deferred).
    cpu_la::solveRightLowerTransposed(la_, Lf, &PA);
    cpu_la::solveLeftLower(la_, Lf, &V);
    const VectorXd y = Lf.triangularView<Eigen::Lower>().solve(z);
    VectorXd dxn = X_.topRows(n) * (V.transpose() * y);
    const VectorXd dxa = PA * y;
    for (int ia = 0; ia < a; ++ia) dxn(stateIndex(ia)) = dxa(ia);
    if (!dxn.allFinite()) return Status::kNonFinite;
    // 4. C_AA -= A_A A_A^T, Phi -= A_A W^T, Psi += W W^T.
    cpu_la::rankUpdateLower(la_, cpu_la::MatRef(Caa_.data(), a, a, Eigen::OuterStride<>(a)), PA, -1.0);
    Caa_.triangularView<Eigen::StrictlyUpper>() = Caa_.transpose();
    cpu_la::gemm(la_, false, false, -1.0, PA, V, 1.0, &Phi_);
    const MatrixXd Wt = V.transpose();  // a0 x m
    cpu_la::rankUpdateLower(la_, cpu_la::MatRef(Psi_.data(), a0, a0, Eigen::OuterStride<>(a0)), Wt, 1.0);
    Psi_.triangularView<Eigen::StrictlyUpper>() = Psi_.transpose();
    *dx = std::move(dxn);
    if (nis) *nis = y.squaredNorm();
    updated_in_epoch_ = true;
    if (!background_) advancePending();
    if (activeLandmarks() > max_active_) flush();
    return Status::kOk;
  }

  // New landmarks join the active part (not the basis): their cross-covariance
  // with the active part is G_pose C_[dp dtheta],A, with the passive part
  // G_pose Phi_[dp dtheta] C^0_{A0,B} (new rows of Phi).
  Status doAddLandmarks(const std::vector<NewLandmarkBlock>& blocks) override {
    finishShare();
    const int a = activeDim(), a0 = basisDim(), n = dim();
    const int M = static_cast<int>(blocks.size());
    const MatrixXd C6a = Caa_.topRows(6);  // 6 x a, before the addition
    const Eigen::Matrix<double, 6, 6> C66 = Caa_.topLeftCorner<6, 6>();
    const MatrixXd Phi6 = Phi_.topRows(6);
    resizeActive(a + 3 * M, a0);
    for (int i = 0; i < M; ++i) {
      const auto& b = blocks[i];
      const int r = a + 3 * i;
      Caa_.block(r, 0, 3, a).noalias() = b.G_pose * C6a;
      for (int j = 0; j < i; ++j) Caa_.block<3, 3>(r, a + 3 * j).noalias() = b.G_pose * C66 * blocks[j].G_pose.transpose();
      const Mat3 Cmm = b.G_pose * C66 * b.G_pose.transpose() + b.G_z * b.Cz * b.G_z.transpose();
      Caa_.block<3, 3>(r, r) = 0.5 * (Cmm + Cmm.transpose());
      Phi_.block(r, 0, 3, a0).noalias() = b.G_pose * Phi6;
      X_.middleRows(n + 3 * i, 3).setZero();  // no C^0 yet: never read before the next flush
      active_pos_[K_ + i] = r;
      active_.push_back(K_ + i);
      if (desc_len_ > 0)
        std::memcpy(&desc_[static_cast<std::size_t>(K_ + i) * desc_len_], b.descriptor, desc_len_);
    }
    const int a_new = a + 3 * M;
    Caa_.block(0, a, a, a_new - a) = Caa_.block(a, 0, a_new - a, a).transpose();
    Caa_.block(a, a, a_new - a, a_new - a).triangularView<Eigen::StrictlyUpper>() =
        Caa_.block(a, a, a_new - a, a_new - a).transpose();
    K_ += M;
    if (activeLandmarks() > max_active_) flush();
    return Status::kOk;
  }

  // A basis landmark's row of C^0 is part of the deferred terms: flush first.
  // Otherwise removed active landmarks leave Caa_ and Phi, removed passive ones
  // need nothing, and the stored C, X_ and the descriptors follow the shared plan.
  Status doRemoveLandmarks(const std::vector<int>& slots) override {
    finishShare();
    for (int s : slots)
      if (in_basis_[s]) {
        flush();
        break;
      }
    const partition::KeptActive kept = partition::keptAfterRemoval(slots, K_, poseDim(), active_, active_pos_);
    const std::vector<int>& keep = kept.rows;
    const std::vector<int>& kept_active = kept.landmarks;
    if (kept_active.size() != active_.size()) {
      const MatrixXd Caa = Caa_(keep, keep);
      const MatrixXd Phi = Phi_(keep, Eigen::all);
      Caa_ = Caa;
      Phi_ = Phi;
    }
    const int P = poseDim();
    const std::vector<SlotMove> moves = lower_triangle::fillHolesFromTail(&C_, K_, slots, P);
    for (const SlotMove& mv : moves) {
      X_.middleRows(row(mv.to), 3) = X_.middleRows(row(mv.from), 3);
      if (pending()) Xp_.middleRows(row(mv.to), 3) = Xp_.middleRows(row(mv.from), 3);
      if (desc_len_ > 0)
        std::memcpy(&desc_[static_cast<std::size_t>(mv.to) * desc_len_],
                    &desc_[static_cast<std::size_t>(mv.from) * desc_len_], desc_len_);
    }
    partition::renumberAfterRemoval(kept, moves, P, &in_basis_, &active_, &active_pos_, &basis_);
    const int n_old = dim();
    K_ -= static_cast<int>(slots.size());
    if (pending()) settleMovedDebt(moves, n_old);
    return Status::kOk;
  }

  Status doMatchDescriptors(const uint8_t* queries, int n_query, std::vector<DescriptorMatch>* out) const override {
    matchHamming(queries, n_query, desc_.data(), K_, desc_len_, out);
    return Status::kOk;
  }

 private:
  int dim() const { return stateDim(K_, poseDim()); }
  int row(int slot) const { return landmarkRow(slot, poseDim()); }
  int activeDim() const { return static_cast<int>(Caa_.rows()); }
  int basisDim() const { return static_cast<int>(Psi_.rows()); }
  // State index of active index ia (pose first, then 3 rows per active landmark).
  int stateIndex(int ia) const {
    const int P = poseDim();
    return ia < P ? ia : row(active_[(ia - P) / 3]) + (ia - P) % 3;
  }

  void resizeActive(int a_new, int a0_new) {
    const int a = activeDim(), a0 = basisDim();
    Caa_.conservativeResize(a_new, a_new);
    Phi_.conservativeResize(a_new, a0_new);
    Psi_.conservativeResize(a0_new, a0_new);
    if (a_new > a) {
      Caa_.bottomRows(a_new - a).setZero();
      Caa_.rightCols(a_new - a).setZero();
      Phi_.bottomRows(a_new - a).setZero();
    }
    if (a0_new > a0) {
      Phi_.rightCols(a0_new - a0).setZero();
      Psi_.bottomRows(a0_new - a0).setZero();
      Psi_.rightCols(a0_new - a0).setZero();
      X_.conservativeResize(N_, a0_new);
    }
  }

  // Passive landmarks J join the active part and the basis: with c_J = C^0_{A0,J},
  // C_AJ = Phi c_J, C_JJ = C^0_JJ - c_J^T Psi c_J, Phi's new rows [-c_J^T Psi, I],
  // new basis columns of Phi zero for the old rows, Psi zero-padded, X_ gains C^0_{.,J}.
  void join(const std::vector<int>& J) {
    if (J.empty()) return;
    const int a = activeDim(), a0 = basisDim(), n = dim(), nj = 3 * static_cast<int>(J.size());
    MatrixXd cJ(nj, a0);  // c_J^T
    std::vector<int> cols;
    for (int s : J)
      for (int r = 0; r < 3; ++r) cols.push_back(row(s) + r);
    MatrixXd G(n, nj);  // C^0_{.,J}
    for (std::size_t u = 0; u < J.size(); ++u) {
      cJ.middleRows(3 * u, 3) = X_.middleRows(row(J[u]), 3);
      lower_triangle::gatherColumns(C_, row(J[u]), 3, n, G.middleCols(3 * u, 3));
    }
    subtractPending(cols, &G);
    const MatrixXd C0JJ = G(cols, Eigen::all);
    MatrixXd cPsi, CAJ;
    cpu_la::gemm(la_, false, false, 1.0, cJ, Psi_, 0.0, &cPsi);  // nj x a0
    cpu_la::gemm(la_, false, true, 1.0, Phi_, cJ, 0.0, &CAJ);    // a x nj
    MatrixXd CJJ = C0JJ - cPsi * cJ.transpose();
    CJJ = (0.5 * (CJJ + CJJ.transpose())).eval();
    resizeActive(a + nj, a0 + nj);
    Caa_.block(0, a, a, nj) = CAJ;
    Caa_.block(a, 0, nj, a) = CAJ.transpose();
    Caa_.block(a, a, nj, nj) = CJJ;
    Phi_.block(a, 0, nj, a0) = -cPsi;
    Phi_.block(a, a0, nj, nj).setIdentity();
    X_.block(0, a0, n, nj) = G;
    for (std::size_t u = 0; u < J.size(); ++u) {
      active_pos_[J[u]] = a + 3 * static_cast<int>(u);
      active_.push_back(J[u]);
      in_basis_[J[u]] = 1;
      basis_.push_back(J[u]);
    }
  }

  // Applies the deferred correction to the stored C and starts a new epoch:
  //   C_BB <- C^0_BB - (X Psi) X^T (one rank-a0 product over the whole lower
  //   triangle; the active rows it also touches are overwritten next),
  //   row of active index i <- (Phi X^T)_i outside A, Caa_ inside A.
  // Staged (flush_shares > 1 or background shares, not `complete`): C_BB's
  // product is left pending instead (startPending). One correction is
  // pending at a time: an earlier one is finished first.
  // Logically const: the represented covariance does not change (the object
  // itself is never const, so the cast is defined; callers hold the filter's lock).
  void flush(bool complete = false) const {
    auto* self = const_cast<PartitionedCpuBackend*>(this);
    self->doFlush(complete || (flush_shares_ <= 1 && !background_));
  }
  void doFlush(bool at_once) {
    applyPendingRows(dim());
    const int a = activeDim(), P = poseDim();
    if (a == P && basisDim() == P && Psi_.isZero(0.0) && Phi_.isIdentity(0.0)) {
      startEpoch();  // pose-only epoch, nothing but the pose block to write
      return;
    }
    const auto t0 = std::chrono::steady_clock::now();
    const int n = dim();
    const MatrixXd X = X_.topRows(n);
    MatrixXd R;
    if (updated_in_epoch_) {
      if (at_once) correctRows(X_, Psi_, 0, n);
      cpu_la::gemm(la_, false, true, 1.0, Phi_, X, 0.0, &R);  // a x n
    } else {
      // No update this epoch: Psi = 0 (C_BB is C^0_BB), a joined row of Phi
      // is [0, I] (its row of C^0 outside A is current) and the pose and new
      // rows of Phi live in the pose columns only (predictions, additions).
      cpu_la::gemm(la_, false, true, 1.0, MatrixXd(Phi_.leftCols(P)), MatrixXd(X.leftCols(P)), 0.0, &R);
    }
    // Joined rows of an epoch without update are current already: outside A
    // their stored rows are C^0, their entries with the pose and the new rows
    // are written by those rows, and joined x joined blocks change only in an
    // update. They are skipped.
    std::vector<char> current(a, 0);
    if (!updated_in_epoch_)
      for (int s : basis_)
        for (int r = 0; r < 3; ++r) current[active_pos_[s] + r] = 1;
    for (int ia = 0; ia < a; ++ia)
      for (int ib = 0; ib < a; ++ib) R(ia, stateIndex(ib)) = Caa_(ia, ib);
    for (int ia = 0; ia < a; ++ia) {
      const int s = stateIndex(ia);
      if (current[ia]) continue;
      C_.row(s).head(s) = R.row(ia).head(s);
      C_.col(s).segment(s, n - s) = R.row(ia).segment(s, n - s).transpose();
    }
    if (updated_in_epoch_ && !at_once) startPending();
    ++flushes_;
    flush_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    startEpoch();
    join_view_ = !at_once;
  }

  // --- Staged flush (staged_flush.hpp) ---
  bool pending() const { return pend_left_ > 0; }

  // C_BB's correction of the epoch being flushed, pending: Xp = X with the
  // active rows (and every row past the state) zero, so that the active rows
  // just written and the landmarks added later owe nothing.
  void startPending() {
    const int n = dim();
    Xp_ = X_;
    Xp_.bottomRows(N_ - n).setZero();
    for (int ia = 0; ia < activeDim(); ++ia) Xp_.row(stateIndex(ia)).setZero();
    Psip_ = Psi_;
    pend_done_ = 0;
    pend_left_ = flush_shares_;
  }

  // lower(C) rows [r0, r1) -= (X Psi X^T) rows, as one row panel: one GEMM
  // left of the diagonal block, one triangular product on it. With r0 = 0
  // and r1 = n this is the whole flush product; the staged shares are
  // consecutive panels of it.
  void correctRows(const MatrixXd& X, const MatrixXd& Psi, int r0, int r1) {
    const int b = r1 - r0;
    if (b <= 0) return;
    const MatrixXd Xb = X.middleRows(r0, b);
    MatrixXd T, left;
    cpu_la::gemm(la_, false, false, 1.0, Xb, Psi, 0.0, &T);  // b x a0
    if (r0 > 0) {
      cpu_la::gemm(la_, false, true, 1.0, T, MatrixXd(X.topRows(r0)), 0.0, &left);
      C_.block(r0, 0, b, r0) -= left;
    }
    cpu_la::productUpdateLower(la_, cpu_la::MatRef(C_.data() + r0 + static_cast<std::size_t>(r0) * N_, b, b,
                                                   Eigen::OuterStride<>(N_)),
                               T, Xb, -1.0);
  }

  // Applies the pending correction to the rows [done, r1).
  void applyPendingRows(int r1) {
    if (!pending()) return;
    const std::pair<int, int> rows = takePendingRows(r1);
    correctRows(Xp_, Psip_, rows.first, rows.second);
  }

  // One share per update, equal in work (partition::nextStagedRow).
  void advancePending() {
    if (!pending()) return;
    const std::pair<int, int> rows = takeShare();
    correctRows(Xp_, Psip_, rows.first, rows.second);
  }

  // The rows [done, min(r1, n)) of the pending correction, counted as
  // applied (the caller applies them before anything reads them); nothing
  // is pending once done reaches n.
  std::pair<int, int> takePendingRows(int r1) {
    const int r0 = pend_done_, r = std::min(r1, dim());
    pend_done_ = std::max(r0, r);
    if (pend_done_ >= dim()) pend_left_ = 0;
    return {r0, r};
  }

  // The rows of the next share (takePendingRows).
  std::pair<int, int> takeShare() {
    const int r1 = partition::nextStagedRow(pend_done_, dim(), pend_left_);
    if (pend_left_ > 1) --pend_left_;  // the last share ends at dim()
    return takePendingRows(r1);
  }

  // Waits for a background share (rethrowing what it threw).
  void finishShare() const {
    if (share_.valid()) share_.get();
  }

  // G (n x |cols|, gathered columns `cols` of the stored C) minus what its
  // entries still owe: G(i, u) -= Xp_i Psip Xp_{cols[u]}^T where pending.
  void subtractPending(const std::vector<int>& cols, MatrixXd* G) const {
    if (!pending() || cols.empty()) return;
    const int n = static_cast<int>(G->rows());
    MatrixXd XpPsi, D;
    cpu_la::gemm(la_, false, false, 1.0, MatrixXd(Xp_(cols, Eigen::all)), Psip_, 0.0, &XpPsi);  // w x a0p
    cpu_la::gemm(la_, false, true, 1.0, MatrixXd(Xp_.topRows(n)), XpPsi, 0.0, &D);               // n x w
    for (std::size_t u = 0; u < cols.size(); ++u)
      for (int i = 0; i < n; ++i)
        if (partition::owesPending(i, cols[u], pend_done_)) (*G)(i, u) -= D(i, u);
  }

  // The 3 x 3 diagonal block at state row r of C^0 (what it still owes subtracted).
  Mat3 storedBlock(int r) const {
    const Mat3 B = lower_triangle::symmetricBlock(C_, r, 3);
    if (!pending()) return B;
    const Eigen::Matrix<double, 3, Eigen::Dynamic> x = Xp_.middleRows(r, 3);
    return partition::withoutOwed(B, x * Psip_ * x.transpose(), r, pend_done_);
  }

  // After a removal's slot moves (C_ and Xp_ rows already moved; n_old the
  // dimension before): the entries that moved before `done` pay their share
  // now (partition::rowsSettledByMoves), the rows past the new dimension are
  // cleared (landmarks added there owe nothing), and `done` is clipped.
  void settleMovedDebt(const std::vector<SlotMove>& moves, int n_old) {
    const int n = dim(), done = std::min(pend_done_, n);
    const std::vector<int> ks = partition::rowsSettledByMoves(moves, pend_done_, poseDim());
    if (!ks.empty() && done > 0) {
      MatrixXd XpPsi, D;
      cpu_la::gemm(la_, false, false, 1.0, MatrixXd(Xp_(ks, Eigen::all)), Psip_, 0.0, &XpPsi);
      cpu_la::gemm(la_, false, true, 1.0, MatrixXd(Xp_.topRows(done)), XpPsi, 0.0, &D);  // done x |ks|
      std::vector<char> settled(done, 0);
      for (int k : ks) settled[k] = 1;
      for (std::size_t u = 0; u < ks.size(); ++u) {
        const int k = ks[u];
        for (int i = 0; i < done; ++i) {
          if (settled[i] && i > k) continue;  // a pair of two settled rows: once, at the larger column
          if (i >= k) C_(i, k) -= D(i, u);
          else C_(k, i) -= D(i, u);
        }
      }
    }
    Xp_.middleRows(n, n_old - n).setZero();
    pend_done_ = done;
    if (pend_done_ >= n) pend_left_ = 0;
  }

  // Active part = the pose, basis = the pose, Phi = I, Psi = 0.
  void startEpoch() {
    const int P = poseDim(), n = dim();
    for (int s : active_) active_pos_[s] = -1;
    for (int s : basis_) in_basis_[s] = 0;
    active_.clear();
    basis_.clear();
    Caa_ = lower_triangle::symmetricBlock(C_, 0, P);
    Phi_ = MatrixXd::Identity(P, P);
    Psi_ = MatrixXd::Zero(P, P);
    X_.setZero(N_, P);
    lower_triangle::gatherColumns(C_, 0, P, n, X_.topRows(n));
    updated_in_epoch_ = false;
  }

  CpuLinearAlgebra la_;
  int capacity_;
  int desc_len_;
  int max_active_;
  int flush_shares_;
  bool background_;
  int N_;
  int K_ = 0;
  MatrixXd C_;
  std::vector<uint8_t> desc_;
  std::vector<int> active_pos_;  // per slot: first active index, -1 when passive
  std::vector<char> in_basis_;   // per slot: joined the basis this epoch
  std::vector<int> active_;      // active landmark slots, in active order
  std::vector<int> basis_;       // basis landmark slots, in basis order
  MatrixXd Caa_, Phi_, Psi_, X_;
  bool updated_in_epoch_ = false;  // a partitioned update ran since the epoch began
  // Staged flush: the pending correction (Xp_ N_ x a0p, Psip_), its progress
  // (rows [0, pend_done_) applied) and shares left (0: nothing pending);
  // join_view_: the epoch began at a staged flush and has had no update yet.
  MatrixXd Xp_, Psip_;
  int pend_done_ = 0, pend_left_ = 0;
  bool join_view_ = false;
  int flushes_ = 0;
  double flush_seconds_ = 0;
  // The background share running on the worker thread (flush_background).
  mutable std::future<void> share_;
};

}  // namespace

bool partitionedFlushStats(const CovarianceBackend& b, int* flushes, double* seconds) {
  const auto* p = dynamic_cast<const PartitionedFlushCounter*>(&b);
  if (!p) return false;
  if (flushes) *flushes = p->flushes();
  if (seconds) *seconds = p->flushSeconds();
  return true;
}

std::unique_ptr<CovarianceBackend> makePartitionedCpuBackend(int capacity, int descriptor_length, int pose_dim,
                                                             CpuLinearAlgebra la, int max_active, int flush_shares,
                                                             bool flush_background) {
  if (capacity < 0 || descriptor_length < 0 || pose_dim < 6 || pose_dim > kMaxPoseDim || max_active < 1 ||
      flush_shares < 1)
    return nullptr;
  return std::make_unique<PartitionedCpuBackend>(capacity, descriptor_length, pose_dim, la, max_active, flush_shares,
                                                 flush_background);
}

}  // namespace hapi_eskf
