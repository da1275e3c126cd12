// Relocalisation after an input outage (EskfSettings::relocalise_gap): the
// camera changes its motion while no frames arrive (front end restarted, link
// down). Without relocalisation the filter extrapolates the old velocity for
// the whole gap and the first update linearises far outside the EKF's range;
// with it, the velocity mean is zeroed, the frames without a map fit are held
// back, and the pose mean moves to the RANSAC fit of the first supported frame.
#include "basic_settings.hpp"
#include "hapi_eskf/eskf/eskf.hpp"
#include "sim_scenario.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>

namespace hapi_eskf {
namespace {

struct OutageRun {
  double final_pos_err = 0, final_rot_err = 0;
  double max_pos_err_after = 0;  // over the frames a nodelet publishes after the outage
  int n_relocalised = 0, n_relocalising = 0;
  bool relocalising_frames_changed_nothing = true;
};

// `unmapped_s`: after the outage the camera first sees only unmapped points
// (another world, other descriptors) for this long.
OutageRun runOutage(double relocalise_gap, double unmapped_s = 0.0) {
  EskfSettings s = testing_settings::basicFilter();
  s.max_landmarks = 500;
  s.max_new_landmarks = 20;
  s.bootstrap_landmarks = 100;
  s.max_update_landmarks = 60;
  s.ransac_iterations = 200;
  s.relocalise_gap = relocalise_gap;
  EXPECT_EQ(s.validate(), "");
  Eskf f(s, makeCpuBackend(s.max_landmarks, 32));
  std::mt19937 rng(21);
  const sim::World world = sim::randomWorld(rng, 600, Vec3(-5, -2, 3), Vec3(5, 2, 10));
  const sim::World unmapped = sim::randomWorld(rng, 600, Vec3(-5, -2, 3), Vec3(5, 2, 10));
  const sim::StereoRig rig;

  PoseState truth;
  truth.v = Vec3(0.15, 0.0, 0.0);
  truth.w = Vec3(0.0, 0.03, 0.0);
  EXPECT_EQ(f.reset(truth, 0.0), Status::kOk);
  OutageRun r;
  const double dt = 0.1, gap_start = 3.0, gap_end = 9.0, end = 12.0;
  bool after = false;
  for (int k = 1; k * dt <= end + 1e-9; ++k) {
    const double t = k * dt;
    // The motion changes during the outage: back and turning the other way.
    if (t > gap_start && !after) {
      truth.v = Vec3(-0.1, 0.03, 0.05);
      truth.w = Vec3(0.0, -0.08, 0.02);
    }
    truth = predictPose(truth, dt, s);
    if (t > gap_start && t < gap_end) continue;  // no frames: outage
    after = t >= gap_end;
    const bool sees_unmapped = after && t < gap_end + unmapped_s - 1e-9;
    const StereoFrame fr = sim::makeFrame(sees_unmapped ? unmapped : world, truth, rig, t, 4, rng);
    const PoseState before = f.pose();
    const int landmarks_before = f.numLandmarks();
    IterationReport rep;
    EXPECT_EQ(f.processFrame(fr, &rep), Status::kOk) << "t=" << t;
    r.n_relocalised += rep.relocalised;
    if (rep.relocalising) {
      ++r.n_relocalising;
      for (const MeasurementOutcome& o : rep.measurements)
        EXPECT_EQ(o.result, MeasurementOutcome::Result::kHeldBack) << "t=" << t;
      // Held back: no update, no new landmarks (the pose only predicted).
      if (rep.n_updated != 0 || rep.n_added != 0 || f.numLandmarks() != landmarks_before ||
          (f.pose().p - before.p).norm() > 1e-12)
        r.relocalising_frames_changed_nothing = false;
      continue;
    }
    const auto e = sim::poseError(truth, f.pose());
    if (after) r.max_pos_err_after = std::max(r.max_pos_err_after, e.head<3>().norm());
    r.final_pos_err = e.head<3>().norm();
    r.final_rot_err = e.tail<3>().norm();
  }
  return r;
}

TEST(Relocalise, RecoversAfterAnOutageWithChangedMotion) {
  const OutageRun off = runOutage(0.0), on = runOutage(1.0);
  std::printf("6 s outage, motion changed: without relocalisation final |dp| %.3f m |dth| %.3f rad, max after %.3f m; "
              "with: final |dp| %.4f m |dth| %.4f rad, max after %.4f m (relocalised %d, frames held %d)\n",
              off.final_pos_err, off.final_rot_err, off.max_pos_err_after, on.final_pos_err, on.final_rot_err,
              on.max_pos_err_after, on.n_relocalised, on.n_relocalising);
  EXPECT_EQ(off.n_relocalised, 0);
  EXPECT_EQ(off.n_relocalising, 0);
  // The first frame after the gap sees enough of the map: relocalised at once.
  EXPECT_EQ(on.n_relocalised, 1);
  EXPECT_TRUE(on.relocalising_frames_changed_nothing);
  EXPECT_LT(on.max_pos_err_after, 0.05);
  EXPECT_LT(on.final_pos_err, 0.02);
  EXPECT_LT(on.final_rot_err, 0.01);
  // The old behaviour (extrapolating the stale velocity over the gap) is off.
  EXPECT_GT(off.max_pos_err_after, 5.0 * on.max_pos_err_after);
}

// Frames of unmapped ground right after the outage are held back (they would
// add landmarks at an unknown pose) until a frame of the map relocalises.
TEST(Relocalise, HoldsFramesWithoutMapSupport) {
  const OutageRun r = runOutage(1.0, 1.0);
  std::printf("held %d frames, relocalised %d, max |dp| after %.4f m\n", r.n_relocalising, r.n_relocalised,
              r.max_pos_err_after);
  EXPECT_GE(r.n_relocalising, 9);  // 1 s of 10 Hz frames (the first at exactly gap_end)
  EXPECT_LE(r.n_relocalising, 11);
  EXPECT_TRUE(r.relocalising_frames_changed_nothing);
  EXPECT_EQ(r.n_relocalised, 1);
  EXPECT_LT(r.max_pos_err_after, 0.05);
}

TEST(Relocalise, SettingValidated) {
  EskfSettings s;
  s.relocalise_gap = -1.0;
  EXPECT_NE(s.validate().find("relocalise_gap"), std::string::npos);
  s.relocalise_gap = 0.5;
  EXPECT_EQ(s.validate(), "");
}

}  // namespace
}  // namespace hapi_eskf
