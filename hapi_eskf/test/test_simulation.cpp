// Simulated scenario: known trajectory, random points, noisy stereo
// 3D measurements with descriptors. Checks pose accuracy and filter
// consistency: the average NEES of the 6-dof pose over >= 30 Monte-Carlo runs
// lies in the 95 % chi^2 interval.
#include "basic_settings.hpp"
#include "hapi_eskf/eskf/eskf.hpp"
#include "hapi_eskf/random_draw.hpp"
#include "sim_scenario.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace hapi_eskf {
namespace {

// chi^2 quantile by the Wilson-Hilferty approximation (relative error < 1e-3 for k >= 30).
double chi2Quantile(double k, double z) {
  const double a = 2.0 / (9.0 * k);
  return k * std::pow(1.0 - a + z * std::sqrt(a), 3.0);
}

EskfSettings scenarioSettings() {
  // C_z is the simulation's true measurement noise: no re-detection term.
  EskfSettings s = testing_settings::basicFilter();
  s.max_landmarks = 150;
  s.max_new_landmarks = 20;
  s.max_update_landmarks = 30;
  // The truth is driven by exactly these densities (sim::truthStep), so the
  // filter's process noise is the honest one.
  s.sigma_acceleration = 0.2;
  s.sigma_angular_acceleration = 0.05;
  // The world frame is the first camera (settings.hpp), so its pose is known
  // up to round-off. With a loose prior on it (e.g. 1e-3) the filter gains
  // spurious information along the unobservable global rotation through
  // re-linearisation (the known EKF-SLAM inconsistency, Huang et al. 2008)
  // and the orientation NEES drifts to ~1.6x its nominal value over 60 frames.
  s.initial_sigma_position = 1e-6;
  s.initial_sigma_orientation = 1e-6;
  s.initial_sigma_velocity = 0.1;
  s.initial_sigma_angular_velocity = 0.05;
  return s;
}

struct RunResult {
  std::vector<double> nees;       // per frame
  std::vector<double> pos_err2;   // per frame, |p - p^|^2
  std::vector<double> rot_err2;   // per frame, |dtheta|^2
  int updated = 0, gated_out = 0, candidates = 0, frames = 0, added = 0, removed = 0;
};

RunResult runOnce(unsigned seed, int n_frames, const EskfSettings& s) {
  std::mt19937 rng(seed);
  const sim::StereoRig rig;
  // Points all around the start, so every viewing direction the random walk
  // may turn to sees ~100 of them within the rig's depth range.
  const sim::World world = sim::randomWorld(rng, 6000, Vec3(-20, -20, -20), Vec3(20, 20, 20));
  const double dt = 0.1;

  // Truth: forward at 1 m/s, turning at 0.1 rad/s about the camera's y axis, plus random accelerations.
  PoseState truth;
  truth.v = Vec3(0, 0, 1.0);
  truth.w = Vec3(0, 0.1, 0);
  // The initial estimate is drawn from the filter's prior around the truth.
  std::normal_distribution<double> g(0.0, 1.0);
  PoseState init = truth;
  init.p += s.initial_sigma_position * drawVec3(g, rng);
  init.q = truth.q * quatExp(s.initial_sigma_orientation * drawVec3(g, rng));
  init.v += s.initial_sigma_velocity * drawVec3(g, rng);
  init.w += s.initial_sigma_angular_velocity * drawVec3(g, rng);

  Eskf f(s, makeCpuBackend(s.max_landmarks, 32));
  EXPECT_EQ(f.reset(init, 0.0), Status::kOk);
  RunResult r;
  for (int k = 0; k < n_frames; ++k) {
    if (k > 0) truth = sim::truthStep(truth, dt, s, rng);
    const StereoFrame frame = sim::makeFrame(world, truth, rig, k * dt, 4, rng);
    IterationReport rep;
    Status st = f.processFrame(frame, &rep);
    if (frame.measurements.empty()) {  // nothing visible: the documented policy is "no-op", so predict here
      EXPECT_EQ(st, Status::kEmptyInput);
      st = f.predictTo(frame.stamp);
    }
    EXPECT_EQ(st, Status::kOk) << toString(st) << " frame " << k << " n " << frame.measurements.size();
    r.updated += rep.n_updated;
    r.gated_out += rep.n_gated_out;
    r.candidates += rep.n_candidates;
    r.added += rep.n_added;
    r.removed += rep.n_removed;
    ++r.frames;
    const auto e = sim::poseError(truth, f.pose());
    const Eigen::Matrix<double, 6, 6> P = f.poseCovariance().topLeftCorner<6, 6>();
    r.nees.push_back(e.dot(P.ldlt().solve(e)));
    r.pos_err2.push_back(e.head<3>().squaredNorm());
    r.rot_err2.push_back(e.tail<3>().squaredNorm());
  }
  return r;
}

// A regression on one fixed sample (seeds 1000..1029), not a proof of
// consistency: the same 30 runs drawn from other seeds give an average pose
// NEES of 7.74, 7.34, 7.48 and 6.62 (seeds 1000.. with the opposite draw
// order of each vector, 2000.., 3000.., 4000..) against 6.54 here, three of
// five outside the band [4.83, 7.30] (docs/DESIGN.md "Not established").
void checkMonteCarlo(const EskfSettings& s) {
  const int runs = 30, frames = 60;
  std::vector<double> nees_mean(frames, 0.0);
  double pos2 = 0, rot2 = 0, final_pos2 = 0;
  long updated = 0, gated = 0, candidates = 0, added = 0, removed = 0;
  for (int r = 0; r < runs; ++r) {
    const RunResult res = runOnce(1000 + r, frames, s);
    ASSERT_EQ(res.frames, frames);
    for (int k = 0; k < frames; ++k) {
      nees_mean[k] += res.nees[k] / runs;
      pos2 += res.pos_err2[k];
      rot2 += res.rot_err2[k];
    }
    final_pos2 += res.pos_err2.back();
    updated += res.updated;
    gated += res.gated_out;
    candidates += res.candidates;
    added += res.added;
    removed += res.removed;
  }
  // Skip the first frame: it only initialises landmarks (NEES of the prior).
  double avg_nees = 0;
  int inside = 0;
  const double lo = chi2Quantile(6.0 * runs, -1.959964) / runs, hi = chi2Quantile(6.0 * runs, 1.959964) / runs;
  std::printf("mean NEES per frame:");
  for (int k = 0; k < frames; ++k) std::printf(" %.2f", nees_mean[k]);
  std::printf("\n");
  for (int k = 1; k < frames; ++k) {
    avg_nees += nees_mean[k] / (frames - 1);
    inside += (nees_mean[k] >= lo && nees_mean[k] <= hi);
  }
  const double rmse_p = std::sqrt(pos2 / (runs * frames)), rmse_r = std::sqrt(rot2 / (runs * frames));
  std::printf("avg NEES %.3f (95%% interval [%.3f, %.3f]); %d/%d frames inside; RMSE p %.4f m, rot %.5f rad; "
              "final RMSE p %.4f m\n",
              avg_nees, lo, hi, inside, frames - 1, rmse_p, rmse_r, std::sqrt(final_pos2 / runs));
  std::printf("per run: updated %.1f/frame, candidates %.1f/frame, gated out %.2f/frame, added %.1f, removed %.1f\n",
              double(updated) / (runs * frames), double(candidates) / (runs * frames),
              double(gated) / (runs * frames), double(added) / runs, double(removed) / runs);
  EXPECT_GE(avg_nees, lo);
  EXPECT_LE(avg_nees, hi);
  EXPECT_GE(inside, static_cast<int>(0.85 * (frames - 1)));
  // The association must be doing its job (most frames use the full L).
  EXPECT_GT(double(updated) / (runs * frames), 20.0);
  EXPECT_LT(double(gated) / std::max<long>(1, candidates), 0.05);
  EXPECT_GT(removed, 0);  // the pool filled and the removal policy ran
  // Observed: RMSE p 0.017 m, rot 0.0016 rad over 6 m of travel; bounds at ~3x.
  EXPECT_LT(rmse_p, 0.05);
  EXPECT_LT(rmse_r, 0.005);
}

// A regression pin, not a consistency test (checkMonteCarlo says why): the
// NEES band holds on this seed set, not on every one.
TEST(Simulation, PoseAccurateAndNeesPinnedOnSeeds1000To1029) { checkMonteCarlo(scenarioSettings()); }

// The e2e configuration's association and start-up (config/eskf.yaml): the
// RANSAC consistency step must not move the pinned figures out of their
// bounds (it only removes pairs off the best rigid fit, ~1 % of the correct
// ones at chi^2 99 %), and a larger first batch of landmarks must not either.
// The same regression pin on the same seeds as above.
TEST(Simulation, RansacAndBootstrapKeepThePinnedNees) {
  EskfSettings s = scenarioSettings();
  s.ransac_iterations = 200;
  s.bootstrap_landmarks = 60;
  checkMonteCarlo(s);
}

}  // namespace
}  // namespace hapi_eskf
