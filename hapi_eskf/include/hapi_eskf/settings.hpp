// Filter settings. Field names are the ROS parameter names used by the
// nodelet (config/eskf.yaml), so a user sees one vocabulary everywhere.
#pragma once

#include <string>

namespace hapi_eskf {

enum class BackendKind { kCpu, kCuda };
enum class Precision { kFp64, kFp32 };  // storage/compute precision of C (CUDA backend)

// Smallest RANSAC inlier set that may relocalise the pose (relocalise_gap):
// 12 pairs pin 6 dof with a wide margin against a chance fit of wrong matches.
constexpr int kRelocaliseMinInliers = 6;
// How long after an outage frames without such a fit are held back
// (prediction only: updating or adding landmarks at an unknown pose would
// corrupt the map) before the filter carries on without relocalising (the
// camera may look at unmapped ground only) [s].
constexpr double kRelocaliseWaitS = 2.0;

struct EskfSettings {
  // --- pool and per-iteration sizes (issue 3) ---
  int max_landmarks = 2000;          // K_max: capacity of the landmark pool
  int max_new_landmarks = 20;        // landmarks initialised per iteration
  int bootstrap_landmarks = 0;       // landmarks initialised by a frame that finds the pool
                                     // empty (start, reset): one well-spread base map instead
                                     // of max_new_landmarks per frame over the first frames.
                                     // 0 = max_new_landmarks (no special case)
  int max_update_landmarks = 200;    // old landmarks used per update (L)
  int max_frame_measurements = 4000;  // a frame with more measurements is rejected
                                      // (kCapacityExceeded): bounds the per-frame work
  double full_pool_add_fraction = 0.5;  // when the pool is full: evict so this fraction
                                        // of max_new_landmarks can still be added
  BackendKind backend = BackendKind::kCpu;
  Precision precision = Precision::kFp64;
  int cuda_device = 0;

  // --- association (DESIGN.md "Gate each association") ---
  int max_hamming = 64;          // descriptor distance accepted as a candidate
  double match_ratio = 0.8;      // best / second-best Hamming ratio test
  double gate_chi2 = 11.345;     // Mahalanobis gate, chi^2(3) at 99 %
  // Geometric consistency of the descriptor candidates before gating: a
  // RANSAC rigid fit world <- camera on the 3D-3D pairs (landmark, stereo
  // point), 3-point samples, this many hypotheses (deterministic seed); pairs
  // off the best fit (Mahalanobis > gate_chi2 with the landmark's marginal
  // plus R C_z R^T) are rejected. Catches wrong descriptor matches that the
  // per-candidate gate lets through when the predicted pose is uncertain
  // (large inter-frame motion). 0 = off; used only with >= 6 candidates.
  int ransac_iterations = 0;
  // Relocalisation after an outage [s]: when the previous frame is older than
  // this (front end restarted, link down), the motion model is not trusted:
  // the velocity mean is zeroed before the prediction (the covariance still
  // grows by the process noise), and the pose mean is moved to the RANSAC
  // rigid fit of the frame against the map (>= kRelocaliseMinInliers pairs)
  // before gating and the update, so the update linearises at a pose the map
  // supports instead of at a long extrapolation (rotation errors of that size
  // are far outside the EKF's linear range and made the filter run away).
  // Only the means move; the covariance stays the conservative predicted one.
  // Needs ransac_iterations > 0 for the pose part; 0 = off.
  double relocalise_gap = 0.0;
  // --- measurement model ---
  // Re-detection noise [rad, 1 sigma] of a keypoint from frame to frame,
  // perpendicular to the viewing ray: the front end's covariance describes one
  // stereo pair (left/right refined against each other), but the detector does
  // not find exactly the same physical point in the next frame. Added to every
  // C_z as (sigma * |z|)^2 (I - r r^T), r = z / |z|. 0 = trust C_z as it is.
  double measurement_angular_sigma = 0.0;

  // --- motion model (DESIGN.md "Predict") ---
  double velocity_damping = 1.0;          // Gamma: v <- Gamma v per second (1 = none)
  double angular_velocity_damping = 1.0;  // Lambda: w <- Lambda w per second
  double sigma_acceleration = 0.5;        // [m/s^2/sqrt(Hz)] random-walk on v
  double sigma_angular_acceleration = 0.5;  // [rad/s^2/sqrt(Hz)] random-walk on w

  // --- initial uncertainty of the first pose (the world frame is the first camera) ---
  double initial_sigma_position = 1e-3;   // [m]
  double initial_sigma_orientation = 1e-3;  // [rad]
  double initial_sigma_velocity = 0.2;    // [m/s]
  double initial_sigma_angular_velocity = 0.5;  // [rad/s]

  // Empty when valid, else a message naming the offending field and its range.
  std::string validate() const;
};

const char* toString(BackendKind b);
const char* toString(Precision p);
// Parses "cpu"/"cuda" and "fp64"/"fp32"; false on anything else.
bool parseBackendKind(const std::string& s, BackendKind* out);
bool parsePrecision(const std::string& s, Precision* out);

}  // namespace hapi_eskf
