// Data association of one frame against the landmark pool (docs/DESIGN.md "Gate
// each association"): descriptor best/second-best with a Hamming threshold and
// a ratio test, then a chi^2(3) Mahalanobis gate with S_j = H_j M_j H_j^T + C_z
// built from the back end's 9x9 marginals, then one measurement per landmark
// (the one with the smallest Mahalanobis distance wins). Shared by every back
// end: each provides descriptors and marginals as an AssociationSource.
#pragma once

#include "hapi_eskf/backend/association_settings.hpp"
#include "hapi_eskf/backend/association_source.hpp"
#include "hapi_eskf/status.hpp"
#include "hapi_eskf/types.hpp"

#include <vector>

namespace hapi_eskf {

struct Association {
  // Per measurement of the frame: the associated slot, or -1.
  std::vector<int> slot;
  // Per measurement: squared Mahalanobis distance of the accepted association (else 0).
  std::vector<double> d2;
  // Per measurement: true when it may start a new landmark, i.e. no pool
  // descriptor is within max_hamming of it. A measurement that resembles a
  // pool landmark but was not associated (ratio test, gate, conflict) is not
  // added: a second copy of a landmark would make the ratio test ambiguous for
  // both copies from then on, and each later observation would add another.
  std::vector<char> may_add;
  int n_candidates = 0;  // descriptor matches (threshold + ratio test) before gating
  int n_gated_out = 0;   // rejected by the Mahalanobis gate (or S_j not PD) or as RANSAC outliers
  int n_ransac_out = 0;  // of those: off the best rigid fit (EskfSettings::ransac_iterations)
  int n_conflicts = 0;   // dropped because another measurement took the same landmark
  // RANSAC rigid fit world <- camera of the candidates (X ~ R Z + t), i.e. the
  // camera pose (q = R, p = t) supported by the map alone, independent of the
  // predicted pose; fit_inliers = 0 when RANSAC did not run or decided nothing.
  int fit_inliers = 0;
  Mat3 fit_R = Mat3::Identity();
  Vec3 fit_t = Vec3::Zero();
  // Of the fit's inliers, those the Mahalanobis gate around the predicted
  // pose rejected: the map agrees with itself on a pose the prediction does
  // not allow (scene_motion_monitor.hpp).
  int n_fit_inliers_gated_out = 0;
};

// `positions` are the landmark positions in slot order (size numLandmarks()).
// Inliers of a RANSAC rigid fit X_i ~ R Z_i + t (world landmark <- camera
// point), Mahalanobis with W_i + R Cz_i R^T against chi2; empty = undecided.
// R_out/t_out (optional) receive the fit that selected the returned inliers.
std::vector<char> ransacRigidInliers(const std::vector<Vec3>& X, const std::vector<Vec3>& Z,
                                     const std::vector<Mat3>& W, const std::vector<Mat3>& Cz, int iterations,
                                     double chi2, Mat3* R_out = nullptr, Vec3* t_out = nullptr);

// `pose` is the camera's; camera_jacobian maps the state's [dp, dtheta] to
// the camera's (MotionModel::cameraJacobian; the identity for the camera
// models), so the gate uses the same measurement Jacobian as the update.
Status associate(const StereoFrame& frame, const PoseState& pose, const Mat6& camera_jacobian,
                 const std::vector<Vec3>& positions, const AssociationSource& source, const AssociationSettings& settings,
                 Association* out);

}  // namespace hapi_eskf
