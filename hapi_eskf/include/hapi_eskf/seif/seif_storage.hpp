// The sparse extended information filter (docs/DESIGN.md "SEIF") as a
// storage behind the ES-EKF's host logic: it keeps the error state's
// information matrix Omega and vector xi (block-sparse,
// information_matrix.hpp) instead of the covariance C, and fulfils the same
// CovarianceBackend contract (predict, marginals, update returning the
// correction dx, add, remove), so association, bookkeeping, relocalisation,
// the motion models and the nominal state are the ES-EKF's own
// (backend_algorithm seif = Eskf + this storage).
//
//  * motion update: touches the pose and the active landmarks only;
//  * measurement update: Omega += H^T R^-1 H, xi += H^T R^-1 nu (the observed
//    landmarks become active);
//  * state recovery (amortised): exact solve over the pose and the active
//    landmarks with the passive ones held at their means, then one
//    coordinate-descent step on seif_recovery_landmarks passive landmarks
//    (round robin); every seif_exact_recovery_period-th update the whole
//    system is solved;
//  * sparsification: after every update and addition, links from the pose
//    to all but the seif_max_active_landmarks most recently seen landmarks
//    are removed (Thrun et al., Probabilistic Robotics, 12.4.3);
//  * covariances (gating marginals, pose and map read-back): the inverse of
//    the pose + active block, a passive landmark conditioned on the other
//    passive ones (exact when nothing is sparsified).
// With seif_max_active_landmarks 0 nothing is sparsified, every landmark
// stays active, and the SEIF equals the ES-EKF to rounding.
#pragma once

#include "hapi_eskf/backend/descriptor_pool.hpp"
#include "hapi_eskf/backend/slam_backend.hpp"
#include "hapi_eskf/covariance/covariance_backend.hpp"
#include "hapi_eskf/seif/information_matrix.hpp"

#include <memory>
#include <string>

namespace hapi_eskf {
namespace seif {

class SeifStorage final : public CovarianceBackend {
 public:
  SeifStorage(int capacity, int descriptor_length, int pose_dim, const EskfSettings& settings);

  const char* name() const override { return "seif"; }
  int capacity() const override { return capacity_; }
  int numLandmarks() const override { return omega_.numLandmarks(); }
  int descriptorLength() const override { return descriptors_.length(); }
  std::size_t memoryBytes() const override { return omega_.memoryBytes() + descriptors_.memoryBytes(); }

  PoseMat poseCovariance() const override;
  std::vector<Mat3> landmarkCovariances() const override;
  Eigen::MatrixXd denseCovariance() const override;  // exact inverse of Omega, O(n^3)
  std::vector<uint8_t> descriptors() const override { return descriptors_.bytes(); }

  int numActive() const { return static_cast<int>(omega_.active().size()); }
  const InformationMatrix& information() const { return omega_; }

 protected:
  Status doReset(const PoseMat& C_pose) override;
  Status doPredict(const PoseMat& F, const PoseMat& Q) override;
  Status doMarginals(const std::vector<int>& slots, std::vector<Mat9>* out) const override;
  Status doUpdate(const std::vector<MeasurementBlock>& blocks, Eigen::VectorXd* dx, double* nis) override;
  Status doAddLandmarks(const std::vector<NewLandmarkBlock>& blocks) override;
  Status doRemoveLandmarks(const std::vector<int>& slots) override;
  Status doMatchDescriptors(const uint8_t* queries, int n_query, std::vector<DescriptorMatch>* out) const override;

 private:
  // Sigma_D = (Omega over the pose and the active landmarks)^-1, cached
  // until Omega changes.
  struct LocalCovariance {
    bool valid = false, ok = false;
    Eigen::MatrixXd sigma;
    std::vector<int> local_row;  // per slot: its first row in sigma, or -1 (passive)
  };
  const LocalCovariance& local() const;
  // Covariances of [dp, dtheta, dm_slot] (pose rows: the first 6) for the
  // slots; ok[i] = 0 where one could not be formed (not PD, not finite).
  void slotCovariances(const std::vector<int>& slots, std::vector<Mat9>* out, std::vector<char>* ok) const;
  void recoverPassive(const std::vector<char>& solved, Eigen::VectorXd* dx);
  void sparsify();
  void touched() { cache_.valid = false; }

  int capacity_;
  EskfSettings settings_;
  InformationMatrix omega_;
  DescriptorPool descriptors_;
  std::vector<long> recency_;  // per slot: tick of the last update or addition that linked it to the pose
  long tick_ = 0;
  int cursor_ = 0;             // round robin of the passive recovery
  long updates_ = 0;
  mutable LocalCovariance cache_;
};

// The storage for backend_algorithm seif: capacity settings.max_landmarks,
// the pose block of settings.motion_model; nullptr with *error otherwise.
std::unique_ptr<CovarianceBackend> makeSeifStorage(const EskfSettings& settings, int descriptor_length,
                                                   std::string* error);

// The SEIF's maker (backend/slam_backend_maker.hpp): backend_algorithm seif,
// the ES-EKF's host logic over this information-form storage.
std::unique_ptr<SlamBackend> makeSeifBackend(const EskfSettings& settings, int descriptor_length,
                                             const CameraExtrinsic& extrinsic, std::string* error);

}  // namespace seif
}  // namespace hapi_eskf
