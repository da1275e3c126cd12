// The SEIF storage (seif_storage.hpp; equations: docs/DESIGN.md "SEIF").
// Every operation gathers a dense block of Omega over the pose and a list of
// slots, works on it, and scatters it back only when everything succeeded, so
// an error return leaves Omega and xi unchanged.
#include "hapi_eskf/seif/seif_storage.hpp"

#include "hapi_eskf/backend/removal_plan.hpp"
#include "hapi_eskf/eskf/frame_error_block.hpp"
#include "hapi_eskf/eskf/motion_model.hpp"
#include "hapi_eskf/seif/sparsification.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include <algorithm>
#include <numeric>

namespace hapi_eskf {
namespace seif {

using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

// Rows of block b (3 per slot) after the pose rows.
int blockRow(int P, int b) { return P + 3 * b; }

}  // namespace

SeifStorage::SeifStorage(int capacity, int descriptor_length, int pose_dim, const EskfSettings& settings)
    : CovarianceBackend(pose_dim), capacity_(capacity), settings_(settings), descriptors_(descriptor_length) {
  omega_.reset(PoseMat::Identity(pose_dim, pose_dim));
}

Status SeifStorage::doReset(const PoseMat& C_pose) {
  const MatrixXd C = C_pose;
  const Eigen::LLT<MatrixXd> llt(C);
  if (llt.info() != Eigen::Success) return Status::kNotPositiveDefinite;
  const MatrixXd inv = llt.solve(MatrixXd::Identity(C_pose.rows(), C_pose.cols()));
  omega_.reset(PoseMat(0.5 * (inv + inv.transpose())));
  descriptors_.clear();
  recency_.clear();
  tick_ = 0;
  cursor_ = 0;
  updates_ = 0;
  touched();
  return Status::kOk;
}

// Motion update (docs/DESIGN.md "SEIF"): Psi = A^-T Omega A^-1 with
// A = diag(F, I), then Omega' = Psi - Psi_.x (I + Q Psi_xx)^-1 Q Psi_x.,
// xi' = xi_Psi - Psi_.x (I + Q Psi_xx)^-1 Q xi_Psi,x. Psi_.x is zero outside
// the pose and the active landmarks, so only that block changes.
Status SeifStorage::doPredict(const PoseMat& F, const PoseMat& Q) {
  const int P = poseDim();
  const std::vector<int> A = omega_.active();
  const MatrixXd Fd = F;
  const Eigen::PartialPivLU<MatrixXd> lu(Fd);
  const MatrixXd Finv = lu.inverse();
  if (!Finv.allFinite()) return Status::kNonFinite;
  MatrixXd Psi = omega_.gather(A);
  VectorXd xi = omega_.gatherXi(A);
  Psi.topRows(P) = (Finv.transpose() * Psi.topRows(P)).eval();
  Psi.leftCols(P) = (Psi.leftCols(P) * Finv).eval();
  xi.head(P) = (Finv.transpose() * xi.head(P)).eval();
  const MatrixXd Qd = Q;
  const MatrixXd G = (MatrixXd::Identity(P, P) + Qd * Psi.topLeftCorner(P, P)).partialPivLu().solve(Qd);
  const MatrixXd Px = Psi.leftCols(P);
  MatrixXd Om = Psi - Px * G * Px.transpose();
  const VectorXd xi_new = xi - Px * (G * xi.head(P));
  if (!Om.allFinite() || !xi_new.allFinite()) return Status::kNonFinite;
  omega_.scatter(A, Om);
  omega_.scatterXi(A, xi_new);
  touched();
  return Status::kOk;
}

const SeifStorage::LocalCovariance& SeifStorage::local() const {
  if (cache_.valid) return cache_;
  const int P = poseDim();
  const std::vector<int>& A = omega_.active();
  cache_.local_row.assign(numLandmarks(), -1);
  for (std::size_t i = 0; i < A.size(); ++i) cache_.local_row[A[i]] = blockRow(P, static_cast<int>(i));
  const MatrixXd Om = omega_.gather(A);
  const Eigen::LLT<MatrixXd> llt(Om);
  cache_.ok = llt.info() == Eigen::Success;
  cache_.sigma = cache_.ok ? MatrixXd(llt.solve(MatrixXd::Identity(Om.rows(), Om.cols()))) : MatrixXd();
  cache_.ok = cache_.ok && cache_.sigma.allFinite();
  cache_.valid = true;
  return cache_;
}

// Active slot: read from Sigma_D. Passive slot k, conditioned on the other
// passive landmarks: with u = Sigma_D Omega_Dk, Sigma_kk = (Omega_kk -
// Omega_kD u)^-1, Sigma_Dk = -u Sigma_kk, Sigma_DD|k = Sigma_D + u Sigma_kk u^T.
// The u of all passive slots are one product Sigma_D [Omega_Dk ...] (a
// full pool gates ~200 candidates per frame, mostly passive).
void SeifStorage::slotCovariances(const std::vector<int>& slots, std::vector<Mat9>* out,
                                  std::vector<char>* ok) const {
  const LocalCovariance& L = local();
  ok->assign(slots.size(), 0);
  if (!L.ok) return;
  const int D = static_cast<int>(L.sigma.rows());
  std::vector<std::size_t> passive;
  for (std::size_t i = 0; i < slots.size(); ++i)
    if (L.local_row[slots[i]] < 0) passive.push_back(i);
  MatrixXd Bd = MatrixXd::Zero(D, 3 * static_cast<Eigen::Index>(passive.size()));  // [Omega_Dk ...]
  for (std::size_t u = 0; u < passive.size(); ++u)
    omega_.forEachLinkAmong(slots[passive[u]], omega_.active(), [&](int j, const Mat3& B) {
      const int rj = L.local_row[j];
      if (rj >= 0) Bd.block<3, 3>(rj, 3 * u) = B.transpose();  // Omega_jk = B^T
    });
  const MatrixXd U = L.sigma * Bd;
  std::size_t u = 0;
  for (std::size_t i = 0; i < slots.size(); ++i) {
    Mat9& M = (*out)[i];
    const int r = L.local_row[slots[i]];
    if (r >= 0) {
      M.topLeftCorner<6, 6>() = L.sigma.topLeftCorner(6, 6);
      M.block<6, 3>(0, 6) = L.sigma.block(0, r, 6, 3);
      M.block<3, 6>(6, 0) = L.sigma.block(r, 0, 3, 6);
      M.block<3, 3>(6, 6) = L.sigma.block(r, r, 3, 3);
      (*ok)[i] = 1;
      continue;
    }
    const Mat3 s = omega_.diagonal(slots[i]) - Bd.middleCols<3>(3 * u).transpose() * U.middleCols<3>(3 * u);
    const Eigen::Matrix<double, 6, 3> ux = U.block<6, 3>(0, 3 * u);
    ++u;
    const Eigen::LLT<Mat3> llt(0.5 * (s + s.transpose()));
    if (llt.info() != Eigen::Success) continue;
    const Mat3 Skk = llt.solve(Mat3::Identity());
    M.topLeftCorner<6, 6>() = L.sigma.topLeftCorner(6, 6) + ux * Skk * ux.transpose();
    M.block<6, 3>(0, 6) = -ux * Skk;
    M.block<3, 6>(6, 0) = M.block<6, 3>(0, 6).transpose();
    M.block<3, 3>(6, 6) = Skk;
    (*ok)[i] = M.allFinite() ? 1 : 0;
  }
}

Status SeifStorage::doMarginals(const std::vector<int>& slots, std::vector<Mat9>* out) const {
  std::vector<char> ok;
  slotCovariances(slots, out, &ok);
  for (char o : ok)
    if (!o) return Status::kNotPositiveDefinite;
  return Status::kOk;
}

PoseMat SeifStorage::poseCovariance() const {
  const LocalCovariance& L = local();
  const int P = poseDim();
  return L.ok ? PoseMat(L.sigma.topLeftCorner(P, P)) : PoseMat::Zero(P, P);
}

std::vector<Mat3> SeifStorage::landmarkCovariances() const {
  std::vector<int> all(numLandmarks());
  std::iota(all.begin(), all.end(), 0);
  std::vector<Mat9> M(all.size());
  std::vector<char> ok;
  slotCovariances(all, &M, &ok);
  std::vector<Mat3> out(numLandmarks(), Mat3::Zero());
  for (int k = 0; k < numLandmarks(); ++k)
    if (ok[k]) out[k] = M[k].block<3, 3>(6, 6);
  return out;
}

MatrixXd SeifStorage::denseCovariance() const {
  std::vector<int> all(numLandmarks());
  std::iota(all.begin(), all.end(), 0);
  const MatrixXd Om = omega_.gather(all);
  return Om.llt().solve(MatrixXd::Identity(Om.rows(), Om.cols()));
}

// Measurement update and recovery (docs/DESIGN.md "SEIF"): on the pose, the
// active and the observed landmarks (every landmark every
// seif_exact_recovery_period-th update), Omega += H^T R^-1 H,
// xi += b = H^T R^-1 nu, then dx = Omega_LL^-1 xi_L, xi <- xi - Omega dx.
// NIS = nu^T R^-1 nu - b^T Omega_LL^-1 b (matrix inversion lemma; exact
// when L is everything).
Status SeifStorage::doUpdate(const std::vector<MeasurementBlock>& blocks, VectorXd* dx, double* nis) {
  const int P = poseDim(), K = numLandmarks();
  const bool exact = settings_.seif.exact_recovery_period > 0 &&
                     (updates_ + 1) % settings_.seif.exact_recovery_period == 0;
  std::vector<int> L;
  std::vector<char> in_L(K, 0);
  std::vector<int> row(K, -1);
  auto include = [&](int k) {
    if (in_L[k]) return;
    in_L[k] = 1;
    row[k] = blockRow(P, static_cast<int>(L.size()));
    L.push_back(k);
  };
  if (exact) {
    for (int k = 0; k < K; ++k) include(k);
  } else {
    for (int k : omega_.active()) include(k);
    for (const MeasurementBlock& b : blocks) include(b.slot);
  }
  MatrixXd Om = omega_.gather(L);
  VectorXd xi = omega_.gatherXi(L);
  VectorXd rhs = VectorXd::Zero(Om.rows());
  double nu_w_nu = 0.0;
  for (const MeasurementBlock& b : blocks) {
    const Eigen::LLT<Mat3> llt(b.R);
    if (llt.info() != Eigen::Success) return Status::kNotPositiveDefinite;
    const Mat3 W = llt.solve(Mat3::Identity());
    const int r = row[b.slot];
    const Mat36 WHp = W * b.H_pose;
    const Mat3 WHm = W * b.H_landmark;
    Om.topLeftCorner<6, 6>() += b.H_pose.transpose() * WHp;
    Om.block<6, 3>(0, r) += b.H_pose.transpose() * WHm;
    Om.block<3, 6>(r, 0) += b.H_landmark.transpose() * WHp;
    Om.block<3, 3>(r, r) += b.H_landmark.transpose() * WHm;
    const Vec3 Wnu = W * b.innovation;
    rhs.head<6>() += b.H_pose.transpose() * Wnu;
    rhs.segment<3>(r) += b.H_landmark.transpose() * Wnu;
    nu_w_nu += b.innovation.dot(Wnu);
  }
  xi += rhs;
  const Eigen::LLT<MatrixXd> llt(Om);
  if (llt.info() != Eigen::Success) return Status::kNotPositiveDefinite;
  const VectorXd y = llt.solve(rhs);
  const VectorXd d = llt.solve(xi);
  const double nis_value = nu_w_nu - rhs.dot(y);
  if (!d.allFinite() || !std::isfinite(nis_value)) return Status::kNonFinite;

  // Commit: Omega, the residual xi - Omega dx (zero on L up to rounding, and
  // moved onto the passive neighbours of L).
  omega_.scatter(L, Om);
  omega_.scatterXi(L, xi - Om * d);
  for (std::size_t i = 0; i < L.size(); ++i) {
    const Vec3 da = d.segment<3>(blockRow(P, static_cast<int>(i)));
    for (const auto& [j, B] : omega_.links(L[i]))
      if (!in_L[j]) omega_.addXiLandmark(j, -B.transpose() * da);  // Omega_ja = B^T
  }
  dx->setZero(stateDim(K, P));
  dx->head(P) = d.head(P);
  for (std::size_t i = 0; i < L.size(); ++i)
    dx->segment<3>(landmarkRow(L[i], P)) = d.segment<3>(blockRow(P, static_cast<int>(i)));
  ++updates_;
  ++tick_;
  for (const MeasurementBlock& b : blocks) recency_[b.slot] = tick_;
  recoverPassive(in_L, dx);
  sparsify();
  touched();
  if (nis) *nis = nis_value;
  return Status::kOk;
}

// One coordinate-descent step dm_k = Omega_kk^-1 xi_k on up to
// seif_recovery_landmarks passive landmarks, round robin over the pool.
void SeifStorage::recoverPassive(const std::vector<char>& solved, VectorXd* dx) {
  const int K = numLandmarks(), P = poseDim();
  int done = 0;
  for (int step = 0; step < K && done < settings_.seif.recovery_landmarks; ++step) {
    const int k = cursor_;
    cursor_ = (cursor_ + 1) % K;
    if (solved[k] || omega_.isActive(k)) continue;
    ++done;
    const Eigen::LLT<Mat3> llt(omega_.diagonal(k));
    if (llt.info() != Eigen::Success) continue;
    const Vec3 dk = llt.solve(omega_.xiLandmark(k));
    if (!dk.allFinite()) continue;
    omega_.setXiLandmark(k, Vec3::Zero());
    for (const auto& [j, B] : omega_.links(k)) omega_.addXiLandmark(j, -B.transpose() * dk);
    dx->segment<3>(landmarkRow(k, P)) += dk;
  }
}

// Sparsification (sparsification.hpp): m0 = the active landmarks beyond the
// bound (least recently linked), m+ = the others; removes the pose-m0 links;
// xi is kept (the error mean is ~0 right after the recovery).
void SeifStorage::sparsify() {
  const int bound = settings_.seif.max_active_landmarks;
  std::vector<int> A = omega_.active();
  if (bound <= 0 || static_cast<int>(A.size()) <= bound) return;
  std::stable_sort(A.begin(), A.end(), [&](int a, int b) {
    if (recency_[a] != recency_[b]) return recency_[a] > recency_[b];
    return a < b;
  });
  const MatrixXd Om = omega_.gather(A);
  MatrixXd sparse;
  if (!sparsifiedInformation(Om, poseDim(), 3 * bound, &sparse)) return;  // keep the denser, valid Omega
  omega_.scatter(A, sparse);
}

// New landmarks (docs/DESIGN.md "SEIF"): m_i = g(x, z_i), dm_i = G_i dx +
// G_z dz, N_i = G_z C_z G_z^T: Omega_xx += sum G_i^T N_i^-1 G_i,
// Omega_x,i = -G_i^T N_i^-1, Omega_ii = N_i^-1, xi_i = 0.
Status SeifStorage::doAddLandmarks(const std::vector<NewLandmarkBlock>& blocks) {
  const int P = poseDim(), K0 = numLandmarks(), M = static_cast<int>(blocks.size());
  std::vector<Mat3> Ninv(M);
  for (int i = 0; i < M; ++i) {
    const Mat3 N = blocks[i].G_z * blocks[i].Cz * blocks[i].G_z.transpose();
    const Eigen::LLT<Mat3> llt(0.5 * (N + N.transpose()));
    if (llt.info() != Eigen::Success) return Status::kNotPositiveDefinite;
    Ninv[i] = llt.solve(Mat3::Identity());
    if (!Ninv[i].allFinite()) return Status::kNonFinite;
  }
  std::vector<int> L(M);
  for (int i = 0; i < M; ++i) L[i] = omega_.appendLandmark();
  MatrixXd Om = omega_.gather(L);
  ++tick_;
  for (int i = 0; i < M; ++i) {
    const int r = blockRow(P, i);
    const Eigen::Matrix<double, 6, 3> GtN = blocks[i].G_pose.transpose() * Ninv[i];
    Om.topLeftCorner<6, 6>() += GtN * blocks[i].G_pose;
    Om.block<6, 3>(0, r) = -GtN;
    Om.block<3, 6>(r, 0) = -GtN.transpose();
    Om.block<3, 3>(r, r) = Ninv[i];
    descriptors_.append(blocks[i].descriptor);
    recency_.push_back(tick_);
  }
  omega_.scatter(L, Om);
  (void)K0;
  sparsify();
  touched();
  return Status::kOk;
}

// Removal = marginalisation of each slot k over its neighbours N (pose
// included when k is active): Omega_NN -= Omega_Nk Omega_kk^-1 Omega_kN, xi
// likewise; then the pool's slot plan (removal_plan.hpp). Sparsified
// (seif_max_active_landmarks > 0), the fill-in is kept only among the pose
// and the active neighbours; a passive neighbour j keeps its own block of
// the Schur complement (Omega_jj -= Omega_jk Omega_kk^-1 Omega_kj) but no new
// links: exact marginalisation would join all of k's neighbours, and with a
// full pool (removals every frame) the landmark graph would grow dense and
// each removal cost O(K^2) (docs/DESIGN.md "SEIF").
Status SeifStorage::doRemoveLandmarks(const std::vector<int>& slots) {
  const int K = numLandmarks();
  const bool exact = settings_.seif.max_active_landmarks <= 0;
  for (int k : slots) {
    std::vector<int> N, passive;
    for (const auto& [j, B] : omega_.links(k)) (exact || omega_.isActive(j) ? N : passive).push_back(j);
    std::sort(N.begin(), N.end());
    std::sort(passive.begin(), passive.end());
    std::vector<int> Lk = N;
    Lk.push_back(k);
    const MatrixXd Om = omega_.gather(Lk);
    const VectorXd xi = omega_.gatherXi(Lk);
    const int n = static_cast<int>(Om.rows()) - 3;
    const Eigen::LLT<Mat3> llt(Mat3(Om.block<3, 3>(n, n)));
    MatrixXd Rest = Om.topLeftCorner(n, n);
    VectorXd xi_rest = xi.head(n);
    std::vector<std::pair<int, Mat3>> diag_updates;
    std::vector<std::pair<int, Vec3>> xi_updates;
    if (llt.info() == Eigen::Success) {
      const MatrixXd Onk = Om.block(0, n, n, 3);
      Rest.noalias() -= Onk * llt.solve(Onk.transpose());
      const Vec3 w = llt.solve(Vec3(xi.tail<3>()));
      xi_rest.noalias() -= Onk * w;
      for (int j : passive) {
        const Mat3 Ojk = omega_.links(k).at(j).transpose();  // Omega_jk
        diag_updates.emplace_back(j, -Ojk * llt.solve(Ojk.transpose()));
        xi_updates.emplace_back(j, -Ojk * w);
      }
    }
    omega_.dropLandmark(k);
    omega_.scatter(N, Rest);
    omega_.scatterXi(N, xi_rest);
    for (const auto& [j, d] : diag_updates) omega_.addDiagonal(j, d);
    for (const auto& [j, d] : xi_updates) omega_.addXiLandmark(j, d);
  }
  for (const SlotMove& mv : tailFillMoves(K, slots)) {
    omega_.moveLandmark(mv.from, mv.to);
    recency_[mv.to] = recency_[mv.from];
  }
  const int K_new = K - static_cast<int>(slots.size());
  omega_.truncate(K_new);
  recency_.resize(K_new);
  descriptors_.remove(slots);
  cursor_ = K_new > 0 ? cursor_ % K_new : 0;
  touched();
  return Status::kOk;
}

Status SeifStorage::doMatchDescriptors(const uint8_t* queries, int n_query, std::vector<DescriptorMatch>* out) const {
  matchHamming(queries, n_query, descriptors_.bytes().data(), numLandmarks(), descriptors_.length(), out);
  return Status::kOk;
}

std::unique_ptr<CovarianceBackend> makeSeifStorage(const EskfSettings& s, int descriptor_length, std::string* error) {
  if (descriptor_length < 0) {
    if (error) *error = "descriptor_length must be >= 0";
    return nullptr;
  }
  return std::make_unique<SeifStorage>(s.max_landmarks, descriptor_length, filterPoseDim(s), s);
}

}  // namespace seif
}  // namespace hapi_eskf
