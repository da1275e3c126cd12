// Partitioned CUDA backend (docs/DESIGN.md "Partitioned update", GPU variant),
// FP64: the representation, the flush triggers and the results of the
// partitioned CPU backend (partitioned_cpu_backend.cpp, whose header comment
// defines C^0, A, A0, Caa, Phi, Psi and X), with every matrix on the device.
// The stored C (C^0 between flushes) and the descriptors live in a dense CUDA
// backend (dense_cuda_backend.hpp), which also runs the dense update of a
// frame whose view jumped and the removals' hole filling; this class adds the
// active blocks Caa (a x a, lower triangle authoritative), Phi (a x a0), Psi
// (a0 x a0, lower) and the basis columns X (n x a0, leading dim that of C),
// all on the dense backend's stream and handles, so the calls are ordered
// without events. Per update the device work is O(a^2 m + a a0 m + n a0)
// (the last one the passive part of dx); the flush is O(n^2 a0) on the dense
// C, which never leaves the device. Only dx, y, the factor's checks and the
// marginals' small blocks come back to the host.
// Staged flush (partition_flush_shares > 1, docs/DESIGN.md "Staged flush"): as
// in the CPU variant, C_BB's correction stays pending (Xp_, Psip_) and is
// applied in row shares by the next updates; reads of the stored C subtract
// what their entries still owe, and removals settle the entries they move.
// Background shares (partition_flush_background, docs/DESIGN.md "Background
// shares"): frameCompleted() queues the next share on the stream and returns
// without waiting; every call that reads or changes the stored C or grows a
// buffer waits for the stream first (waitShare), and the pose block is kept
// on the host so that reading it does not wait.
#include "hapi_eskf/covariance/cuda_backend.hpp"
#include "hapi_eskf/covariance/partition_epoch.hpp"
#include "hapi_eskf/covariance/staged_flush.hpp"

#include "dense_cuda_backend.hpp"
#include "partitioned_kernels.cuh"

#include <algorithm>
#include <chrono>
#include <memory>
#include <string>
#include <vector>

namespace hapi_eskf {
namespace cuda {
namespace {

using Eigen::VectorXd;
using Dense = CudaBackend<double>;

class PartitionedCudaBackend final : public CovarianceBackend, public PartitionedFlushCounter {
 public:
  PartitionedCudaBackend(std::unique_ptr<Dense> dense, int max_active, int flush_shares, bool flush_background)
      : CovarianceBackend(dense->poseDim()),
        dense_(std::move(dense)),
        max_active_(max_active),
        flush_shares_(flush_shares),
        background_(flush_background),
        ld_(dense_->ld()),
        stream_(dense_->stream()),
        blas_(dense_->blas()),
        solver_(dense_->solver()),
        active_pos_(dense_->capacity(), -1),
        in_basis_(dense_->capacity(), 0) {}

  // The active blocks sized for max_active + 64 landmarks up front (at most
  // the pool; they grow on demand, but growing X needs the old and the new
  // buffer at once, which the largest pools cannot spare), the pose
  // indices, and an epoch on the (zero) stored C.
  bool init(std::string* why) {
    const int P = poseDim();
    const int cap = P + 3 * std::min(std::max(dense_->capacity(), 1), max_active_ + 64);
    // X takes ld doubles per basis column: at most what the device has free
    // beside a reserve of 512 MiB for the small buffers (it grows later if
    // it can).
    std::size_t free_b = 0, total_b = 0;
    if (failed(cudaMemGetInfo(&free_b, &total_b), "cudaMemGetInfo", why)) return false;
    const std::size_t reserve = std::size_t(512) << 20;
    const long long fit = free_b > reserve ? static_cast<long long>((free_b - reserve) / (ld_ * sizeof(double))) : 0;
    const int cap_b = static_cast<int>(std::max<long long>(std::min<long long>(cap, fit), P + 3));
    if (growActive(cap, cap_b, why) != Status::kOk) return false;
    std::vector<int> pose(P);
    for (int i = 0; i < P; ++i) pose[i] = i;
    if (failed(pose_idx_.ensure(P), "cudaMalloc(pose indices)", why) ||
        failed(cudaMemcpyAsync(pose_idx_.get(), pose.data(), P * sizeof(int), cudaMemcpyHostToDevice, stream_),
               "cudaMemcpyAsync(pose indices)", why))
      return false;
    if (startEpoch() != Status::kOk || readPoseBlock() != Status::kOk) {
      *why = last_error_;
      return false;
    }
    return true;
  }

  const char* name() const override { return "cuda-fp64-partitioned"; }
  int capacity() const override { return dense_->capacity(); }
  int numLandmarks() const override { return dense_->numLandmarks(); }
  int descriptorLength() const override { return dense_->descriptorLength(); }
  std::string lastError() const override { return last_error_.empty() ? dense_->lastError() : last_error_; }
  std::size_t memoryBytes() const override {
    return dense_->memoryBytes() + Caa_.bytes() + Phi_.bytes() + Psi_.bytes() + X_.bytes() + flush_.bytes() +
           Ht_.bytes() + PA_.bytes() + S_.bytes() + V_.bytes() + vec_.bytes() + small_.bytes() + H_.bytes() +
           factor_.bytes() + Xp_.bytes() + Psip_.bytes() + owed_.bytes() + owed_small_.bytes();
  }
  int flushes() const override { return flushes_; }
  double flushSeconds() const override { return flush_seconds_; }

  // The pose block: the host copy of Caa's (readPoseBlock); read-backs of
  // the map flush first (the represented covariance does not change, only
  // where it is stored).
  PoseMat poseCovariance() const override { return pose_block_; }
  std::vector<Mat3> landmarkCovariances() const override {
    if (waitShare() != Status::kOk || flush(true) != Status::kOk)
      return std::vector<Mat3>(numLandmarks(), Mat3::Constant(std::numeric_limits<double>::quiet_NaN()));
    return dense_->landmarkCovariances();
  }
  Eigen::MatrixXd denseCovariance() const override {
    if (waitShare() != Status::kOk || flush(true) != Status::kOk)
      return Eigen::MatrixXd::Constant(dim(), dim(), std::numeric_limits<double>::quiet_NaN());
    return dense_->denseCovariance();
  }
  std::vector<uint8_t> descriptors() const override { return dense_->descriptors(); }

  // The next share of a pending correction, queued on the stream; the host
  // does not wait for it.
  Status frameCompleted() override {
    if (!background_ || !pending()) return Status::kOk;
    const Status st = advancePending(false);
    share_queued_ = true;
    return st;
  }

 protected:
  Status doReset(const PoseMat& C_pose) override {
    Status st = waitShare();
    if (st != Status::kOk) return st;
    st = dense_->reset(C_pose);
    if (st != Status::kOk) return st;
    std::fill(active_pos_.begin(), active_pos_.end(), -1);
    std::fill(in_basis_.begin(), in_basis_.end(), 0);
    active_.clear();
    basis_.clear();
    pend_left_ = 0;
    join_view_ = false;
    st = startEpoch();
    return st == Status::kOk ? readPoseBlock() : st;
  }

  // Only the pose rows change: Caa's pose block and cross rows as the dense
  // backend's predict of C (launchPredict on Caa), Phi's pose rows <- F Phi.
  Status doPredict(const PoseMat& F, const PoseMat& Q) override {
    const int P = poseDim(), a = a_, a0 = a0_;
    const std::vector<double> h = rowMajorPair(F, Q);
    HAPI_CUDA_TRY(pose_mats_.ensure(h.size()));
    HAPI_CUDA_TRY(small_.ensure(static_cast<std::size_t>(P) * a0));
    HAPI_CUDA_TRY(
        cudaMemcpyAsync(pose_mats_.get(), h.data(), h.size() * sizeof(double), cudaMemcpyHostToDevice, stream_));
    HAPI_CUDA_TRY(launchPredict<double>(Caa_.get(), ca_, a, P, pose_mats_.get(), pose_mats_.get() + P * P, stream_));
    // F row-major is F^T column-major: op T gives F.
    HAPI_CUDA_TRY(Blas<double>::gemm(blas_, true, false, P, a0, P, 1.0, pose_mats_.get(), P, Phi_.get(),
                                     static_cast<int>(ca_), 0.0, small_.get(), P));
    HAPI_CUDA_TRY(cudaMemcpy2DAsync(Phi_.get(), ca_ * sizeof(double), small_.get(), P * sizeof(double),
                                    P * sizeof(double), a0, cudaMemcpyDeviceToDevice, stream_));
    touched_ = true;
    return readPoseBlock();  // synchronises
  }

  // Active slots from Caa; passive ones in one batch with c = C^0(A0, slots)
  // (rows of X): C(pose, j) = (Phi_p c_j)^T, C_jj = C^0_jj - c_j^T Psi c_j.
  Status doMarginals(const std::vector<int>& slots, std::vector<Mat9>* out) const override {
    const Status sw = waitShare();
    if (sw != Status::kOk) return sw;
    const int P = poseDim(), cnt = static_cast<int>(slots.size()), a0 = a0_;
    std::vector<int> passive, act_idx(cnt), rows;
    for (int i = 0; i < cnt; ++i) {
      const int ia = active_pos_[slots[i]];
      act_idx[i] = ia >= 0 ? (ia - P) / 3 : 0;  // launchMarginals reads rows P + 3 idx
      if (ia < 0) {
        passive.push_back(slots[i]);
        for (int r = 0; r < 3; ++r) rows.push_back(landmarkRow(slots[i], P) + r);
      }
    }
    const int np = static_cast<int>(passive.size()), m3 = 3 * np;
    // small_: 81 per slot (from Caa) | 81 per passive slot (from C) | Cb Phi_6^T (m3 x 6) | 9 per passive slot
    // | 9 per passive slot (what its diagonal block of C still owes, staged flush).
    const std::size_t o_c = 81 * static_cast<std::size_t>(cnt), o_phi = o_c + 81 * static_cast<std::size_t>(np),
                      o_d = o_phi + 6 * static_cast<std::size_t>(m3), o_p = o_d + 9 * static_cast<std::size_t>(np),
                      total = o_p + 9 * static_cast<std::size_t>(np);
    HAPI_CUDA_TRY(small_.ensure(total));
    HAPI_CUDA_TRY(idx_.ensure(cnt + np + m3));
    int* d_act = idx_.get();
    int* d_passive = d_act + cnt;
    int* d_rows = d_passive + np;
    HAPI_CUDA_TRY(cudaMemcpyAsync(d_act, act_idx.data(), cnt * sizeof(int), cudaMemcpyHostToDevice, stream_));
    HAPI_CUDA_TRY(launchMarginals<double>(Caa_.get(), ca_, P, d_act, cnt, small_.get(), stream_));
    if (np > 0) {
      HAPI_CUDA_TRY(cudaMemcpyAsync(d_passive, passive.data(), np * sizeof(int), cudaMemcpyHostToDevice, stream_));
      HAPI_CUDA_TRY(cudaMemcpyAsync(d_rows, rows.data(), m3 * sizeof(int), cudaMemcpyHostToDevice, stream_));
      HAPI_CUDA_TRY(
          launchMarginals<double>(dense_->covariance(), ld_, P, d_passive, np, small_.get() + o_c, stream_));
      HAPI_CUDA_TRY(PA_.ensure(2 * static_cast<std::size_t>(m3) * a0));
      double* Cb = PA_.get();
      double* CbPsi = Cb + static_cast<std::size_t>(m3) * a0;
      HAPI_CUDA_TRY(launchGatherRows(X_.get(), ld_, d_rows, m3, a0, Cb, m3, stream_));
      HAPI_CUDA_TRY(Blas<double>::gemm(blas_, false, true, m3, 6, a0, 1.0, Cb, m3, Phi_.get(), static_cast<int>(ca_),
                                       0.0, small_.get() + o_phi, m3));
      if (updated_in_epoch_) {  // else Psi = 0 and so is c_j^T Psi c_j
        HAPI_CUDA_TRY(Blas<double>::symmRight(blas_, m3, a0, 1.0, Psi_.get(), static_cast<int>(cb_), Cb, m3, 0.0,
                                              CbPsi, m3));
        HAPI_CUDA_TRY(Blas<double>::gemmNTBatched(blas_, 3, 3, a0, CbPsi, m3, 3, Cb, m3, 3, small_.get() + o_d, 3, 9,
                                                  np));
      } else {
        HAPI_CUDA_TRY(cudaMemsetAsync(small_.get() + o_d, 0, 9 * static_cast<std::size_t>(np) * sizeof(double),
                                      stream_));
      }
      if (pending()) {  // Xp_j Psip Xp_j^T per passive slot
        const int ap = a0p_;
        HAPI_CUDA_TRY(owed_small_.ensure(2 * static_cast<std::size_t>(m3) * ap));
        double* Xj = owed_small_.get();
        double* XjPsi = Xj + static_cast<std::size_t>(m3) * ap;
        HAPI_CUDA_TRY(launchGatherRows(Xp_.get(), ld_, d_rows, m3, ap, Xj, m3, stream_));
        HAPI_CUDA_TRY(Blas<double>::symmRight(blas_, m3, ap, 1.0, Psip_.get(), ap, Xj, m3, 0.0, XjPsi, m3));
        HAPI_CUDA_TRY(Blas<double>::gemmNTBatched(blas_, 3, 3, ap, XjPsi, m3, 3, Xj, m3, 3, small_.get() + o_p, 3, 9,
                                                  np));
      } else {
        HAPI_CUDA_TRY(cudaMemsetAsync(small_.get() + o_p, 0, 9 * static_cast<std::size_t>(np) * sizeof(double),
                                      stream_));
      }
    }
    std::vector<double> h(total);
    HAPI_CUDA_TRY(cudaMemcpyAsync(h.data(), small_.get(), total * sizeof(double), cudaMemcpyDeviceToHost, stream_));
    HAPI_CUDA_TRY(cudaStreamSynchronize(stream_));
    int u = 0;
    for (int i = 0; i < cnt; ++i) {
      Mat9& M = (*out)[i];
      std::memcpy(M.data(), h.data() + 81 * static_cast<std::size_t>(i), 81 * sizeof(double));
      if (active_pos_[slots[i]] >= 0) continue;
      Mat9 C0;
      std::memcpy(C0.data(), h.data() + o_c + 81 * static_cast<std::size_t>(u), 81 * sizeof(double));
      Mat3 D, owed;
      std::memcpy(D.data(), h.data() + o_d + 9 * static_cast<std::size_t>(u), 9 * sizeof(double));
      std::memcpy(owed.data(), h.data() + o_p + 9 * static_cast<std::size_t>(u), 9 * sizeof(double));
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 6; ++c) M(6 + r, c) = h[o_phi + 3 * u + r + static_cast<std::size_t>(c) * m3];
      const Mat3 C0jj = pending() ? partition::withoutOwed(C0.block<3, 3>(6, 6), owed, landmarkRow(passive[u], P),
                                                           pend_done_)
                                  : Mat3(C0.block<3, 3>(6, 6));
      const Mat3 Cjj = C0jj - D;
      M.block<3, 3>(6, 6) = 0.5 * (Cjj + Cjj.transpose());
      M.block<6, 3>(0, 6) = M.block<3, 6>(6, 0).transpose();
      ++u;
    }
    return Status::kOk;
  }

  Status doUpdate(const std::vector<MeasurementBlock>& blocks, VectorXd* dx, double* nis) override {
    Status st = waitShare();
    if (st != Status::kOk) return st;
    const partition::EpochStep step = partition::planEpochStep(blocks, active_pos_, join_view_);
    join_view_ = false;
    if (step.new_epoch) {
      st = flush(true);
      if (st != Status::kOk) return st;
      st = dense_->update(blocks, dx, nis);
      if (st != Status::kOk) return st;
      st = startEpoch();
      if (st == Status::kOk) st = readPoseBlock();
      if (st != Status::kOk) return st;
      return join(step.join);
    }
    st = join(step.join);
    if (st != Status::kOk) return st;

    const int n = dim(), a = a_, a0 = a0_, L = static_cast<int>(blocks.size()), m3 = 3 * L;
    std::vector<double> hH, hR, hz;
    std::vector<int> hslots, arow(L);
    packMeasurements(blocks, &hH, &hR, &hz, &hslots);
    for (int j = 0; j < L; ++j) arow[j] = active_pos_[blocks[j].slot];
    HAPI_CUDA_TRY(H_.ensure(hH.size() + hR.size()));
    HAPI_CUDA_TRY(idx_.ensure(L));
    HAPI_CUDA_TRY(Ht_.ensure(static_cast<std::size_t>(a) * m3));
    HAPI_CUDA_TRY(PA_.ensure(static_cast<std::size_t>(a) * m3));
    HAPI_CUDA_TRY(S_.ensure(static_cast<std::size_t>(m3) * m3));
    HAPI_CUDA_TRY(V_.ensure(static_cast<std::size_t>(m3) * a0));
    // vec_: y (m3) | w = V^T y (a0) | dx_A (a) | dx (n).
    HAPI_CUDA_TRY(vec_.ensure(static_cast<std::size_t>(m3) + a0 + a + n));
    double* d_H = H_.get();
    double* d_R = d_H + hH.size();
    double* y = vec_.get();
    double* w = y + m3;
    double* dxa = w + a0;
    double* dxn = dxa + a;
    double* Ht = Ht_.get();
    double* PA = PA_.get();
    double* S = S_.get();
    double* V = V_.get();
    HAPI_CUDA_TRY(cudaMemcpyAsync(d_H, hH.data(), hH.size() * sizeof(double), cudaMemcpyHostToDevice, stream_));
    HAPI_CUDA_TRY(cudaMemcpyAsync(d_R, hR.data(), hR.size() * sizeof(double), cudaMemcpyHostToDevice, stream_));
    HAPI_CUDA_TRY(cudaMemcpyAsync(idx_.get(), arow.data(), L * sizeof(int), cudaMemcpyHostToDevice, stream_));
    HAPI_CUDA_TRY(cudaMemcpyAsync(y, hz.data(), m3 * sizeof(double), cudaMemcpyHostToDevice, stream_));
    HAPI_CUDA_TRY(cudaMemsetAsync(Ht, 0, static_cast<std::size_t>(a) * m3 * sizeof(double), stream_));
    HAPI_CUDA_TRY(cudaMemsetAsync(S, 0, static_cast<std::size_t>(m3) * m3 * sizeof(double), stream_));
    HAPI_CUDA_TRY(launchScatterMeasurements(d_H, d_R, idx_.get(), L, Ht, a, S, stream_));
    // 1.-2. P_A = C_AA H_A^T, S = H_A P_A + R, V = H_A Phi; factor S.
    const int lda = static_cast<int>(ca_);
    HAPI_CUDA_TRY(Blas<double>::symmLeft(blas_, a, m3, 1.0, Caa_.get(), lda, Ht, a, 0.0, PA, a));
    HAPI_CUDA_TRY(Blas<double>::gemm(blas_, true, false, m3, m3, a, 1.0, Ht, a, PA, a, 1.0, S, m3));
    HAPI_CUDA_TRY(Blas<double>::gemm(blas_, true, false, m3, a0, a, 1.0, Ht, a, Phi_.get(), lda, 0.0, V, m3));
    st = factor_.enqueueCheck(stream_, S, m3, &last_error_);
    if (st == Status::kOk) st = factor_.enqueueFactor(solver_, stream_, S, &last_error_);
    if (st != Status::kOk) return st;
    HAPI_CUDA_TRY(cudaStreamSynchronize(stream_));
    st = factor_.verdict(&last_error_);
    if (st != Status::kOk) return st;
    // 3. A_A = P_A L^-T, W^T = L^-1 V, y = L^-1 z; dx_A = A_A y, dx_B = X W y.
    HAPI_CUDA_TRY(Blas<double>::trsmRightLowerT(blas_, a, m3, S, m3, PA, a));
    HAPI_CUDA_TRY(Blas<double>::trsmLeftLower(blas_, m3, a0, S, m3, V, m3));
    HAPI_CUDA_TRY(Blas<double>::trsvLower(blas_, m3, S, m3, y));
    HAPI_CUDA_TRY(Blas<double>::gemvT(blas_, m3, a0, V, m3, y, w));
    HAPI_CUDA_TRY(Blas<double>::gemv(blas_, n, a0, X_.get(), static_cast<int>(ld_), w, dxn));
    HAPI_CUDA_TRY(Blas<double>::gemv(blas_, a, m3, PA, a, y, dxa));
    std::vector<double> hy(m3), hdxa(a);
    VectorXd dxd(n);
    HAPI_CUDA_TRY(cudaMemcpyAsync(hy.data(), y, m3 * sizeof(double), cudaMemcpyDeviceToHost, stream_));
    HAPI_CUDA_TRY(cudaMemcpyAsync(hdxa.data(), dxa, a * sizeof(double), cudaMemcpyDeviceToHost, stream_));
    HAPI_CUDA_TRY(cudaMemcpyAsync(dxd.data(), dxn, n * sizeof(double), cudaMemcpyDeviceToHost, stream_));
    HAPI_CUDA_TRY(cudaStreamSynchronize(stream_));
    for (int ia = 0; ia < a; ++ia) dxd(stateIndex(ia)) = hdxa[ia];
    double y2 = 0;
    for (double v : hy) y2 += v * v;
    if (!std::isfinite(y2) || !dxd.allFinite()) return Status::kNonFinite;  // nothing changed yet
    // 4. C_AA -= A_A A_A^T, Phi -= A_A W^T, Psi += W W^T (lower triangles).
    HAPI_CUDA_TRY(Blas<double>::syrk(blas_, a, m3, -1.0, PA, a, 1.0, Caa_.get(), lda));
    HAPI_CUDA_TRY(Blas<double>::gemm(blas_, false, false, a, a0, m3, -1.0, PA, a, V, m3, 1.0, Phi_.get(), lda));
    HAPI_CUDA_TRY(Blas<double>::syrkT(blas_, a0, m3, 1.0, V, m3, 1.0, Psi_.get(), static_cast<int>(cb_)));
    st = readPoseBlock();  // synchronises
    if (st != Status::kOk) return st;
    *dx = std::move(dxd);
    if (nis) *nis = y2;
    updated_in_epoch_ = touched_ = true;
    if (!background_) st = advancePending(true);
    if (st != Status::kOk) return st;
    if (activeLandmarks() > max_active_) return flush();
    return Status::kOk;
  }

  // New landmarks join the active part (not the basis): Caa's new rows as the
  // dense backend adds rows to C (launchAddLandmarks on Caa), Phi's new rows
  // G_pose Phi_[dp dtheta]. The dense backend stores the descriptors and
  // counts them; the rows it writes into the stored C are never read before
  // the next flush overwrites them (they are active rows), as X's new rows.
  Status doAddLandmarks(const std::vector<NewLandmarkBlock>& blocks) override {
    const Status sw = waitShare();
    if (sw != Status::kOk) return sw;
    const int a = a_, a0 = a0_, n = dim(), M = static_cast<int>(blocks.size()), K = numLandmarks();
    std::vector<double> hG, hN;
    std::vector<uint8_t> hd;
    packNewLandmarks(blocks, descriptorLength(), &hG, &hN, &hd);
    Status st = resizeActive(a + 3 * M, a0);
    if (st != Status::kOk) return st;
    HAPI_CUDA_TRY(H_.ensure(hG.size() + hN.size()));
    double* d_G = H_.get();
    double* d_N = d_G + hG.size();
    HAPI_CUDA_TRY(cudaMemcpyAsync(d_G, hG.data(), hG.size() * sizeof(double), cudaMemcpyHostToDevice, stream_));
    HAPI_CUDA_TRY(cudaMemcpyAsync(d_N, hN.data(), hN.size() * sizeof(double), cudaMemcpyHostToDevice, stream_));
    HAPI_CUDA_TRY(launchAddLandmarks<double>(Caa_.get(), ca_, a, d_G, d_N, M, stream_));
    // The packed G (18 per block, row-major 3 x 6) is G^T column-major (6 x 3M).
    HAPI_CUDA_TRY(Blas<double>::gemm(blas_, true, false, 3 * M, a0, 6, 1.0, d_G, 6, Phi_.get(), static_cast<int>(ca_),
                                     0.0, Phi_.get() + a, static_cast<int>(ca_)));
    HAPI_CUDA_TRY(cudaMemset2DAsync(X_.get() + n, ld_ * sizeof(double), 0, 3 * M * sizeof(double), a0, stream_));
    st = dense_->addLandmarks(blocks);
    if (st != Status::kOk) return st;
    for (int i = 0; i < M; ++i) {
      active_pos_[K + i] = a + 3 * i;
      active_.push_back(K + i);
    }
    if (activeLandmarks() > max_active_) return flush();
    return Status::kOk;
  }

  // A basis landmark's row of C^0 is part of the deferred terms: flush first.
  // Removed active landmarks leave Caa and Phi; the stored C and the
  // descriptors follow the shared plan in the dense backend, X's rows here.
  Status doRemoveLandmarks(const std::vector<int>& slots) override {
    const Status sw = waitShare();
    if (sw != Status::kOk) return sw;
    for (int s : slots)
      if (in_basis_[s]) {
        const Status st = flush();
        if (st != Status::kOk) return st;
        break;
      }
    const int P = poseDim(), K = numLandmarks(), a0 = a0_;
    const partition::KeptActive kept = partition::keptAfterRemoval(slots, K, P, active_, active_pos_);
    const std::vector<int>& keep = kept.rows;
    const std::vector<int>& kept_active = kept.landmarks;
    if (kept_active.size() != active_.size()) {
      const int nk = static_cast<int>(keep.size());
      HAPI_CUDA_TRY(idx_.ensure(nk));
      HAPI_CUDA_TRY(PA_.ensure(static_cast<std::size_t>(nk) * std::max(nk, a0)));
      HAPI_CUDA_TRY(cudaMemcpyAsync(idx_.get(), keep.data(), nk * sizeof(int), cudaMemcpyHostToDevice, stream_));
      HAPI_CUDA_TRY(launchGatherSymmetric(Caa_.get(), ca_, idx_.get(), nk, idx_.get(), nk, PA_.get(), nk, stream_));
      HAPI_CUDA_TRY(cudaMemcpy2DAsync(Caa_.get(), ca_ * sizeof(double), PA_.get(), nk * sizeof(double),
                                      nk * sizeof(double), nk, cudaMemcpyDeviceToDevice, stream_));
      HAPI_CUDA_TRY(launchGatherRows(Phi_.get(), ca_, idx_.get(), nk, a0, PA_.get(), nk, stream_));
      HAPI_CUDA_TRY(cudaMemcpy2DAsync(Phi_.get(), ca_ * sizeof(double), PA_.get(), nk * sizeof(double),
                                      nk * sizeof(double), a0, cudaMemcpyDeviceToDevice, stream_));
      a_ = nk;
    }
    // X's rows follow the plan (sources >= the new dimension > destinations).
    const std::vector<SlotMove> moves = tailFillMoves(K, slots);
    for (const SlotMove& mv : moves) {
      HAPI_CUDA_TRY(cudaMemcpy2DAsync(X_.get() + landmarkRow(mv.to, P), ld_ * sizeof(double),
                                      X_.get() + landmarkRow(mv.from, P), ld_ * sizeof(double), 3 * sizeof(double),
                                      a0, cudaMemcpyDeviceToDevice, stream_));
      if (pending())
        HAPI_CUDA_TRY(cudaMemcpy2DAsync(Xp_.get() + landmarkRow(mv.to, P), ld_ * sizeof(double),
                                        Xp_.get() + landmarkRow(mv.from, P), ld_ * sizeof(double),
                                        3 * sizeof(double), a0p_, cudaMemcpyDeviceToDevice, stream_));
    }
    const int n_old = dim();
    Status st = dense_->removeLandmarks(slots);  // synchronises the shared stream
    if (st != Status::kOk) return st;
    partition::renumberAfterRemoval(kept, moves, P, &in_basis_, &active_, &active_pos_, &basis_);
    if (pending()) {
      st = settleMovedDebt(moves, n_old);
      if (st != Status::kOk) return st;
    }
    HAPI_CUDA_TRY(cudaStreamSynchronize(stream_));
    return Status::kOk;
  }

  Status doMatchDescriptors(const uint8_t* queries, int n_query, std::vector<DescriptorMatch>* out) const override {
    return dense_->matchDescriptors(queries, n_query, out);
  }

 private:
  int dim() const { return stateDim(numLandmarks(), poseDim()); }
  int activeLandmarks() const { return static_cast<int>(active_.size()); }
  // State index of active index ia (pose first, then 3 rows per active landmark).
  int stateIndex(int ia) const {
    const int P = poseDim();
    return ia < P ? ia : landmarkRow(active_[(ia - P) / 3], P) + (ia - P) % 3;
  }

  // Capacities of the active blocks (rows of Caa and Phi: ca_; columns of
  // Phi, Psi and X: cb_), grown by a quarter again, contents kept, the rest
  // zero. Only the buffers whose capacity changes are reallocated: X is n
  // rows tall, and beside the largest pools there is no room for two.
  Status growActive(int a_need, int a0_need, std::string* why) {
    const bool grow_a = a_need > static_cast<int>(ca_), grow_b = a0_need > static_cast<int>(cb_);
    if (!grow_a && !grow_b) return Status::kOk;
    const bool first = ca_ == 0;  // the first allocation is exact
    auto grown = [first](int need) { return static_cast<std::size_t>(need + (first ? 0 : need / 4)); };
    const std::size_t ca = grow_a ? grown(a_need) : ca_, cb = grow_b ? grown(a0_need) : cb_;
    const std::size_t d = sizeof(double);
    // A new zeroed rows x cols buffer (leading dim ld) holding the old
    // used_rows x used_cols block of *buf (leading dim old_ld).
    auto regrow = [&](DeviceBuffer<double>* buf, std::size_t ld, std::size_t cols, std::size_t old_ld, int used_rows,
                      int used_cols, const char* what) {
      DeviceBuffer<double> fresh;
      if (failed(fresh.ensure(ld * cols), what, why) ||
          failed(cudaMemsetAsync(fresh.get(), 0, fresh.bytes(), stream_), what, why))
        return false;
      if (used_rows > 0 && used_cols > 0 &&
          failed(cudaMemcpy2DAsync(fresh.get(), ld * d, buf->get(), old_ld * d, used_rows * d, used_cols,
                                   cudaMemcpyDeviceToDevice, stream_),
                 what, why))
        return false;
      if (failed(cudaStreamSynchronize(stream_), what, why)) return false;
      buf->swap(fresh);  // the old buffer is freed here
      return true;
    };
    if (grow_a && !regrow(&Caa_, ca, ca, ca_, a_, a_, "Caa")) return Status::kBackendError;
    if (!regrow(&Phi_, ca, cb, ca_, a_, a0_, "Phi")) return Status::kBackendError;
    if (grow_b && (!regrow(&Psi_, cb, cb, cb_, a0_, a0_, "Psi") || !regrow(&X_, ld_, cb, ld_, dim(), a0_, "X")))
      return Status::kBackendError;
    ca_ = ca;
    cb_ = cb;
    return Status::kOk;
  }

  // a_ <- a_new, a0_ <- a0_new (not smaller): the new rows and columns of
  // Caa, Phi and Psi are zero (X's new columns are written by the caller).
  Status resizeActive(int a_new, int a0_new) {
    const Status st = growActive(a_new, a0_new, &last_error_);
    if (st != Status::kOk) return st;
    const std::size_t d = sizeof(double);
    const int a = a_, a0 = a0_;
    if (a_new > a) {
      HAPI_CUDA_TRY(cudaMemset2DAsync(Caa_.get() + a, ca_ * d, 0, (a_new - a) * d, a_new, stream_));
      HAPI_CUDA_TRY(cudaMemset2DAsync(Phi_.get() + a, ca_ * d, 0, (a_new - a) * d, a0_new, stream_));
    }
    if (a0_new > a0) {
      HAPI_CUDA_TRY(cudaMemset2DAsync(Phi_.get() + a0 * ca_, ca_ * d, 0, a * d, a0_new - a0, stream_));
      HAPI_CUDA_TRY(cudaMemset2DAsync(Psi_.get() + a0, cb_ * d, 0, (a0_new - a0) * d, a0_new, stream_));
      HAPI_CUDA_TRY(cudaMemset2DAsync(Psi_.get() + a0 * cb_, cb_ * d, 0, a0 * d, a0_new - a0, stream_));
    }
    a_ = a_new;
    a0_ = a0_new;
    return Status::kOk;
  }

  // Passive landmarks J join the active part and the basis (as the CPU
  // variant): with c_J = C^0_{A0,J} (rows of X), Phi's new rows
  // [-c_J^T Psi, I], C_JA = c_J^T Phi^T, C_JJ = C^0_JJ - c_J^T Psi c_J, X gains
  // the columns C^0_{.,J} of the stored C.
  Status join(const std::vector<int>& J) {
    if (J.empty()) return Status::kOk;
    const int P = poseDim(), a = a_, a0 = a0_, n = dim(), nj = 3 * static_cast<int>(J.size());
    std::vector<int> rows;
    for (int s : J)
      for (int r = 0; r < 3; ++r) rows.push_back(landmarkRow(s, P) + r);
    HAPI_CUDA_TRY(idx_.ensure(nj));
    HAPI_CUDA_TRY(PA_.ensure(static_cast<std::size_t>(nj) * (a0 + nj)));
    double* cJ = PA_.get();                                   // nj x a0
    double* CJJ = cJ + static_cast<std::size_t>(nj) * a0;      // nj x nj
    HAPI_CUDA_TRY(cudaMemcpyAsync(idx_.get(), rows.data(), nj * sizeof(int), cudaMemcpyHostToDevice, stream_));
    HAPI_CUDA_TRY(launchGatherRows(X_.get(), ld_, idx_.get(), nj, a0, cJ, nj, stream_));
    HAPI_CUDA_TRY(launchGatherSymmetric(dense_->covariance(), ld_, idx_.get(), nj, idx_.get(), nj, CJJ, nj, stream_));
    // Staged flush: D = Xp Psip Xp_J^T (n x nj), what C^0's columns J still owe.
    const double* D = nullptr;
    if (pending()) {
      const Status so = owedColumns(idx_.get(), nj, &D);
      if (so != Status::kOk) return so;
      HAPI_CUDA_TRY(launchSubtractOwed(CJJ, nj, idx_.get(), nj, idx_.get(), nj, D, n, pend_done_, stream_));
    }
    const Status st = resizeActive(a + nj, a0 + nj);
    if (st != Status::kOk) return st;
    const int lda = static_cast<int>(ca_);
    double* phi_j = Phi_.get() + a;  // rows a.. of Phi
    if (updated_in_epoch_) {  // else Psi = 0: Phi's new rows stay zero left of I (resizeActive), C_JJ = C^0_JJ
      HAPI_CUDA_TRY(Blas<double>::symmRight(blas_, nj, a0, -1.0, Psi_.get(), static_cast<int>(cb_), cJ, nj, 0.0,
                                            phi_j, lda));
      HAPI_CUDA_TRY(Blas<double>::gemm(blas_, false, true, nj, nj, a0, 1.0, phi_j, lda, cJ, nj, 1.0, CJJ, nj));
    }
    HAPI_CUDA_TRY(Blas<double>::gemm(blas_, false, true, nj, a, a0, 1.0, cJ, nj, Phi_.get(), lda, 0.0,
                                     Caa_.get() + a, lda));
    HAPI_CUDA_TRY(cudaMemcpy2DAsync(Caa_.get() + a + static_cast<std::size_t>(a) * ca_, ca_ * sizeof(double), CJJ,
                                    nj * sizeof(double), nj * sizeof(double), nj, cudaMemcpyDeviceToDevice, stream_));
    HAPI_CUDA_TRY(launchSetDiagonalOne(phi_j + static_cast<std::size_t>(a0) * ca_, ca_, nj, stream_));
    HAPI_CUDA_TRY(launchGatherSymmetric(dense_->covariance(), ld_, nullptr, n, idx_.get(), nj,
                                        X_.get() + static_cast<std::size_t>(a0) * ld_, ld_, stream_));
    if (D != nullptr)
      HAPI_CUDA_TRY(launchSubtractOwed(X_.get() + static_cast<std::size_t>(a0) * ld_, ld_, nullptr, n, idx_.get(), nj,
                                       D, n, pend_done_, stream_));
    HAPI_CUDA_TRY(cudaStreamSynchronize(stream_));
    for (std::size_t u = 0; u < J.size(); ++u) {
      active_pos_[J[u]] = a + 3 * static_cast<int>(u);
      active_.push_back(J[u]);
      in_basis_[J[u]] = 1;
      basis_.push_back(J[u]);
    }
    return Status::kOk;
  }

  // The deferred correction, applied to the stored C on the device, then a
  // new epoch (the CPU variant's flush):
  //   C_BB <- C^0_BB - (X Psi) X^T, in row panels of the lower triangle (the
  //   panel's X Psi rows, one GEMM left of the diagonal block, one SYRKX on
  //   it; the active rows it also touches are overwritten next);
  //   row s of active index i <- (Phi X^T)_i outside A, Caa_ inside A,
  //   formed for a chunk of active rows at a time (X Phi^T columns).
  // Buffers stay O(n) wide in one dimension and bounded in the other, so the
  // largest pools keep their memory for C. Logically const, as on the CPU.
  // Staged (partition_flush_shares > 1, not `complete`): C_BB's product is
  // left pending instead (startPending), unless the device lacks the memory
  // for Xp. One correction is pending at a time: an earlier one is finished
  // first.
  Status flush(bool complete = false) const {
    return const_cast<PartitionedCudaBackend*>(this)->doFlush(complete || (flush_shares_ <= 1 && !background_));
  }
  Status doFlush(bool at_once) {
    Status st = applyPendingRows(dim());
    if (st != Status::kOk) return st;
    const int a = a_, a0 = a0_, P = poseDim();
    if (a == P && a0 == P && !touched_) return startEpoch();  // nothing deferred
    const auto t0 = std::chrono::steady_clock::now();
    const int n = dim();
    constexpr int kChunk = 128;  // active rows written back per pass
    // Room for the pending correction (Xp n x a0, Psip a0 x a0)? Else at once.
    bool stage = updated_in_epoch_ && !at_once;
    if (stage && (Xp_.ensure(ld_ * static_cast<std::size_t>(a0)) != cudaSuccess ||
                  Psip_.ensure(static_cast<std::size_t>(a0) * a0) != cudaSuccess)) {
      (void)cudaGetLastError();  // the failed allocation's error is not sticky: clear it
      stage = false;
    }
    if (updated_in_epoch_ && !stage) {
      st = correctRows(X_.get(), Psi_.get(), static_cast<int>(cb_), a0, 0, n);
      if (st != Status::kOk) return st;
    }
    double* T = scratch(static_cast<std::size_t>(n) * kChunk);  // after correctRows, which may grow the scratch
    if (T == nullptr) return Status::kBackendError;
    double* C = dense_->covariance();
    const int ldc = static_cast<int>(ld_);
    // Rows of the active landmarks: all state indices, and which are active.
    // Joined rows of an epoch without update are current already (see the
    // CPU variant) and skipped; without update Phi lives in the pose columns.
    std::vector<int> state_of_active(a), active_of_state(n, -1);
    std::vector<unsigned char> skip(a, 0);
    for (int ia = 0; ia < a; ++ia) {
      state_of_active[ia] = stateIndex(ia);
      active_of_state[state_of_active[ia]] = ia;
    }
    if (!updated_in_epoch_)
      for (int s : basis_)
        for (int r = 0; r < 3; ++r) skip[active_pos_[s] + r] = 1;
    HAPI_CUDA_TRY(idx_.ensure(static_cast<std::size_t>(a) + n + (a + 3) / 4));
    int* d_soa = idx_.get();
    int* d_aos = d_soa + a;
    unsigned char* d_skip = reinterpret_cast<unsigned char*>(d_aos + n);
    HAPI_CUDA_TRY(cudaMemcpyAsync(d_soa, state_of_active.data(), a * sizeof(int), cudaMemcpyHostToDevice, stream_));
    HAPI_CUDA_TRY(cudaMemcpyAsync(d_aos, active_of_state.data(), n * sizeof(int), cudaMemcpyHostToDevice, stream_));
    HAPI_CUDA_TRY(cudaMemcpyAsync(d_skip, skip.data(), a, cudaMemcpyHostToDevice, stream_));
    const int k = updated_in_epoch_ ? a0 : P;
    for (int c0 = 0; c0 < a; c0 += kChunk) {
      const int w = std::min(kChunk, a - c0);
      HAPI_CUDA_TRY(Blas<double>::gemm(blas_, false, true, n, w, k, 1.0, X_.get(), ldc, Phi_.get() + c0,
                                       static_cast<int>(ca_), 0.0, T, n));
      HAPI_CUDA_TRY(launchWriteActiveRows(C, ld_, n, T, c0, w, d_soa, d_aos, Caa_.get(), ca_, d_skip, stream_));
    }
    if (stage) {
      // Xp = X with the active rows (written above) and the rows past the
      // state (landmarks added later) zero: they owe nothing.
      const std::size_t d = sizeof(double);
      HAPI_CUDA_TRY(cudaMemcpy2DAsync(Xp_.get(), ld_ * d, X_.get(), ld_ * d, n * d, a0, cudaMemcpyDeviceToDevice,
                                      stream_));
      HAPI_CUDA_TRY(cudaMemset2DAsync(Xp_.get() + n, ld_ * d, 0, (ld_ - n) * d, a0, stream_));
      HAPI_CUDA_TRY(launchZeroRows(Xp_.get(), ld_, d_soa, a, a0, stream_));
      HAPI_CUDA_TRY(cudaMemcpy2DAsync(Psip_.get(), a0 * d, Psi_.get(), cb_ * d, a0 * d, a0, cudaMemcpyDeviceToDevice,
                                      stream_));
      a0p_ = a0;
      pend_done_ = 0;
      pend_left_ = flush_shares_;
    }
    HAPI_CUDA_TRY(cudaStreamSynchronize(stream_));
    ++flushes_;
    flush_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    st = startEpoch();
    join_view_ = !at_once;
    return st;
  }

  // The dense backend's update workspace (idle between calls) when it holds
  // `count` doubles, else an own buffer; null when that cannot be allocated.
  double* scratch(std::size_t count) {
    if (count <= dense_->workspaceCount()) return dense_->workspace();
    // Growing frees the old buffer, which queued work (a background share) may still use.
    if (count > flush_.count() && cudaStreamSynchronize(stream_) != cudaSuccess) {
      last_error_ = "cudaStreamSynchronize before growing the partitioned scratch failed";
      return nullptr;
    }
    if (flush_.ensure(count) != cudaSuccess) {
      last_error_ = "cudaMalloc(partitioned scratch of " + std::to_string(count) + " doubles) failed";
      return nullptr;
    }
    return flush_.get();
  }

  // lower(C) rows [r0, r1) -= (X Psi X^T) rows (X n x k, leading dim ld_;
  // Psi k x k lower, leading dim ldpsi), in row panels of defaultPanel(n):
  // the panel's X Psi rows (DSYMM), one DGEMM left of the diagonal block, one
  // DSYRKX on it. The flush's product (rows 0..n) and the staged shares.
  Status correctRows(const double* X, const double* Psi, int ldpsi, int k, int r0, int r1) {
    const int n = dim();
    if (r1 <= r0 || k <= 0) return Status::kOk;
    const int panel = std::min(defaultPanel(n), std::max(n, 1));
    double* T = scratch(static_cast<std::size_t>(panel) * k);
    if (T == nullptr) return Status::kBackendError;
    double* C = dense_->covariance();
    const int ldc = static_cast<int>(ld_);
    for (int i0 = r0; i0 < r1; i0 += panel) {
      const int b = std::min(panel, r1 - i0);
      HAPI_CUDA_TRY(Blas<double>::symmRight(blas_, b, k, 1.0, Psi, ldpsi, X + i0, ldc, 0.0, T, b));
      if (i0 > 0)
        HAPI_CUDA_TRY(Blas<double>::gemm(blas_, false, true, b, i0, k, -1.0, T, b, X, ldc, 1.0, C + i0, ldc));
      HAPI_CUDA_TRY(Blas<double>::syrkx(blas_, b, k, -1.0, T, b, X + i0, ldc, 1.0,
                                        C + i0 + static_cast<std::size_t>(i0) * ld_, ldc));
    }
    return Status::kOk;
  }

  // --- Staged flush (staged_flush.hpp) ---
  bool pending() const { return pend_left_ > 0; }

  // The pending correction applied to the rows [done, r1): ends
  // synchronised, or with `wait` false only queued (a background share).
  Status applyPendingRows(int r1, bool wait = true) {
    if (!pending()) return Status::kOk;
    const int r0 = pend_done_, r = std::min(r1, dim());
    if (r > r0) {
      const Status st = correctRows(Xp_.get(), Psip_.get(), a0p_, a0p_, r0, r);
      if (st != Status::kOk) return st;
      if (wait) HAPI_CUDA_TRY(cudaStreamSynchronize(stream_));
      pend_done_ = r;
    }
    if (pend_done_ >= dim()) pend_left_ = 0;
    return Status::kOk;
  }

  // One share, equal in work (partition::nextStagedRow): per update, or per
  // frame in the background.
  Status advancePending(bool wait) {
    if (!pending()) return Status::kOk;
    const int r1 = partition::nextStagedRow(pend_done_, dim(), pend_left_);
    if (pend_left_ > 1) --pend_left_;  // the last share ends at dim(), where applyPendingRows clears it
    return applyPendingRows(r1, wait);
  }

  // A queued background share finished (its errors reported here).
  Status waitShare() const {
    if (!share_queued_) return Status::kOk;
    share_queued_ = false;
    HAPI_CUDA_TRY(cudaStreamSynchronize(stream_));
    return Status::kOk;
  }

  // The host copy of Caa's pose block, after every call that changes it
  // (synchronises the stream).
  Status readPoseBlock() {
    const int P = poseDim();
    std::vector<double> h(static_cast<std::size_t>(P) * P);
    HAPI_CUDA_TRY(cudaMemcpy2DAsync(h.data(), P * sizeof(double), Caa_.get(), ca_ * sizeof(double),
                                    P * sizeof(double), P, cudaMemcpyDeviceToHost, stream_));
    HAPI_CUDA_TRY(cudaStreamSynchronize(stream_));
    pose_block_.resize(P, P);
    for (int c = 0; c < P; ++c)
      for (int r = c; r < P; ++r) pose_block_(r, c) = pose_block_(c, r) = h[r + static_cast<std::size_t>(P) * c];
    return Status::kOk;
  }

  // *D = Xp Psip Xp_cols^T (n x w, leading dim n) for the w state rows in
  // the device array `cols`: what C^0's columns `cols` still owe, in a
  // scratch buffer valid until the next scratch use.
  Status owedColumns(const int* cols, int w, const double** D) {
    const int n = dim(), ap = a0p_;
    HAPI_CUDA_TRY(owed_small_.ensure(2 * static_cast<std::size_t>(w) * ap));
    HAPI_CUDA_TRY(owed_.ensure(static_cast<std::size_t>(n) * w));
    double* Xc = owed_small_.get();
    double* XcPsi = Xc + static_cast<std::size_t>(w) * ap;
    HAPI_CUDA_TRY(launchGatherRows(Xp_.get(), ld_, cols, w, ap, Xc, w, stream_));
    HAPI_CUDA_TRY(Blas<double>::symmRight(blas_, w, ap, 1.0, Psip_.get(), ap, Xc, w, 0.0, XcPsi, w));
    HAPI_CUDA_TRY(Blas<double>::gemm(blas_, false, true, n, w, ap, 1.0, Xp_.get(), static_cast<int>(ld_), XcPsi, w,
                                     0.0, owed_.get(), n));
    *D = owed_.get();
    return Status::kOk;
  }

  // After a removal's slot moves (C and Xp rows moved, n_old the dimension
  // before): the entries that moved before `done` pay their share now
  // (partition::rowsSettledByMoves), Xp's rows past the new dimension are
  // cleared and `done` is clipped (the CPU variant's settleMovedDebt).
  Status settleMovedDebt(const std::vector<SlotMove>& moves, int n_old) {
    const int n = dim(), done = std::min(pend_done_, n);
    const std::vector<int> ks = partition::rowsSettledByMoves(moves, pend_done_, poseDim());
    const int w = static_cast<int>(ks.size());
    if (w > 0 && done > 0) {
      std::vector<unsigned char> settled(done, 0);
      for (int k : ks) settled[k] = 1;
      HAPI_CUDA_TRY(idx_.ensure(w + (done + 3) / 4));
      int* d_ks = idx_.get();
      unsigned char* d_settled = reinterpret_cast<unsigned char*>(d_ks + w);
      HAPI_CUDA_TRY(cudaMemcpyAsync(d_ks, ks.data(), w * sizeof(int), cudaMemcpyHostToDevice, stream_));
      HAPI_CUDA_TRY(cudaMemcpyAsync(d_settled, settled.data(), done, cudaMemcpyHostToDevice, stream_));
      const double* D = nullptr;
      const Status st = owedColumns(d_ks, w, &D);  // n x w; rows < done used
      if (st != Status::kOk) return st;
      HAPI_CUDA_TRY(launchSettleOwed(dense_->covariance(), ld_, d_ks, w, D, n, done, d_settled, stream_));
    }
    if (n_old > n)
      HAPI_CUDA_TRY(cudaMemset2DAsync(Xp_.get() + n, ld_ * sizeof(double), 0, (n_old - n) * sizeof(double), a0p_,
                                      stream_));
    HAPI_CUDA_TRY(cudaStreamSynchronize(stream_));
    pend_done_ = done;
    if (pend_done_ >= n) pend_left_ = 0;
    return Status::kOk;
  }

  // Active part = the pose, basis = the pose, Phi = I, Psi = 0, Caa = C_pp,
  // X = the pose columns of the stored C.
  Status startEpoch() {
    const int P = poseDim(), n = dim();
    for (int s : active_) active_pos_[s] = -1;
    for (int s : basis_) in_basis_[s] = 0;
    active_.clear();
    basis_.clear();
    const std::size_t d = sizeof(double);
    HAPI_CUDA_TRY(cudaMemcpy2DAsync(Caa_.get(), ca_ * d, dense_->covariance(), ld_ * d, P * d, P,
                                    cudaMemcpyDeviceToDevice, stream_));
    HAPI_CUDA_TRY(cudaMemset2DAsync(Phi_.get(), ca_ * d, 0, P * d, P, stream_));
    HAPI_CUDA_TRY(launchSetDiagonalOne(Phi_.get(), ca_, P, stream_));
    HAPI_CUDA_TRY(cudaMemset2DAsync(Psi_.get(), cb_ * d, 0, P * d, P, stream_));
    HAPI_CUDA_TRY(launchGatherSymmetric(dense_->covariance(), ld_, nullptr, n, pose_idx_.get(), P, X_.get(), ld_,
                                        stream_));
    HAPI_CUDA_TRY(cudaStreamSynchronize(stream_));
    a_ = a0_ = P;
    updated_in_epoch_ = touched_ = false;
    return Status::kOk;
  }

  std::unique_ptr<Dense> dense_;  // stored C (C^0), descriptors, dense update
  const int max_active_;
  const int flush_shares_;
  const bool background_;         // partition_flush_background
  const std::size_t ld_;          // of C and X
  cudaStream_t stream_;
  cublasHandle_t blas_;
  cusolverDnHandle_t solver_;
  std::vector<int> active_pos_;  // per slot: first active index, -1 when passive
  std::vector<char> in_basis_;   // per slot: joined the basis this epoch
  std::vector<int> active_;      // active landmark slots, in active order
  std::vector<int> basis_;       // basis landmark slots, in basis order
  int a_ = 0, a0_ = 0;           // active and basis dimensions
  std::size_t ca_ = 0, cb_ = 0;  // their capacities (growActive)
  DeviceBuffer<double> Caa_, Phi_, Psi_, X_;
  DeviceBuffer<int> pose_idx_;   // 0 .. P-1
  // Scratch: the flush's panel / write-back chunk where the dense
  // workspace is too small; update operands
  // (H_A^T, P_A, S, V, vectors); host-visible small results.
  DeviceBuffer<double> flush_, Ht_, S_, V_, vec_, H_, pose_mats_;
  mutable DeviceBuffer<double> PA_, small_;
  mutable DeviceBuffer<int> idx_;
  InnovationFactor<double> factor_;
  bool updated_in_epoch_ = false;  // a partitioned update ran since the epoch began
  bool touched_ = false;           // a predict or an update since the epoch began
  // Staged flush: the pending correction (Xp_ ld x a0p_, Psip_ a0p_ x a0p_
  // packed), its progress (rows [0, pend_done_) applied) and shares left (0:
  // nothing pending); owed_ / owed_small_: what gathered columns still owe
  // and their operands; join_view_: the epoch began at a staged flush and has
  // had no update yet.
  DeviceBuffer<double> Xp_, Psip_, owed_;
  mutable DeviceBuffer<double> owed_small_;
  int a0p_ = 0, pend_done_ = 0, pend_left_ = 0;
  bool join_view_ = false;
  // A background share queued on the stream and not yet waited for.
  mutable bool share_queued_ = false;
  PoseMat pose_block_;  // host copy of Caa's pose block (readPoseBlock)
  int flushes_ = 0;
  double flush_seconds_ = 0;
  mutable std::string last_error_;
};

}  // namespace

std::unique_ptr<CovarianceBackend> makePartitionedCudaBackend(int capacity, int descriptor_length, int pose_dim,
                                                              const EskfSettings& s, std::string* error) {
  std::string dummy;
  std::string* err = error != nullptr ? error : &dummy;
  if (s.precision != Precision::kFp64) {
    *err = "covariance_update partitioned on the cuda backend supports precision fp64 only";
    return nullptr;
  }
  if (s.partition_max_active < 1) {
    *err = "partition_max_active must be >= 1";
    return nullptr;
  }
  // The dense update of a view jump forms A = P L^-T in place (TRSM) unless
  // the settings fix the solve: trtri + GEMM would need a second n x 3L
  // workspace, memory that X needs beside the largest pools.
  EskfSettings sd = s;
  if (sd.cuda_solve == CudaSolve::kAuto) sd.cuda_solve = CudaSolve::kTrsm;
  std::unique_ptr<CovarianceBackend> base = makeCudaBackend(capacity, descriptor_length, pose_dim, sd, err);
  if (!base) return nullptr;
  std::unique_ptr<Dense> dense(static_cast<Dense*>(base.release()));  // fp64: a CudaBackend<double>
  auto b = std::make_unique<PartitionedCudaBackend>(std::move(dense), s.partition_max_active,
                                                    s.partition_flush_shares, s.partition_flush_background);
  std::string why;
  if (!b->init(&why)) {
    *err = "partitioned CUDA backend (capacity " + std::to_string(capacity) + "): " + why;
    return nullptr;
  }
  return b;
}

}  // namespace cuda
}  // namespace hapi_eskf
