// The dense CUDA backend (docs/DESIGN.md "CUDA backend"): C lives on the
// device for the whole run (capacity-sized, column-major, ld = 12 + 3 capacity
// rounded up to 32 elements, lower triangle authoritative); only dx (length
// n), the 3m-vector y and small blocks cross the bus inside the filter loop.
// The O(n^2 m) step is cuBLAS (SYRK, panelled or recursive GEMMs), the
// factorisations cuSOLVER, the O(n m) gathers and all bookkeeping our own
// kernels (kernels.cuh). Inputs arrive checked (CovarianceBackend's public
// methods, src/covariance/covariance_backend.cpp), before anything touches the
// device. A header because the partitioned CUDA backend keeps its stored C in
// one (partitioned_cuda_backend.cpp); the factories are in cuda_backend.cpp.
#pragma once

#include "hapi_eskf/backend/removal_plan.hpp"
#include "hapi_eskf/covariance/covariance_backend.hpp"

#include "blas_traits.hpp"
#include "cuda_check.hpp"
#include "device_buffer.hpp"
#include "innovation_factor.hpp"
#include "kernels.cuh"
#include "stage_times.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace hapi_eskf {
namespace cuda {

// F then Q, each P x P row-major (the layout launchPredict reads).
inline std::vector<double> rowMajorPair(const PoseMat& F, const PoseMat& Q) {
  const int P = static_cast<int>(F.rows());
  std::vector<double> h(2 * static_cast<std::size_t>(P) * P);
  for (int r = 0; r < P; ++r)
    for (int c = 0; c < P; ++c) {
      h[P * r + c] = F(r, c);
      h[P * P + P * r + c] = Q(r, c);
    }
  return h;
}

// Columns of the update workspace allocated up front (it grows when an
// update has more blocks).
inline int initialWorkColumns(int capacity) { return std::max(3, std::min(600, 3 * capacity)); }

// Host packing of the inputs that go to the device, shared by the dense and
// the partitioned backends. Per measurement block: 27 H values (row-major 3x6
// H_pose, then row-major 3x3 H_landmark, the layout of kernels.cuh), 9 R
// values (row-major), 3 innovations, and its slot.
template <typename T>
void packMeasurements(const std::vector<MeasurementBlock>& blocks, std::vector<T>* H, std::vector<T>* R,
                      std::vector<T>* z, std::vector<int>* slots) {
  const std::size_t m = blocks.size();
  H->assign(27 * m, T(0));
  R->assign(9 * m, T(0));
  z->assign(3 * m, T(0));
  slots->assign(m, -1);
  for (std::size_t j = 0; j < m; ++j) {
    const MeasurementBlock& b = blocks[j];
    (*slots)[j] = b.slot;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 6; ++c) (*H)[27 * j + 6 * r + c] = static_cast<T>(b.H_pose(r, c));
      for (int c = 0; c < 3; ++c) {
        (*H)[27 * j + 18 + 3 * r + c] = static_cast<T>(b.H_landmark(r, c));
        (*R)[9 * j + 3 * r + c] = static_cast<T>(b.R(r, c));
      }
      (*z)[3 * j + r] = static_cast<T>(b.innovation(r));
    }
  }
}

// Per new landmark: 18 G_pose values (row-major 3x6), 9 values of
// G_z Cz G_z^T (row-major) and its D descriptor bytes.
template <typename T>
void packNewLandmarks(const std::vector<NewLandmarkBlock>& blocks, int D, std::vector<T>* G, std::vector<T>* Nz,
                      std::vector<uint8_t>* desc) {
  const std::size_t m = blocks.size();
  G->assign(18 * m, T(0));
  Nz->assign(9 * m, T(0));
  desc->assign(m * static_cast<std::size_t>(D), 0);
  for (std::size_t j = 0; j < m; ++j) {
    const NewLandmarkBlock& b = blocks[j];
    const Mat3 N = b.G_z * b.Cz * b.G_z.transpose();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 6; ++c) (*G)[18 * j + 6 * r + c] = static_cast<T>(b.G_pose(r, c));
      for (int c = 0; c < 3; ++c) (*Nz)[9 * j + 3 * r + c] = static_cast<T>(N(r, c));
    }
    if (D > 0) std::memcpy(desc->data() + j * D, b.descriptor, D);
  }
}

// The settings' cuda_rank_update fixes the schedule of C <- C - A A^T
// (blas_traits.hpp), cuda_solve how A = P L^-T is formed; auto (the default)
// chooses both by size (autoRankUpdate, autoSolveByInverse: the fastest on
// the H100, docs/BENCHMARKS.md). The GPU tests run every pair against the CPU.
template <typename T>
class CudaBackend final : public CovarianceBackend {
 public:
  CudaBackend(int capacity, int descriptor_length, int pose_dim, const EskfSettings& s)
      : CovarianceBackend(pose_dim),
        cap_(capacity),
        D_(descriptor_length),
        device_(s.cuda_device),
        ld_(paddedLd(stateDim(capacity, pose_dim))),
        rank_(s.cuda_rank_update),
        solve_(s.cuda_solve),
        stage_times_(s.cuda_stage_times) {}

  ~CudaBackend() override {
    cudaSetDevice(device_);
    if (solver_ != nullptr) cusolverDnDestroy(solver_);
    if (blas_ != nullptr) cublasDestroy(blas_);
    if (stream_ != nullptr) cudaStreamDestroy(stream_);
    for (cudaEvent_t e : ev_)
      if (e != nullptr) cudaEventDestroy(e);
  }

  // Allocates everything the loop needs up front (C, a workspace of W columns,
  // descriptor pool); false and *why on failure.
  bool init(std::string* why) {
    if (failed(cudaSetDevice(device_), "cudaSetDevice", why)) return false;
    if (failed(cudaStreamCreateWithFlags(&stream_, cudaStreamNonBlocking), "cudaStreamCreate", why)) return false;
    if (failed(cublasCreate(&blas_), "cublasCreate", why)) return false;
    if (failed(cublasSetStream(blas_, stream_), "cublasSetStream", why)) return false;
    if (failed(cusolverDnCreate(&solver_), "cusolverDnCreate", why)) return false;
    if (failed(cusolverDnSetStream(solver_, stream_), "cusolverDnSetStream", why)) return false;
    if (failed(C_.ensure(ld_ * ld_), "cudaMalloc(C)", why)) return false;
    // Zeroed once so the scratch upper triangle never holds NaN patterns.
    if (failed(cudaMemsetAsync(C_.get(), 0, C_.bytes(), stream_), "cudaMemset(C)", why)) return false;
    work_cols_ = initialWorkColumns(cap_);
    if (failed(work_.ensure(ld_ * static_cast<std::size_t>(work_cols_)), "cudaMalloc(work)", why)) return false;
    const std::size_t pool = static_cast<std::size_t>(std::max(cap_, 1)) * std::max(D_, 1);
    if (failed(desc_.ensure(pool), "cudaMalloc(descriptors)", why)) return false;
    if (failed(desc_tmp_.ensure(pool), "cudaMalloc(descriptors)", why)) return false;
    if (failed(dx_.ensure(ld_), "cudaMalloc(dx)", why)) return false;
    if (failed(pose_mats_.ensure(2 * kMaxPoseDim * kMaxPoseDim), "cudaMalloc(F, Q)", why)) return false;
    if (failed(cudaStreamSynchronize(stream_), "cudaStreamSynchronize", why)) return false;
    if (stage_times_) {
      for (cudaEvent_t& e : ev_)
        if (failed(cudaEventCreate(&e), "cudaEventCreate", why)) return false;
    }
    return true;
  }

  const char* name() const override { return sizeof(T) == 8 ? "cuda-fp64" : "cuda-fp32"; }
  int capacity() const override { return cap_; }
  int numLandmarks() const override { return K_; }
  int descriptorLength() const override { return D_; }
  std::string lastError() const override { return last_error_; }
  std::size_t memoryBytes() const override {
    return C_.bytes() + work_.bytes() + S_.bytes() + y_.bytes() + dx_.bytes() + factor_.bytes() + H_.bytes() +
           R_.bytes() + slots_.bytes() + ints_.bytes() + desc_.bytes() + desc_tmp_.bytes() + queries_.bytes() +
           small_.bytes() + work2_.bytes() + y2_.bytes() + trtri_dev_.bytes() + pose_mats_.bytes();
  }

 protected:
  Status doReset(const PoseMat& C_pose) override {
    HAPI_CUDA_TRY(cudaSetDevice(device_));
    const int P = poseDim();
    std::vector<T> h(static_cast<std::size_t>(P) * P);
    for (std::size_t i = 0; i < h.size(); ++i) h[i] = static_cast<T>(C_pose.data()[i]);  // column-major
    HAPI_CUDA_TRY(cudaMemcpy2DAsync(C_.get(), ld_ * sizeof(T), h.data(), P * sizeof(T), P * sizeof(T), P,
                                    cudaMemcpyHostToDevice, stream_));
    HAPI_CUDA_TRY(cudaStreamSynchronize(stream_));
    K_ = 0;
    return Status::kOk;
  }

  Status doPredict(const PoseMat& F, const PoseMat& Q) override {
    HAPI_CUDA_TRY(cudaSetDevice(device_));
    const int P = poseDim();
    const std::vector<double> h = rowMajorPair(F, Q);
    HAPI_CUDA_TRY(cudaMemcpyAsync(pose_mats_.get(), h.data(), h.size() * sizeof(double), cudaMemcpyHostToDevice,
                                  stream_));
    HAPI_CUDA_TRY(launchPredict<T>(C_.get(), ld_, n(), P, pose_mats_.get(), pose_mats_.get() + P * P, stream_));
    HAPI_CUDA_TRY(cudaStreamSynchronize(stream_));
    return Status::kOk;
  }

  Status doMarginals(const std::vector<int>& slots, std::vector<Mat9>* out) const override {
    HAPI_CUDA_TRY(cudaSetDevice(device_));
    const int cnt = static_cast<int>(slots.size());
    HAPI_CUDA_TRY(slots_.ensure(slots.size()));
    HAPI_CUDA_TRY(small_.ensure(81 * slots.size()));
    HAPI_CUDA_TRY(cudaMemcpyAsync(slots_.get(), slots.data(), slots.size() * sizeof(int), cudaMemcpyHostToDevice,
                                  stream_));
    HAPI_CUDA_TRY(launchMarginals<T>(C_.get(), ld_, poseDim(), slots_.get(), cnt, small_.get(), stream_));
    std::vector<double> h(81 * slots.size());
    HAPI_CUDA_TRY(cudaMemcpyAsync(h.data(), small_.get(), h.size() * sizeof(double), cudaMemcpyDeviceToHost, stream_));
    HAPI_CUDA_TRY(cudaStreamSynchronize(stream_));
    for (int i = 0; i < cnt; ++i) std::memcpy((*out)[i].data(), h.data() + 81 * i, 81 * sizeof(double));
    return Status::kOk;
  }

  Status doUpdate(const std::vector<MeasurementBlock>& blocks, Eigen::VectorXd* dx, double* nis) override {
    HAPI_CUDA_TRY(cudaSetDevice(device_));
    const int m = static_cast<int>(blocks.size());
    const int dim = 3 * m;
    const int nn = n();

    std::vector<T> hH, hR, hz;
    std::vector<int> hslots;
    packMeasurements(blocks, &hH, &hR, &hz, &hslots);
    HAPI_CUDA_TRY(ensureWork(dim));
    HAPI_CUDA_TRY(mark(kEvStart));
    HAPI_CUDA_TRY(H_.ensure(hH.size()));
    HAPI_CUDA_TRY(R_.ensure(hR.size()));
    HAPI_CUDA_TRY(slots_.ensure(m));
    HAPI_CUDA_TRY(S_.ensure(static_cast<std::size_t>(dim) * dim));
    HAPI_CUDA_TRY(y_.ensure(dim));
    HAPI_CUDA_TRY(cudaMemcpyAsync(H_.get(), hH.data(), hH.size() * sizeof(T), cudaMemcpyHostToDevice, stream_));
    HAPI_CUDA_TRY(cudaMemcpyAsync(R_.get(), hR.data(), hR.size() * sizeof(T), cudaMemcpyHostToDevice, stream_));
    HAPI_CUDA_TRY(cudaMemcpyAsync(slots_.get(), hslots.data(), m * sizeof(int), cudaMemcpyHostToDevice, stream_));
    HAPI_CUDA_TRY(cudaMemcpyAsync(y_.get(), hz.data(), dim * sizeof(T), cudaMemcpyHostToDevice, stream_));

    // 1. P = C H^T by gather; 2. S = H P + R; Cholesky of S (lower).
    T* P = work_.get();
    const int ldP = static_cast<int>(ld_);
    HAPI_CUDA_TRY(mark(kEvUploaded));
    HAPI_CUDA_TRY(launchGatherPHt<T>(C_.get(), ld_, nn, poseDim(), slots_.get(), H_.get(), m, P, ld_, stream_));
    HAPI_CUDA_TRY(mark(kEvGathered));
    HAPI_CUDA_TRY(launchInnovationCov<T>(P, ld_, poseDim(), slots_.get(), H_.get(), R_.get(), m, S_.get(), stream_));
    // As the reference (innovation_factor.hpp); C not touched yet on failure.
    Status st = factor_.enqueueCheck(stream_, S_.get(), dim, &last_error_);
    if (st != Status::kOk) return st;
    HAPI_CUDA_TRY(mark(kEvInnovationCov));
    st = factor_.enqueueFactor(solver_, stream_, S_.get(), &last_error_);
    if (st != Status::kOk) return st;
    HAPI_CUDA_TRY(mark(kEvFactored));
    HAPI_CUDA_TRY(cudaStreamSynchronize(stream_));
    st = factor_.verdict(&last_error_);
    if (st != Status::kOk) return st;

    // 3. A = P L^-T, y = L^-1 z, dx = A y. CudaSolve::kTrsm: in place by TRSM.
    // CudaSolve::kInverse: L^-1 by trtri (3m x 3m, small), then A = P L^-T as one
    // GEMM into a second workspace: the same product at GEMM rate instead of
    // TRSM's (bench, docs/BENCHMARKS.md). L's diagonal was checked above, so
    // trtri cannot meet a zero pivot.
    T* A = P;
    T* y = y_.get();
    HAPI_CUDA_TRY(mark(kEvTrsmStart));
    const bool by_inverse = solve_ == CudaSolve::kInverse || (solve_ == CudaSolve::kAuto && autoSolveByInverse(nn));
    if (by_inverse) {
      HAPI_CUDA_TRY(ensureInverseWork(dim));
      HAPI_CUDA_TRY(trtri<T>(solver_, dim, S_.get(), trtri_dev_.get(), trtri_dev_.bytes(), trtri_host_.data(),
                             trtri_host_.size(), ints_.get()));
      HAPI_CUDA_TRY(launchZeroStrictUpper<T>(S_.get(), dim, stream_));
      A = work2_.get();
      HAPI_CUDA_TRY(Blas<T>::gemmNT(blas_, nn, dim, dim, T(1), P, ldP, S_.get(), dim, T(0), A, ldP));
      HAPI_CUDA_TRY(mark(kEvTrsmDone));
      y = y2_.get();
      HAPI_CUDA_TRY(Blas<T>::gemv(blas_, dim, dim, S_.get(), dim, y_.get(), y));
    } else {
      HAPI_CUDA_TRY(Blas<T>::trsmRightLowerT(blas_, nn, dim, S_.get(), dim, P, ldP));
      HAPI_CUDA_TRY(mark(kEvTrsmDone));
      HAPI_CUDA_TRY(Blas<T>::trsvLower(blas_, dim, S_.get(), dim, y));
    }
    HAPI_CUDA_TRY(Blas<T>::gemv(blas_, nn, dim, A, ldP, y, dx_.get()));
    std::vector<T> hy(dim), hdx(nn);
    HAPI_CUDA_TRY(cudaMemcpyAsync(hy.data(), y, dim * sizeof(T), cudaMemcpyDeviceToHost, stream_));
    HAPI_CUDA_TRY(cudaMemcpyAsync(hdx.data(), dx_.get(), nn * sizeof(T), cudaMemcpyDeviceToHost, stream_));
    HAPI_CUDA_TRY(mark(kEvSolved));
    HAPI_CUDA_TRY(cudaStreamSynchronize(stream_));
    double y2 = 0;
    for (T v : hy) y2 += static_cast<double>(v) * static_cast<double>(v);
    Eigen::VectorXd dxd(nn);
    for (int i = 0; i < nn; ++i) dxd(i) = static_cast<double>(hdx[i]);
    // A poisoned C (or an overflow in FP32) shows up here: refuse before C changes.
    if (!std::isfinite(y2) || !dxd.allFinite()) return Status::kNonFinite;

    // 4. C <- C - A A^T (lower triangle only).
    HAPI_CUDA_TRY(mark(kEvRankStart));
    HAPI_CUDA_TRY(rankUpdate<T>(blas_, rank_, nn, dim, A, ldP, C_.get(), ld_, defaultPanel(nn)));
    HAPI_CUDA_TRY(mark(kEvRankDone));
    HAPI_CUDA_TRY(cudaStreamSynchronize(stream_));
    HAPI_CUDA_TRY(accumulateStageTimes());
    *dx = std::move(dxd);
    if (nis != nullptr) *nis = y2;
    return Status::kOk;
  }

  Status doAddLandmarks(const std::vector<NewLandmarkBlock>& blocks) override {
    HAPI_CUDA_TRY(cudaSetDevice(device_));
    const int m = static_cast<int>(blocks.size());
    std::vector<T> hG, hN;
    std::vector<uint8_t> hd;
    packNewLandmarks(blocks, D_, &hG, &hN, &hd);
    HAPI_CUDA_TRY(H_.ensure(hG.size()));
    HAPI_CUDA_TRY(R_.ensure(hN.size()));
    HAPI_CUDA_TRY(cudaMemcpyAsync(H_.get(), hG.data(), hG.size() * sizeof(T), cudaMemcpyHostToDevice, stream_));
    HAPI_CUDA_TRY(cudaMemcpyAsync(R_.get(), hN.data(), hN.size() * sizeof(T), cudaMemcpyHostToDevice, stream_));
    if (!hd.empty()) {
      HAPI_CUDA_TRY(cudaMemcpyAsync(desc_.get() + static_cast<std::size_t>(K_) * D_, hd.data(), hd.size(),
                                    cudaMemcpyHostToDevice, stream_));
    }
    HAPI_CUDA_TRY(launchAddLandmarks<T>(C_.get(), ld_, n(), H_.get(), R_.get(), m, stream_));
    HAPI_CUDA_TRY(cudaStreamSynchronize(stream_));
    K_ += m;
    return Status::kOk;
  }

  // Fill holes from the tail (removal_plan.hpp, launchFillHoles in
  // kernels.cuh): O(n) per moved landmark, no workspace; the descriptors
  // follow the same plan.
  Status doRemoveLandmarks(const std::vector<int>& slots) override {
    HAPI_CUDA_TRY(cudaSetDevice(device_));
    const int K_new = K_ - static_cast<int>(slots.size());
    const std::vector<SlotMove> moves = tailFillMoves(K_, slots);
    if (!moves.empty()) {
      // ints_ layout: old slot of every new slot (K_new) | holes (h).
      std::vector<int> h = oldSlotOfNew(K_new, moves);
      for (const SlotMove& m : moves) h.push_back(m.to);
      HAPI_CUDA_TRY(ints_.ensure(h.size()));
      int* d = ints_.get();
      HAPI_CUDA_TRY(cudaMemcpyAsync(d, h.data(), h.size() * sizeof(int), cudaMemcpyHostToDevice, stream_));
      HAPI_CUDA_TRY(launchFillHoles<T>(C_.get(), ld_, stateDim(K_new, poseDim()), poseDim(), d, d + K_new, static_cast<int>(moves.size()),
                                       stream_));
      HAPI_CUDA_TRY(launchGatherDescriptors(desc_.get(), d, K_new, D_, desc_tmp_.get(), stream_));
      HAPI_CUDA_TRY(cudaStreamSynchronize(stream_));
      desc_.swap(desc_tmp_);
    }
    K_ = K_new;
    return Status::kOk;
  }

  Status doMatchDescriptors(const uint8_t* queries, int n_query, std::vector<DescriptorMatch>* out) const override {
    HAPI_CUDA_TRY(cudaSetDevice(device_));
    const std::size_t qbytes = static_cast<std::size_t>(n_query) * D_;
    HAPI_CUDA_TRY(queries_.ensure(qbytes));
    HAPI_CUDA_TRY(ints_.ensure(4 * static_cast<std::size_t>(n_query)));
    HAPI_CUDA_TRY(cudaMemcpyAsync(queries_.get(), queries, qbytes, cudaMemcpyHostToDevice, stream_));
    int* d = ints_.get();
    HAPI_CUDA_TRY(launchHammingTop2(desc_.get(), K_, queries_.get(), n_query, D_, d, d + n_query, d + 2 * n_query,
                                    d + 3 * n_query, stream_));
    std::vector<int> h(4 * static_cast<std::size_t>(n_query));
    HAPI_CUDA_TRY(cudaMemcpyAsync(h.data(), d, h.size() * sizeof(int), cudaMemcpyDeviceToHost, stream_));
    HAPI_CUDA_TRY(cudaStreamSynchronize(stream_));
    for (int q = 0; q < n_query; ++q) {
      DescriptorMatch& o = (*out)[q];
      o.best_slot = h[q];
      o.best_distance = h[n_query + q];
      o.second_slot = h[2 * n_query + q];
      o.second_distance = h[3 * n_query + q];
    }
    return Status::kOk;
  }

 public:
  PoseMat poseCovariance() const override {
    const int P = poseDim();
    PoseMat out = PoseMat::Constant(P, P, std::numeric_limits<double>::quiet_NaN());
    std::vector<T> h(static_cast<std::size_t>(P) * P);
    if (cudaSetDevice(device_) != cudaSuccess ||
        cudaMemcpy2DAsync(h.data(), P * sizeof(T), C_.get(), ld_ * sizeof(T), P * sizeof(T), P,
                          cudaMemcpyDeviceToHost, stream_) != cudaSuccess ||
        cudaStreamSynchronize(stream_) != cudaSuccess) {
      return out;
    }
    for (int c = 0; c < P; ++c)
      for (int r = c; r < P; ++r) out(r, c) = out(c, r) = static_cast<double>(h[r + P * c]);
    return out;
  }

  std::vector<Mat3> landmarkCovariances() const override {
    std::vector<Mat3> out(K_, Mat3::Constant(std::numeric_limits<double>::quiet_NaN()));
    if (K_ == 0) return out;
    std::vector<double> h(9 * static_cast<std::size_t>(K_));
    if (cudaSetDevice(device_) != cudaSuccess || small_.ensure(h.size()) != cudaSuccess ||
        launchLandmarkBlocks<T>(C_.get(), ld_, poseDim(), K_, small_.get(), stream_) != cudaSuccess ||
        cudaMemcpyAsync(h.data(), small_.get(), h.size() * sizeof(double), cudaMemcpyDeviceToHost, stream_) !=
            cudaSuccess ||
        cudaStreamSynchronize(stream_) != cudaSuccess) {
      return out;
    }
    for (int k = 0; k < K_; ++k) std::memcpy(out[k].data(), h.data() + 9 * k, 9 * sizeof(double));
    return out;
  }

  Eigen::MatrixXd denseCovariance() const override {
    const int nn = n();
    Eigen::MatrixXd out = Eigen::MatrixXd::Constant(nn, nn, std::numeric_limits<double>::quiet_NaN());
    std::vector<T> h(static_cast<std::size_t>(nn) * nn);
    if (cudaSetDevice(device_) != cudaSuccess ||
        cudaMemcpy2DAsync(h.data(), nn * sizeof(T), C_.get(), ld_ * sizeof(T), nn * sizeof(T), nn,
                          cudaMemcpyDeviceToHost, stream_) != cudaSuccess ||
        cudaStreamSynchronize(stream_) != cudaSuccess) {
      return out;
    }
    for (int c = 0; c < nn; ++c)
      for (int r = c; r < nn; ++r) out(r, c) = out(c, r) = static_cast<double>(h[r + static_cast<std::size_t>(nn) * c]);
    return out;
  }

  std::vector<uint8_t> descriptors() const override {
    std::vector<uint8_t> h(static_cast<std::size_t>(K_) * D_);
    if (h.empty()) return h;
    if (cudaSetDevice(device_) != cudaSuccess ||
        cudaMemcpyAsync(h.data(), desc_.get(), h.size(), cudaMemcpyDeviceToHost, stream_) != cudaSuccess ||
        cudaStreamSynchronize(stream_) != cudaSuccess) {
      h.clear();
    }
    return h;
  }

  // The stored C, its stream and handles, for the partitioned backend that
  // keeps its C^0 in a dense backend (partitioned_cuda_backend.cpp) and runs
  // its own products on the same stream, so no call needs a cross-stream wait.
  cudaStream_t stream() const { return stream_; }
  cublasHandle_t blas() const { return blas_; }
  cusolverDnHandle_t solver() const { return solver_; }
  T* covariance() const { return C_.get(); }
  std::size_t ld() const { return ld_; }
  // The update workspace (ld x at least 3 columns), free between calls: the
  // partitioned backend's flush borrows it instead of allocating its own.
  T* workspace() const { return work_.get(); }
  std::size_t workspaceCount() const { return work_.count(); }

 private:
  int n() const { return stateDim(K_, poseDim()); }

  // Optional per-stage timing of update() (the cuda_stage_times setting,
  // stage_times.hpp): events on the filter's own stream, so the spans include
  // the bubbles of the host round trips; off by default (no events recorded).
  enum Ev { kEvStart, kEvUploaded, kEvGathered, kEvInnovationCov, kEvFactored, kEvTrsmStart, kEvTrsmDone, kEvSolved,
            kEvRankStart, kEvRankDone, kEvCount };
  cudaError_t mark(Ev e) { return ev_[e] != nullptr ? cudaEventRecord(ev_[e], stream_) : cudaSuccess; }
  cudaError_t accumulateStageTimes() {
    if (ev_[0] == nullptr) return cudaSuccess;
    float ms[kEvCount - 1];
    for (int i = 0; i + 1 < kEvCount; ++i) {
      const cudaError_t e = cudaEventElapsedTime(&ms[i], ev_[i], ev_[i + 1]);
      if (e != cudaSuccess) return e;
    }
    UpdateStageTimes t;
    t.upload = ms[0];
    t.gather = ms[1];
    t.innovation_cov = ms[2];
    t.factor = ms[3];
    t.host_check1 = ms[4];
    t.trsm = ms[5];
    t.solve = ms[6];
    t.host_check2 = ms[7];
    t.rank_update = ms[8];
    recordUpdateStageTimes(t);
    return cudaSuccess;
  }

  // The workspace holds P / A (n x 3m) during an update; it grows when an
  // update has more than work_cols_ / 3 blocks.
  cudaError_t ensureWork(int cols) {
    if (cols <= work_cols_) return cudaSuccess;
    const cudaError_t e = work_.ensure(ld_ * static_cast<std::size_t>(cols));
    if (e == cudaSuccess) work_cols_ = cols;
    return e;
  }

  // Second workspace and trtri buffers of Solve::kInverse, grown on demand.
  cudaError_t ensureInverseWork(int dim) {
    cudaError_t e = work2_.ensure(ld_ * static_cast<std::size_t>(std::max(dim, work_cols_)));
    if (e == cudaSuccess) e = y2_.ensure(static_cast<std::size_t>(dim));
    if (e != cudaSuccess) return e;
    std::size_t dev = 0, host = 0;
    if (trtriBufferSize<T>(solver_, dim, S_.get(), &dev, &host) != CUSOLVER_STATUS_SUCCESS)
      return cudaErrorInvalidValue;
    e = trtri_dev_.ensure(std::max<std::size_t>(dev, 1));
    if (host > trtri_host_.size()) trtri_host_.resize(host);
    return e;
  }

  const int cap_, D_, device_;
  const std::size_t ld_;
  const CudaRankUpdate rank_;  // kAuto: autoRankUpdate(n) at each update
  const CudaSolve solve_;      // kAuto: autoSolveByInverse(n) at each update
  const bool stage_times_;
  int K_ = 0;
  int work_cols_ = 0;
  cudaEvent_t ev_[kEvCount] = {};
  cudaStream_t stream_ = nullptr;
  cublasHandle_t blas_ = nullptr;
  cusolverDnHandle_t solver_ = nullptr;
  DeviceBuffer<T> C_, work_, S_, y_, dx_, H_, R_;
  InnovationFactor<T> factor_;
  // Solve::kInverse: A = P L^-T lands in work2_ (n x 3m), y = L^-1 z in y2_.
  DeviceBuffer<T> work2_, y2_;
  DeviceBuffer<uint8_t> trtri_dev_;
  std::vector<uint8_t> trtri_host_;
  DeviceBuffer<uint8_t> desc_, desc_tmp_;
  // Scratch of const read-back / association calls.
  mutable DeviceBuffer<int> slots_, ints_;
  mutable DeviceBuffer<uint8_t> queries_;
  mutable DeviceBuffer<double> small_;
  DeviceBuffer<double> pose_mats_;  // F and Q of predict(), row-major
  mutable std::string last_error_;
};

}  // namespace cuda
}  // namespace hapi_eskf
