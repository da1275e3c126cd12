// Eskf host logic: settings, bad frames (exact no-op), pool policy, reports,
// prediction entry points and association rules.
#include "hapi_eskf/backend/association.hpp"
#include "basic_settings.hpp"
#include "hapi_eskf/backend/measurement_model.hpp"
#include "hapi_eskf/backend/pose_kinematics.hpp"
#include "hapi_eskf/eskf/eskf.hpp"
#include "sim_scenario.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

namespace hapi_eskf {
namespace {

EskfSettings smallSettings() {
  EskfSettings s = testing_settings::basicFilter();
  s.max_landmarks = 60;
  s.max_new_landmarks = 20;
  s.max_update_landmarks = 15;
  s.max_frame_measurements = 400;
  s.sigma_acceleration = 0.2;
  s.sigma_angular_acceleration = 0.05;
  return s;
}

// Everything observable about the filter, compared bit for bit.
struct FilterSnapshot {
  PoseState pose;
  double time;
  Eigen::MatrixXd C;
  std::vector<Vec3> positions;
  std::vector<uint64_t> ids;
  std::vector<uint8_t> desc;
  explicit FilterSnapshot(const Eskf& f)
      : pose(f.pose()),
        time(f.time()),
        C(f.backend().denseCovariance()),
        positions(f.landmarkPositions()),
        ids(f.landmarkIds()),
        desc(f.backend().descriptors()) {}
  void expectSame(const Eskf& f, const char* what) const {
    EXPECT_TRUE(pose.p == f.pose().p && pose.q.coeffs() == f.pose().q.coeffs() && pose.v == f.pose().v &&
                pose.w == f.pose().w)
        << what;
    EXPECT_EQ(time, f.time()) << what;
    const Eigen::MatrixXd C2 = f.backend().denseCovariance();
    ASSERT_EQ(C.rows(), C2.rows()) << what;
    EXPECT_TRUE((C.array() == C2.array()).all()) << what;
    EXPECT_TRUE(positions == f.landmarkPositions()) << what;
    EXPECT_TRUE(ids == f.landmarkIds()) << what;
    EXPECT_TRUE(desc == f.backend().descriptors()) << what;
  }
};

// A filter that has run a few frames of the simulated scenario.
struct Scenario {
  std::mt19937 rng{7};
  EskfSettings s = smallSettings();
  sim::StereoRig rig;
  sim::World world = sim::randomWorld(rng, 3000, Vec3(-20, -20, -20), Vec3(20, 20, 20));
  PoseState truth;
  Eskf f{s, makeCpuBackend(s.max_landmarks, 32)};
  double t = 0;
  Scenario() {
    truth.v = Vec3(0, 0, 1);
    truth.w = Vec3(0, 0.1, 0);
    EXPECT_EQ(f.reset(truth, 0.0), Status::kOk);
  }
  StereoFrame next() {
    t += 0.1;
    truth = sim::truthStep(truth, 0.1, s, rng);
    return sim::makeFrame(world, truth, rig, t, 4, rng);
  }
};

TEST(Settings, ValidateNamesTheOffendingFieldAndParsers) {
  EskfSettings s;
  EXPECT_EQ(s.validate(), "");
  s.match_ratio = 1.5;
  EXPECT_NE(s.validate().find("match_ratio"), std::string::npos);
  s = EskfSettings();
  s.full_pool_add_fraction = std::nan("");
  EXPECT_NE(s.validate().find("full_pool_add_fraction"), std::string::npos);
  s = EskfSettings();
  s.sigma_acceleration = 0;
  EXPECT_NE(s.validate().find("sigma_acceleration"), std::string::npos);
  s = EskfSettings();
  s.max_new_landmarks = s.max_landmarks + 1;
  EXPECT_NE(s.validate().find("max_new_landmarks"), std::string::npos);
  BackendKind b;
  Precision p;
  EXPECT_TRUE(parseBackendKind("cuda", &b));
  EXPECT_EQ(b, BackendKind::kCuda);
  EXPECT_STREQ(toString(b), "cuda");
  EXPECT_FALSE(parseBackendKind("gpu", &b));
  EXPECT_TRUE(parsePrecision("fp32", &p));
  EXPECT_STREQ(toString(p), "fp32");
  EXPECT_FALSE(parsePrecision("double", &p));
  EXPECT_STREQ(toString(Status::kNotPositiveDefinite), "covariance not positive definite");
}

// A filter that never reset successfully says so (kNotInitialised); one
// without a backend says that (kBackendUnavailable).
TEST(Eskf, UninitialisedAndBackendlessFiltersSaySo) {
  EskfSettings s = smallSettings();
  Eskf mismatch(s, makeCpuBackend(s.max_landmarks + 1, 32));  // capacity != max_landmarks
  EXPECT_EQ(mismatch.reset(PoseState(), 0.0), Status::kInvalidArgument);
  EXPECT_EQ(mismatch.predictTo(1.0), Status::kNotInitialised);
  EXPECT_EQ(mismatch.addImu(ImuSample{1.0, Vec3::Zero(), Vec3::Zero()}), Status::kNotInitialised);
  StereoFrame fr;
  fr.stamp = 1.0;
  EXPECT_EQ(mismatch.processFrame(fr), Status::kNotInitialised);
  Eskf none(s, nullptr);
  EXPECT_EQ(none.reset(PoseState(), 0.0), Status::kBackendUnavailable);
  EXPECT_EQ(none.processFrame(fr), Status::kBackendUnavailable);
  EXPECT_STREQ(toString(Status::kNotInitialised), "not initialised");
}

TEST(Eskf, BadFramesReturnTheirStatusAndLeaveTheStateExactlyUnchanged) {
  Scenario sc;
  for (int k = 0; k < 5; ++k) ASSERT_EQ(sc.f.processFrame(sc.next()), Status::kOk);
  ASSERT_GT(sc.f.numLandmarks(), 0);
  const StereoFrame good = sc.next();
  ASSERT_GT(good.measurements.size(), 3u);
  const FilterSnapshot snap(sc.f);
  const double nan = std::numeric_limits<double>::quiet_NaN();

  auto check = [&](StereoFrame fr, Status expected, const char* what) {
    IterationReport rep;
    EXPECT_EQ(sc.f.processFrame(fr, &rep), expected) << what;
    snap.expectSame(sc.f, what);
    EXPECT_EQ(rep.n_updated, 0) << what;
    EXPECT_EQ(rep.n_added, 0) << what;
  };
  StereoFrame fr = good;
  fr.measurements[2].z.y() = nan;
  check(fr, Status::kNonFinite, "NaN position");
  fr = good;
  fr.measurements[1].Cz(0, 2) = fr.measurements[1].Cz(2, 0) = std::numeric_limits<double>::infinity();
  check(fr, Status::kNonFinite, "Inf covariance");
  fr = good;
  fr.stamp = nan;
  check(fr, Status::kNonFinite, "NaN stamp");
  fr = good;
  fr.measurements.clear();
  fr.descriptors.clear();
  check(fr, Status::kEmptyInput, "empty frame");
  fr = good;
  fr.measurements[3].frontend_id = fr.measurements[0].frontend_id;
  check(fr, Status::kDuplicateId, "duplicate frontend id");
  fr = good;
  while (static_cast<int>(fr.measurements.size()) <= sc.s.max_frame_measurements) {
    fr.measurements.push_back(fr.measurements[0]);
    fr.measurements.back().frontend_id = 100000 + static_cast<uint32_t>(fr.measurements.size());
    fr.descriptors.insert(fr.descriptors.end(), good.descriptors.begin(), good.descriptors.begin() + 32);
  }
  check(fr, Status::kCapacityExceeded, "more measurements than max_frame_measurements");
  fr = good;
  fr.descriptor_length = 16;
  fr.descriptors.resize(16 * fr.measurements.size());
  check(fr, Status::kInvalidArgument, "descriptor length differs from the pool's");
  fr = good;
  fr.descriptors.pop_back();
  check(fr, Status::kInvalidArgument, "descriptor buffer size");
  fr = good;
  fr.measurements[0].Cz = -fr.measurements[0].Cz;
  check(fr, Status::kNotPositiveDefinite, "negative definite Cz");
  fr = good;
  fr.measurements[0].Cz(0, 1) += 1e-3;  // not symmetric
  check(fr, Status::kNotPositiveDefinite, "non-symmetric Cz");
  fr = good;
  fr.stamp = sc.f.time() - 0.05;
  check(fr, Status::kInvalidArgument, "stamp backwards");

  // The good frame still works afterwards, and a backwards predict is refused too.
  IterationReport rep;
  EXPECT_EQ(sc.f.processFrame(good, &rep), Status::kOk);
  EXPECT_GT(rep.n_updated, 0);
  const FilterSnapshot snap2(sc.f);
  EXPECT_EQ(sc.f.predictTo(sc.f.time() - 1e-3), Status::kInvalidArgument);
  EXPECT_EQ(sc.f.predictTo(nan), Status::kNonFinite);
  EXPECT_EQ(sc.f.addImu(ImuSample{sc.f.time() + 0.1, Vec3(nan, 0, 0), Vec3::Zero()}), Status::kNonFinite);
  EXPECT_EQ(sc.f.addImu(ImuSample{sc.f.time() + 0.1, Vec3::Zero(), Vec3::Zero()}), Status::kInvalidArgument)
      << "the constant-velocity model has no IMU input";
  snap2.expectSame(sc.f, "bad predict");
}

TEST(Eskf, ReportIsFilledAndPoolPolicyEvictsTheStalest) {
  EskfSettings s = smallSettings();
  s.max_landmarks = 30;
  s.max_new_landmarks = 20;
  s.full_pool_add_fraction = 0.5;
  s.max_hamming = 8;  // 8-byte codes: random pairs differ by ~32 bits
  Eskf f(s, makeCpuBackend(s.max_landmarks, 8));
  ASSERT_EQ(f.reset(PoseState(), 0.0), Status::kOk);
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> byte(0, 255);
  // Frames of 25 never-seen points each (fresh random descriptors).
  auto freshFrame = [&](double stamp) {
    StereoFrame fr;
    fr.stamp = stamp;
    fr.descriptor_length = 8;
    for (int i = 0; i < 25; ++i) {
      StereoMeasurement m;
      m.z = Vec3(0.1 * i - 1.2, 0.05 * (i % 5), 3.0 + 0.1 * i);
      m.Cz = 1e-4 * Mat3::Identity();
      m.frontend_id = i;
      m.response = static_cast<float>(i);  // strongest = highest index
      fr.measurements.push_back(m);
      for (int b = 0; b < 8; ++b) fr.descriptors.push_back(static_cast<uint8_t>(byte(rng)));
    }
    return fr;
  };
  IterationReport rep;
  ASSERT_EQ(f.processFrame(freshFrame(0.1), &rep), Status::kOk);
  EXPECT_EQ(rep.n_measurements, 25);
  EXPECT_EQ(rep.n_added, 20);  // max_new_landmarks
  EXPECT_EQ(rep.n_removed, 0);
  EXPECT_EQ(rep.n_landmarks, 20);
  EXPECT_GE(rep.t_total_ms, rep.t_predict_ms + rep.t_association_ms + rep.t_update_ms);
  EXPECT_GT(rep.t_total_ms, 0.0);
  const auto first_ids = f.landmarkIds();
  // Strongest first: the first landmark came from measurement 24.
  EXPECT_LT((f.landmarkPositions()[0] - Vec3(0.1 * 24 - 1.2, 0.05 * 4, 5.4)).norm(), 1e-9);

  ASSERT_EQ(f.processFrame(freshFrame(0.2), &rep), Status::kOk);
  EXPECT_EQ(rep.n_added, 10);  // only 10 free slots; not below the 0.5 * 20 target, so nothing evicted
  EXPECT_EQ(rep.n_removed, 0);
  EXPECT_EQ(f.numLandmarks(), 30);

  ASSERT_EQ(f.processFrame(freshFrame(0.3), &rep), Status::kOk);
  EXPECT_EQ(rep.n_removed, 10);  // pool full: evict ceil(0.5 * 20) ...
  EXPECT_EQ(rep.n_added, 10);    // ... so that many new ones fit
  EXPECT_EQ(f.numLandmarks(), 30);
  // The evicted ones are the least recently seen: 10 of the first frame's
  // (smallest ids among ties), i.e. slots 0-9; the second frame's 10 (slots
  // 20-29) refilled them (removal_plan.hpp) and the new ones are appended.
  const auto ids = f.landmarkIds();
  const auto second_ids = std::vector<uint64_t>(ids.begin(), ids.begin() + 10);
  for (int k = 0; k < 10; ++k) {
    EXPECT_EQ(std::count(ids.begin(), ids.end(), first_ids[k]), 0) << "id " << first_ids[k] << " should be evicted";
    EXPECT_EQ(ids[10 + k], first_ids[10 + k]);  // kept in place
    EXPECT_GT(second_ids[k], first_ids.back());  // a second-frame landmark
  }
  EXPECT_EQ(static_cast<int>(f.landmarks().size()), 30);
  EXPECT_EQ(f.backend().numLandmarks(), 30);
}

TEST(Eskf, RepeatedObservationsOfAStaticSceneShrinkUncertaintyAndAssociate) {
  EskfSettings s = smallSettings();
  s.sigma_acceleration = 0.01;
  s.sigma_angular_acceleration = 0.01;
  Eskf f(s, makeCpuBackend(s.max_landmarks, 32));
  ASSERT_EQ(f.reset(PoseState(), 0.0), Status::kOk);
  std::mt19937 rng(5);
  sim::StereoRig rig;
  sim::World world = sim::randomWorld(rng, 40, Vec3(-3, -2, 4), Vec3(3, 2, 9));
  PoseState still;  // camera at rest at the origin
  IterationReport rep;
  ASSERT_EQ(f.processFrame(sim::makeFrame(world, still, rig, 0.0, 3, rng), &rep), Status::kOk);
  const int n0 = f.numLandmarks();
  EXPECT_EQ(n0, 20);
  const double trace0 = f.landmarks()[0].covariance.trace();
  for (int k = 1; k <= 20; ++k) {
    ASSERT_EQ(f.processFrame(sim::makeFrame(world, still, rig, 0.1 * k, 3, rng), &rep), Status::kOk);
    EXPECT_EQ(rep.n_updated, std::min(15, rep.n_candidates - rep.n_gated_out)) << k;
  }
  EXPECT_EQ(f.numLandmarks(), 40);  // the other 20 points were added in frame 1, no duplicates since
  EXPECT_LT(f.landmarks()[0].covariance.trace(), 0.5 * trace0);
  EXPECT_GT(f.landmarks()[0].times_observed, 1);
  EXPECT_LT(f.pose().p.norm(), 0.05);
  EXPECT_LT(f.pose().v.norm(), 0.1);
  // Each landmark sits near its true point (association found the right one).
  for (const auto& l : f.landmarks()) {
    double best = 1e9;
    for (const auto& p : world.points) best = std::min(best, (p - l.position).norm());
    EXPECT_LT(best, 5.0 * std::sqrt(l.covariance.trace()) + 0.05);
  }
}

// The report says what became of every measurement, and that agrees with
// the filter's own map: the fused ones name the landmarks whose observation
// count went up (each started by the same scene point), the added ones the
// landmarks that are new, placed from the camera the frame saw.
TEST(Eskf, ReportSaysWhatBecameOfEachMeasurement) {
  using Result = MeasurementOutcome::Result;
  EskfSettings s = smallSettings();
  s.sigma_acceleration = 0.01;
  s.sigma_angular_acceleration = 0.01;
  s.measurement_angular_sigma = 2e-3;  // the outcomes carry C_z as the filter used it
  Eskf f(s, makeCpuBackend(s.max_landmarks, 32));
  ASSERT_EQ(f.reset(PoseState(), 0.0), Status::kOk);
  std::mt19937 rng(5);
  sim::StereoRig rig;
  sim::World world = sim::randomWorld(rng, 40, Vec3(-3, -2, 4), Vec3(3, 2, 9));
  PoseState still;
  std::map<uint64_t, uint32_t> origin;  // landmark id -> the scene point that started it
  std::map<Result, int> seen;
  for (int k = 0; k <= 5; ++k) {
    const StereoFrame fr = sim::makeFrame(world, still, rig, 0.1 * k, 3, rng);
    std::map<uint64_t, int> before;  // id -> times observed
    for (const LandmarkInfo& l : f.landmarks()) before[l.id] = l.times_observed;
    IterationReport rep;
    ASSERT_EQ(f.processFrame(fr, &rep), Status::kOk) << k;
    ASSERT_EQ(rep.measurements.size(), fr.measurements.size()) << k;
    std::map<uint64_t, LandmarkInfo> after;
    for (const LandmarkInfo& l : f.landmarks()) after[l.id] = l;
    std::set<uint64_t> fused, added, observed_more, new_ids;
    int associated = 0;
    for (std::size_t i = 0; i < rep.measurements.size(); ++i) {
      const MeasurementOutcome& o = rep.measurements[i];
      const StereoMeasurement& m = fr.measurements[i];
      ++seen[o.result];
      EXPECT_EQ(o.measurement, static_cast<int>(i));
      EXPECT_TRUE(o.Cz == m.Cz + redetectionCovariance(m.z, s.measurement_angular_sigma)) << k << " " << i;
      associated += o.associated;
      EXPECT_EQ(o.associated, std::isfinite(o.nis)) << k << " " << i;
      if (o.associated) {
        EXPECT_TRUE(o.nis >= 0.0 && o.nis <= s.gate_chi2) << o.nis;
        ASSERT_TRUE(before.count(o.landmark_id)) << "associated with a landmark of the pool";
        EXPECT_EQ(origin.at(o.landmark_id), m.frontend_id) << "the landmark of the same scene point";
        EXPECT_TRUE(o.result == Result::kFused || o.result == Result::kNotUpdated);
      }
      if (o.fused()) {
        EXPECT_TRUE(fused.insert(o.landmark_id).second) << "one measurement per landmark";
      }
      if (o.added()) {
        EXPECT_FALSE(o.associated);
        ASSERT_TRUE(after.count(o.landmark_id));
        EXPECT_FALSE(before.count(o.landmark_id));
        EXPECT_EQ(after[o.landmark_id].position, initLandmark(f.frameCamera(), m.z));
        added.insert(o.landmark_id);
        origin[o.landmark_id] = m.frontend_id;
      }
      if (!o.associated && !o.added()) {
        EXPECT_EQ(o.landmark_id, 0u);
        EXPECT_TRUE(o.result == Result::kNotAdded || o.result == Result::kNotAssociated);
      }
    }
    for (const auto& kv : after) {
      const auto b = before.find(kv.first);
      if (b == before.end())
        new_ids.insert(kv.first);
      else if (kv.second.times_observed > b->second)
        observed_more.insert(kv.first);
    }
    EXPECT_EQ(fused, observed_more) << k;
    EXPECT_EQ(added, new_ids) << k;
    EXPECT_EQ(static_cast<int>(fused.size()), rep.n_updated) << k;
    EXPECT_EQ(static_cast<int>(added.size()), rep.n_added) << k;
    EXPECT_EQ(rep.n_updated, std::min(s.max_update_landmarks, associated)) << k;
  }
  // Every kind of this scene came up: 40 points, 20 added per frame, 15 updated.
  for (Result r : {Result::kFused, Result::kNotUpdated, Result::kAdded, Result::kNotAdded})
    EXPECT_GT(seen[r], 0) << static_cast<int>(r);

  // A rejected frame: every measurement says so.
  IterationReport rep;
  const StereoFrame late = sim::makeFrame(world, still, rig, 0.0, 3, rng);  // before the filter time
  ASSERT_EQ(f.processFrame(late, &rep), Status::kInvalidArgument);
  ASSERT_EQ(rep.measurements.size(), late.measurements.size());
  for (const MeasurementOutcome& o : rep.measurements) {
    EXPECT_EQ(o.result, Result::kNotProcessed);
    EXPECT_FALSE(o.associated);
  }
}

// A CPU backend whose joint update fails, on demand, as with an S that is not PD.
class FailingUpdateBackend final : public CovarianceBackend {
 public:
  explicit FailingUpdateBackend(std::unique_ptr<CovarianceBackend> inner)
      : CovarianceBackend(inner->poseDim()), inner_(std::move(inner)) {}
  bool fail_updates = false;
  const char* name() const override { return inner_->name(); }
  int capacity() const override { return inner_->capacity(); }
  int numLandmarks() const override { return inner_->numLandmarks(); }
  int descriptorLength() const override { return inner_->descriptorLength(); }
  std::size_t memoryBytes() const override { return inner_->memoryBytes(); }
  PoseMat poseCovariance() const override { return inner_->poseCovariance(); }
  std::vector<Mat3> landmarkCovariances() const override { return inner_->landmarkCovariances(); }
  Eigen::MatrixXd denseCovariance() const override { return inner_->denseCovariance(); }
  std::vector<uint8_t> descriptors() const override { return inner_->descriptors(); }

 protected:
  Status doReset(const PoseMat& C) override { return inner_->reset(C); }
  Status doPredict(const PoseMat& F, const PoseMat& Q) override { return inner_->predict(F, Q); }
  Status doMarginals(const std::vector<int>& slots, std::vector<Mat9>* out) const override {
    return inner_->marginals(slots, out);
  }
  Status doUpdate(const std::vector<MeasurementBlock>& blocks, Eigen::VectorXd* dx, double* nis) override {
    return fail_updates ? Status::kNotPositiveDefinite : inner_->update(blocks, dx, nis);
  }
  Status doAddLandmarks(const std::vector<NewLandmarkBlock>& blocks) override { return inner_->addLandmarks(blocks); }
  Status doRemoveLandmarks(const std::vector<int>& slots) override { return inner_->removeLandmarks(slots); }
  Status doMatchDescriptors(const uint8_t* q, int n, std::vector<DescriptorMatch>* out) const override {
    return inner_->matchDescriptors(q, n, out);
  }

 private:
  std::unique_ptr<CovarianceBackend> inner_;
};

// The one error after state changes: the joint update is skipped, the
// prediction and the bookkeeping still apply, and the outcomes say which
// measurements were in the skipped update.
TEST(Eskf, SkippedUpdateStillPredictsAndAddsAndSaysWhichMeasurements) {
  using Result = MeasurementOutcome::Result;
  const EskfSettings s = smallSettings();
  auto failing = std::make_unique<FailingUpdateBackend>(makeCpuBackend(s.max_landmarks, 32));
  FailingUpdateBackend* backend = failing.get();
  Eskf f(s, std::move(failing));
  ASSERT_EQ(f.reset(PoseState(), 0.0), Status::kOk);
  std::mt19937 rng(5);
  sim::StereoRig rig;
  sim::World world = sim::randomWorld(rng, 40, Vec3(-3, -2, 4), Vec3(3, 2, 9));
  PoseState still;
  ASSERT_EQ(f.processFrame(sim::makeFrame(world, still, rig, 0.1, 3, rng)), Status::kOk);
  const int n0 = f.numLandmarks();
  std::vector<int> times_before;
  for (const LandmarkInfo& l : f.landmarks()) times_before.push_back(l.times_observed);

  backend->fail_updates = true;
  const StereoFrame fr = sim::makeFrame(world, still, rig, 0.2, 3, rng);
  IterationReport rep;
  ASSERT_EQ(f.processFrame(fr, &rep), Status::kNotPositiveDefinite);
  EXPECT_TRUE(rep.update_skipped);
  EXPECT_EQ(rep.n_updated, 0);
  EXPECT_EQ(f.time(), 0.2);  // predicted to the frame
  EXPECT_GT(rep.n_added, 0);  // the additions still apply
  EXPECT_EQ(f.numLandmarks(), n0 + rep.n_added);
  int skipped = 0, associated = 0;
  for (const MeasurementOutcome& o : rep.measurements) {
    skipped += o.result == Result::kUpdateSkipped;
    associated += o.associated;
    EXPECT_FALSE(o.fused());
    if (o.result == Result::kUpdateSkipped) {
      EXPECT_TRUE(o.associated && std::isfinite(o.nis));
    }
  }
  EXPECT_GT(skipped, 0);
  EXPECT_EQ(skipped, std::min(s.max_update_landmarks, associated));
  const std::vector<LandmarkInfo> after = f.landmarks();
  for (int k = 0; k < n0; ++k) EXPECT_EQ(after[k].times_observed, times_before[k]) << "no observation counted";
}

TEST(Eskf, PredictEntryPoints) {
  EskfSettings s = smallSettings();
  s.angular_velocity_damping = 0.5;
  s.motion_model = MotionModelKind::kGyro;  // without a sample it is the constant-velocity step
  s.gyro_noise_density = 0.01;
  Eskf f(s, makeCpuBackend(s.max_landmarks, 32, kGyroDim));
  PoseState x0;
  x0.v = Vec3(0.3, 0, 1);
  x0.w = Vec3(0.1, 0.2, 0);
  ASSERT_EQ(f.reset(x0, 1.0), Status::kOk);
  ASSERT_EQ(f.predictTo(1.0), Status::kOk);  // no-op
  EXPECT_EQ(f.time(), 1.0);
  ASSERT_EQ(f.predictTo(1.5), Status::kOk);
  const PoseState ref = predictPose(x0, 0.5, s);
  EXPECT_LT((f.pose().p - ref.p).norm(), 1e-15);
  EXPECT_LT(f.pose().q.angularDistance(ref.q), 1e-15);
  const Mat12 F = predictJacobian(x0, 0.5, s);
  Mat12 C0 = Mat12::Zero();
  C0.diagonal() << Vec3::Constant(1e-6), Vec3::Constant(1e-6), Vec3::Constant(0.04), Vec3::Constant(0.25);
  C0.diagonal().head<3>().setConstant(s.initial_sigma_position * s.initial_sigma_position);
  C0.diagonal().segment<3>(3).setConstant(s.initial_sigma_orientation * s.initial_sigma_orientation);
  C0.diagonal().segment<3>(6).setConstant(s.initial_sigma_velocity * s.initial_sigma_velocity);
  C0.diagonal().segment<3>(9).setConstant(s.initial_sigma_angular_velocity * s.initial_sigma_angular_velocity);
  const Mat12 expect = F * C0 * F.transpose() + processNoise(0.5, s);
  EXPECT_LT((f.poseCovariance().topLeftCorner<12, 12>() - expect).cwiseAbs().maxCoeff(), 1e-15);

  // Gyro: w is replaced by the measurement less the bias, its variance by
  // sigma^2/dt plus the bias's (then damped), sigma the inflated density
  // (motion_model.hpp imuNoiseDensities); the camera is the IMU here.
  const Vec3 gyro(0.0, -0.3, 0.05);
  ASSERT_EQ(f.addImu(ImuSample{1.6, gyro, Vec3::Zero()}), Status::kOk);
  const double lam = std::pow(0.5, 0.1);
  EXPECT_LT((f.pose().w - lam * gyro).norm(), 1e-15);
  const PoseMat C = f.poseCovariance();
  // The bias as the step began: its prior and 0.5 s of random walk.
  const double sg = 0.01 * s.gyro_noise_inflation;
  const double vb = s.initial_sigma_gyro_bias * s.initial_sigma_gyro_bias + s.gyro_random_walk * s.gyro_random_walk * 0.5;
  EXPECT_NEAR(C(kIdxW, kIdxW), lam * lam * (sg * sg / 0.1 + vb) + processNoise(0.1, s)(kIdxW, kIdxW), 1e-14);
  EXPECT_NEAR(C(kIdxW, kIdxGyroBias), -lam * vb, 1e-14);  // the rate's error is the bias's
  EXPECT_NEAR(C(kIdxW, kIdxV), 0.0, 1e-18);  // the old w's correlations are gone
}

TEST(Association, RatioTestGateAndOneMeasurementPerLandmark) {
  EskfSettings s = smallSettings();
  s.max_hamming = 10;  // 8-byte codes
  auto backend = makeCpuBackend(s.max_landmarks, 8);
  Mat12 C0 = 1e-6 * Mat12::Identity();
  ASSERT_EQ(backend->reset(C0), Status::kOk);
  PoseState pose;
  std::vector<Vec3> pos = {Vec3(0, 0, 5), Vec3(1, 0, 5), Vec3(-1, 0, 5)};
  std::vector<std::vector<uint8_t>> d = {std::vector<uint8_t>(8, 0x00), std::vector<uint8_t>(8, 0xFF),
                                         std::vector<uint8_t>(8, 0x0F)};
  d[2][0] = 0x0E;  // landmark 2 is 1 bit from... nothing close to the others
  std::vector<NewLandmarkBlock> nb(3);
  for (int i = 0; i < 3; ++i) {
    newLandmarkJacobian(pose, pos[i], &nb[i].G_pose, &nb[i].G_z);
    nb[i].Cz = 1e-4 * Mat3::Identity();
    nb[i].descriptor = d[i].data();
  }
  ASSERT_EQ(backend->addLandmarks(nb), Status::kOk);

  StereoFrame fr;
  fr.descriptor_length = 8;
  auto addMeas = [&](const Vec3& z, std::vector<uint8_t> desc) {
    StereoMeasurement m;
    m.z = z;
    m.Cz = 1e-4 * Mat3::Identity();
    m.frontend_id = static_cast<uint32_t>(fr.measurements.size());
    fr.measurements.push_back(m);
    fr.descriptors.insert(fr.descriptors.end(), desc.begin(), desc.end());
  };
  std::vector<uint8_t> near0 = d[0];
  near0[3] = 0x01;                                     // 1 bit from landmark 0
  addMeas(Vec3(0, 0, 5.001), near0);                   // 0: good match of landmark 0
  addMeas(Vec3(0, 0, 5.02), d[0]);                     // 1: same landmark, larger distance -> conflict loser
  addMeas(Vec3(1, 0, 7.0), d[1]);                      // 2: descriptor of 1 but 2 m off -> gated out
  addMeas(Vec3(3, 3, 3), std::vector<uint8_t>(8, 0x55));  // 3: new point (32 bits from everything)
  Association a;
  ASSERT_EQ(associate(fr, pose, Mat6::Identity(), pos, *backend, s, &a), Status::kOk);
  EXPECT_EQ(a.slot[0], 0);
  EXPECT_EQ(a.slot[1], -1);
  EXPECT_EQ(a.slot[2], -1);
  EXPECT_EQ(a.slot[3], -1);
  EXPECT_EQ(a.n_candidates, 3);
  EXPECT_EQ(a.n_gated_out, 1);
  EXPECT_EQ(a.n_conflicts, 1);
  EXPECT_FALSE(a.may_add[0]);
  EXPECT_FALSE(a.may_add[1]);
  EXPECT_FALSE(a.may_add[2]);  // copy_chi2 0: a measurement that resembles a landmark is a copy
  EXPECT_TRUE(a.may_add[3]);
  {
    // With copy_chi2, 2 m from the landmark it resembles (d2 2e4) is another point.
    EskfSettings far = s;
    far.copy_chi2 = 100.0;
    Association b;
    ASSERT_EQ(associate(fr, pose, Mat6::Identity(), pos, *backend, far, &b), Status::kOk);
    EXPECT_EQ(b.slot[2], -1);
    EXPECT_TRUE(b.may_add[2]);
    EXPECT_TRUE(b.may_add[3]);
  }
  {
    // Nearer than copy_chi2 to the landmark it resembles, a gated-out
    // measurement is taken for a copy and may not start a landmark.
    EskfSettings wide = s;
    wide.copy_chi2 = 1e5;  // nearer than this
    Association b;
    ASSERT_EQ(associate(fr, pose, Mat6::Identity(), pos, *backend, wide, &b), Status::kOk);
    EXPECT_EQ(b.slot[2], -1);
    EXPECT_FALSE(b.may_add[2]);
    EXPECT_TRUE(b.may_add[3]);
  }
  // Landmark and measurement share the pose, whose terms cancel in S:
  // S = C_init + C_z = 2e-4 I, innovation 1e-3 along z.
  EXPECT_NEAR(a.d2[0], 1e-6 / 2e-4, 1e-9);

  // Ratio test: a query equidistant from two landmarks is ambiguous.
  StereoFrame amb;
  amb.descriptor_length = 8;
  std::swap(fr, amb);
  std::vector<uint8_t> half(8, 0x00);
  half[0] = 0x0F;  // 4 bits from landmark 0 (0x00...) ; landmark 2 is 0x0E,0x0F.. far
  addMeas(Vec3(0, 0, 5), half);
  s.match_ratio = 0.8;
  ASSERT_EQ(associate(fr, pose, Mat6::Identity(), pos, *backend, s, &a), Status::kOk);
  EXPECT_EQ(a.slot[0], 0);  // 4 vs >= 26 bits: unambiguous
  s.max_hamming = 3;
  ASSERT_EQ(associate(fr, pose, Mat6::Identity(), pos, *backend, s, &a), Status::kOk);
  EXPECT_EQ(a.slot[0], -1);  // beyond max_hamming
  EXPECT_TRUE(a.may_add[0]);
}

}  // namespace
}  // namespace hapi_eskf
