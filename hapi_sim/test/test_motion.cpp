// Kinematics of the simulation suite: exact trajectory derivatives against
// finite differences (the moving trajectories, both scene framings, the scene's
// own motion, the IMU lever arm and the relative motion), the IMU model
// (noise-free readings integrate back to the trajectory; gravity sign; noise
// statistics match the densities), the tremor/sway and fast-turn figures,
// the loop's return and the subject motion's amplitude.
#include <gtest/gtest.h>
#include <cmath>

#include "hapi_sim/imu_model.hpp"
#include "hapi_sim/scenario.hpp"
#include "hapi_sim/trajectories.hpp"

using namespace hapi_sim;

namespace {

ViewGeometry skinView() {  // as makeSkinScene()'s, without building its textures
  ViewGeometry v;
  v.centre = Eigen::Vector3d(0, 0, 0.09);
  v.along = Eigen::Vector3d::UnitX();
  v.up = Eigen::Vector3d::UnitY();
  v.standoff = 0.22;
  v.extent = 0.08;
  return v;
}

ViewGeometry globeView() {
  ViewGeometry v;
  v.along = Eigen::Vector3d::UnitX();
  v.up = Eigen::Vector3d::UnitZ();
  v.standoff = 0.55;
  v.extent = 0.1;
  v.globe = true;
  return v;
}

Eigen::Vector3d rotationLog(const Eigen::Quaterniond& q) {
  const Eigen::AngleAxisd aa(q);
  return aa.axis() * aa.angle();
}

// Finite differences of the pose only, compared with the exact derivatives.
void checkDerivatives(const std::function<MotionSample(double)>& f, const std::string& what, bool accelerations = true) {
  const double h = 1e-5, h2 = 2e-4;
  for (double t = 0.37; t < 25; t += 1.913) {
    const MotionSample m = f(t), a = f(t - h), b = f(t + h);
    const Eigen::Vector3d v_fd = (b.p - a.p) / (2 * h);
    EXPECT_LT((v_fd - m.v).norm(), 1e-6 * (1 + m.v.norm())) << what << " v at " << t;
    const Eigen::Vector3d w_fd = rotationLog(a.q.conjugate() * b.q) / (2 * h);
    EXPECT_LT((w_fd - m.omega).norm(), 1e-6 * (1 + m.omega.norm())) << what << " omega at " << t;
    if (!accelerations) continue;
    const MotionSample a2 = f(t - h2), b2 = f(t + h2);
    const Eigen::Vector3d acc_fd = (b2.p - 2 * m.p + a2.p) / (h2 * h2);
    EXPECT_LT((acc_fd - m.a).norm(), 1e-4 * (1 + m.a.norm())) << what << " a at " << t;
    const Eigen::Vector3d alpha_fd = (b.omega - a.omega) / (2 * h);
    EXPECT_LT((alpha_fd - m.alpha).norm(), 1e-5 * (1 + m.alpha.norm())) << what << " alpha at " << t;
  }
}

Pose extrinsic() { return CameraImuCalibration::makeDefault().T_cam_imu; }

}  // namespace

// The kinds that move (rest and orbit are covered by their own tests).
const TrajectoryKind kMoving[] = {TrajectoryKind::Smooth,  TrajectoryKind::Handheld,    TrajectoryKind::Fast,
                                  TrajectoryKind::Loop,    TrajectoryKind::Subject,     TrajectoryKind::Measurement,
                                  TrajectoryKind::MeasurementSubject, TrajectoryKind::Stage, TrajectoryKind::Tremor};

TEST(Trajectories, ExactDerivativesMatchFiniteDifferences) {
  for (const ViewGeometry& view : {skinView(), globeView()})
    for (const TrajectoryKind kind : kMoving) {
      const std::string name = trajectoryName(kind) + (view.globe ? " globe" : " skin");
      const auto device = makeDeviceMotion(kind, view, 7);
      const auto scene = makeSceneMotion(kind, view, 7);
      checkDerivatives([&](double t) { return device->sample(t); }, name + " device");
      checkDerivatives([&](double t) { return scene->sample(t); }, name + " scene");
      checkDerivatives([&](double t) { return attachedFrame(device->sample(t), extrinsic()); }, name + " imu");
      checkDerivatives([&](double t) { return relativeMotion(scene->sample(t), device->sample(t)); },
                       name + " camera in scene", false);
    }
}

// The legacy orbit (make_globe_bag) now has exact derivatives too.
TEST(Trajectories, GlobeOrbitLegacySampleIsExact) {
  const GlobeScene g = GlobeScene::makeDefault("");
  const Trajectory traj(g);
  const auto orbit = makeSmoothTrajectory(globeView());
  for (double t = 0; t < 20; t += 1.7) {
    const TrajectorySample s = traj.at(t);
    const MotionSample m = orbit->sample(t);
    EXPECT_LT((s.T_wc.p - m.p).norm(), 1e-15);
    EXPECT_LT(s.T_wc.q.angularDistance(m.q), 1e-12);
    EXPECT_LT((s.v_w - m.v).norm(), 1e-15);
    EXPECT_LT((s.omega_c - m.omega).norm(), 1e-15);
  }
}

// Noise off: RK4 on (q, v, p) driven by the simulated gyro and accelerometer
// from the true initial state reproduces the true IMU trajectory.
TEST(Imu, NoiseFreeReadingsIntegrateBackToTheTrajectory) {
  for (const TrajectoryKind kind : kMoving) {
    const auto device = makeDeviceMotion(kind, skinView(), 3);
    ImuModel model(ImuSpec::adis16448(), 200.0, 3, false, false);
    auto truth = [&](double t) { return attachedFrame(device->sample(t), extrinsic()); };
    auto read = [&](double t) { return model.measure(truth(t)); };
    const Eigen::Vector3d g(0, 0, -kGravity);
    MotionSample s0 = truth(1.0);
    Eigen::Quaterniond q = s0.q;
    Eigen::Vector3d v = s0.v, p = s0.p;
    const double h = 1.0 / 200.0;
    struct D { Eigen::Vector4d dq; Eigen::Vector3d dv, dp; };
    auto deriv = [&](double t, const Eigen::Quaterniond& qq, const Eigen::Vector3d& vv) {
      const ImuReading r = read(t);
      const Eigen::Quaterniond w(0, r.gyro.x(), r.gyro.y(), r.gyro.z());
      const Eigen::Quaterniond qd = qq * w;
      return D{0.5 * qd.coeffs(), qq * r.accel + g, vv};
    };
    auto step = [](const Eigen::Quaterniond& qq, const Eigen::Vector4d& dq, double s) {
      return Eigen::Quaterniond(Eigen::Vector4d(qq.coeffs() + s * dq)).normalized();
    };
    double t = 1.0;
    for (int i = 0; i < 400; ++i, t += h) {
      const D k1 = deriv(t, q, v);
      const D k2 = deriv(t + h / 2, step(q, k1.dq, h / 2), v + h / 2 * k1.dv);
      const D k3 = deriv(t + h / 2, step(q, k2.dq, h / 2), v + h / 2 * k2.dv);
      const D k4 = deriv(t + h, step(q, k3.dq, h), v + h * k3.dv);
      q = step(q, (k1.dq + 2 * k2.dq + 2 * k3.dq + k4.dq) / 6, h);
      p += h / 6 * (k1.dp + 2 * k2.dp + 2 * k3.dp + k4.dp);
      v += h / 6 * (k1.dv + 2 * k2.dv + 2 * k3.dv + k4.dv);
    }
    const MotionSample end = truth(t);
    EXPECT_LT((p - end.p).norm(), 1e-3) << trajectoryName(kind);
    EXPECT_LT((v - end.v).norm(), 1e-3) << trajectoryName(kind);
    EXPECT_LT(q.angularDistance(end.q), 1e-4) << trajectoryName(kind);
  }
}

TEST(Imu, GravitySignAtRest) {
  ImuModel model(ImuSpec::adis16448(), 200.0, 1, false, false);
  const StaticMotion level;
  const ImuReading r = model.measure(level.sample(0.0));
  EXPECT_LT((r.accel - Eigen::Vector3d(0, 0, kGravity)).norm(), 1e-12);  // reads +g up when resting
  EXPECT_LT(r.gyro.norm(), 1e-15);
  // The simulated device: the IMU's x axis is the optical axis; looking down
  // it reads about -g on x (tremor adds up to ~2 m/s^2).
  const auto still = makeStillTrajectory(skinView(), 1);
  const ImuReading d = model.measure(attachedFrame(still->sample(0.0), extrinsic()));
  EXPECT_LT(d.accel.x(), -0.75 * kGravity);
  EXPECT_LT(std::abs(d.accel.y()), 0.25 * kGravity);
  EXPECT_LT(std::abs(d.accel.z()), 0.25 * kGravity);
}

// The standing-still scenario: the device on a stand does not move at all
// (the filter's drift there is then all its own), in a static scene.
TEST(Trajectories, RestNeverMoves) {
  TrajectoryKind kind;
  ASSERT_TRUE(parseTrajectoryKind("rest", &kind));
  EXPECT_EQ(trajectoryName(kind), "rest");
  const auto device = makeDeviceMotion(kind, skinView(), 3);
  const MotionSample s0 = device->sample(0.0);
  for (double t = 0.0; t < 30.0; t += 0.37) {
    const MotionSample s = device->sample(t);
    EXPECT_LT((s.p - s0.p).norm(), 1e-15);
    EXPECT_LT(s.q.angularDistance(s0.q), 1e-12);
    EXPECT_LT(s.v.norm() + s.a.norm() + s.omega.norm() + s.alpha.norm(), 1e-12);
  }
  const auto scene = makeSceneMotion(kind, skinView(), 3);
  EXPECT_LT(scene->sample(7.0).p.norm() + scene->sample(7.0).v.norm(), 1e-15);
}

// Tremor only: the device held still moves by the hand's tremor alone
// (0.1-0.5 mm at 8-12 Hz: no more than a millimetre from its start, but
// millimetres per second), in a static scene.
TEST(Trajectories, TremorOnlyShakesInPlace) {
  TrajectoryKind kind;
  ASSERT_TRUE(parseTrajectoryKind("tremor", &kind));
  EXPECT_EQ(trajectoryName(kind), "tremor");
  const auto device = makeDeviceMotion(kind, skinView(), 3);
  const MotionSample s0 = device->sample(0.0);
  double max_dist = 0, max_speed = 0;
  for (double t = 0.0; t < 7.0; t += 0.001) {
    const MotionSample s = device->sample(t);
    max_dist = std::max(max_dist, (s.p - s0.p).norm());
    max_speed = std::max(max_speed, s.v.norm());
  }
  EXPECT_LT(max_dist, 2e-3);
  EXPECT_GT(max_speed, 3e-3);
  const auto scene = makeSceneMotion(kind, skinView(), 3);
  EXPECT_LT(scene->sample(3.0).p.norm() + scene->sample(3.0).v.norm(), 1e-15);
}

// Noise on: white-noise standard deviation = density * sqrt(rate), bias
// increments = random walk / sqrt(rate), turn-on bias seeded.
TEST(Imu, NoiseStatisticsMatchTheDensities) {
  const ImuSpec spec = ImuSpec::adis16448();
  const double rate = 200.0;
  ImuModel model(spec, rate, 11, true, false);
  const StaticMotion level;
  const MotionSample rest = level.sample(0.0);
  const int N = 200000;
  double wg = 0, wa = 0, dbg = 0, dba = 0;
  ImuReading prev = model.measure(rest);
  const ImuReading first = prev;
  for (int i = 0; i < N; ++i) {
    const ImuReading r = model.measure(rest);
    const Eigen::Vector3d eg = r.gyro - r.gyro_bias, ea = r.accel - Eigen::Vector3d(0, 0, kGravity) - r.accel_bias;
    wg += eg.squaredNorm();
    wa += ea.squaredNorm();
    dbg += (r.gyro_bias - prev.gyro_bias).squaredNorm();
    dba += (r.accel_bias - prev.accel_bias).squaredNorm();
    prev = r;
  }
  EXPECT_NEAR(std::sqrt(wg / (3.0 * N)), spec.gyro_noise_density * std::sqrt(rate), 0.01 * spec.gyro_noise_density * std::sqrt(rate));
  EXPECT_NEAR(std::sqrt(wa / (3.0 * N)), spec.accel_noise_density * std::sqrt(rate), 0.01 * spec.accel_noise_density * std::sqrt(rate));
  EXPECT_NEAR(std::sqrt(dbg / (3.0 * N)), spec.gyro_random_walk / std::sqrt(rate), 0.01 * spec.gyro_random_walk / std::sqrt(rate));
  EXPECT_NEAR(std::sqrt(dba / (3.0 * N)), spec.accel_random_walk / std::sqrt(rate), 0.01 * spec.accel_random_walk / std::sqrt(rate));
  EXPECT_GT(first.gyro_bias.norm(), 0.0);
  ImuModel other(spec, rate, 12, true, false);
  EXPECT_NE(other.measure(rest).gyro_bias, first.gyro_bias);
}

TEST(Imu, SaturatesAtTheRange) {
  const ImuSpec spec = ImuSpec::adis16448();
  ImuModel model(spec, 200.0, 1, false, true);
  MotionSample m;
  m.omega = Eigen::Vector3d(30, -30, 1);
  m.a = Eigen::Vector3d(400, 0, 0);
  const ImuReading r = model.measure(m);
  EXPECT_EQ(r.gyro.x(), spec.gyro_range);
  EXPECT_EQ(r.gyro.y(), -spec.gyro_range);
  EXPECT_EQ(r.gyro.z(), 1.0);
  EXPECT_EQ(r.accel.x(), spec.accel_range);
}

// Tremor 8-12 Hz, 0.1-0.5 mm per axis; sway 1-3 Hz, mm to cm and degrees.
TEST(HandMotionTest, TremorAndSwayAmplitudeAndFrequency) {
  for (uint32_t seed : {1u, 2u, 3u}) {
    const HandMotion tremor(seed, true, false), sway(seed, false, true);
    for (int axis = 0; axis < 3; ++axis) {
      for (const auto& s : tremor.tremorTranslation(axis)) {
        EXPECT_GE(s.hz, 8.0);
        EXPECT_LE(s.hz, 12.0);
      }
      for (const auto& s : sway.swayTranslation(axis)) {
        EXPECT_GE(s.hz, 1.0);
        EXPECT_LE(s.hz, 3.0);
      }
      EXPECT_TRUE(tremor.swayTranslation(axis).empty());
    }
    // Peak displacement per axis over 20 s, and the band of the motion: a
    // 8-12 Hz band-pass (DFT) keeps all the tremor's energy.
    const int n = 20000;
    const double dt = 1e-3;
    for (int axis = 0; axis < 3; ++axis) {
      std::vector<double> x(n);
      double peak_t = 0, peak_s = 0, peak_a = 0;
      for (int i = 0; i < n; ++i) {
        const Jet2 t = Jet2::time(i * dt);
        const V3<Jet2> tr = tremor.translation(t), sw = sway.translation(t), an = sway.angles(t);
        const double c[3] = {tr.x.v, tr.y.v, tr.z.v}, s[3] = {sw.x.v, sw.y.v, sw.z.v}, a[3] = {an.x.v, an.y.v, an.z.v};
        x[i] = c[axis];
        peak_t = std::max(peak_t, std::abs(c[axis]));
        peak_s = std::max(peak_s, std::abs(s[axis]));
        peak_a = std::max(peak_a, std::abs(a[axis]));
      }
      EXPECT_GT(peak_t, 0.1e-3);
      EXPECT_LT(peak_t, 0.5e-3);
      EXPECT_GT(peak_s, 1e-3);
      EXPECT_LT(peak_s, 2e-2);
      EXPECT_GT(peak_a, 0.5 * M_PI / 180);
      EXPECT_LT(peak_a, 5.0 * M_PI / 180);
      double in_band = 0, total = 0;
      for (int f = 1; f <= 50 * 20; ++f) {  // 0.05 Hz bins up to 50 Hz
        double re = 0, im = 0;
        for (int i = 0; i < n; i += 2) {
          re += x[i] * std::cos(2 * M_PI * f * i / n);
          im += x[i] * std::sin(2 * M_PI * f * i / n);
        }
        const double pw = re * re + im * im, hz = f / 20.0;
        total += pw;
        if (hz >= 7.9 && hz <= 12.1) in_band += pw;
      }
      EXPECT_GT(in_band / total, 0.95);
    }
  }
  // The seed draws other phases.
  const HandMotion a(1, true, true), b(2, true, true);
  EXPECT_NE(a.translation(Jet2::time(0.5)).x.v, b.translation(Jet2::time(0.5)).x.v);
}

TEST(Trajectories, FastTurnsReachTheirPeaks) {
  for (const ViewGeometry& view : {skinView(), globeView()}) {
    const auto fast = makeFastTrajectory(view, 1);
    double w = 0, v = 0;
    for (double t = 0; t < 10; t += 0.005) {
      const MotionSample m = fast->sample(t);
      w = std::max(w, m.omega.norm());
      v = std::max(v, m.v.norm());
    }
    EXPECT_GE(w, 3.0);
    EXPECT_GE(v, 1.0);
    EXPECT_LT(w, 8.0);
    EXPECT_LT(v, 2.0);
  }
}

// The loop leaves the start area (the view centre at t = 0 is out of the
// image half-way) and comes back to it.
TEST(Trajectories, LoopLeavesAndReturns) {
  const StereoRigModel rig = StereoRigModel::makeDefault();
  for (const ViewGeometry& view : {skinView(), globeView()}) {
    const auto loop = makeLoopTrajectory(view, 1);
    const double period = view.globe ? 24.0 : 20.0;
    const Pose start = loop->pose(0.0), away = loop->pose(period / 2), back = loop->pose(period);
    // The surface point seen at the image centre at the start.
    const Eigen::Vector3d seen = view.globe ? Eigen::Vector3d(view.centre + 0.2 * view.normal()) : view.centre;
    Eigen::Vector2d px;
    const bool in_front = project(seen, away, rig.left, &px);
    const bool visible = in_front && px.x() >= 0 && px.x() < 640 && px.y() >= 0 && px.y() < 480 &&
                         (!view.globe || (seen - view.centre).dot(away.p - seen) > 0);
    EXPECT_FALSE(visible) << (view.globe ? "globe" : "skin");
    EXPECT_GT((away.p - start.p).norm(), 0.3);
    EXPECT_LT((back.p - start.p).norm(), 0.03);  // sway is not periodic: back within it
    EXPECT_LT(back.q.angularDistance(start.q), 0.1);
  }
}

// Subject motion: the device is still but for tremor; the scene moves by
// centimetres and degrees.
TEST(Trajectories, SubjectMovesTheDeviceIsStill) {
  const auto device = makeStillTrajectory(skinView(), 1);
  const auto scene = makeSubjectSceneMotion(skinView(), 1);
  const Pose d0 = device->pose(0.0), s0 = scene->pose(0.0);
  double dev = 0, disp = 0, rot = 0;
  for (double t = 0; t < 20; t += 0.01) {
    dev = std::max(dev, (device->pose(t).p - d0.p).norm());
    const Pose s = scene->pose(t);
    disp = std::max(disp, (s.p + s.q * skinView().centre - s0.p - s0.q * skinView().centre).norm());
    rot = std::max(rot, s.q.angularDistance(s0.q));
  }
  EXPECT_LT(dev, 1e-3);
  EXPECT_GT(disp, 0.01);
  EXPECT_LT(disp, 0.06);
  EXPECT_GT(rot, 1.0 * M_PI / 180);
  EXPECT_LT(rot, 8.0 * M_PI / 180);
}
