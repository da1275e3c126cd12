// eskf_replay: runs the ROS-free filter on front-end frames dumped from a bag
// (dump_frames.py), or on the synthetic orbit (stream_source.hpp), without
// any real-time pressure, and prints the accuracy
// numbers the e2e test checks (ATE after rigid alignment, % of distance, map
// RMS to the true sphere) plus per-frame filter statistics. A development
// tool for studying accuracy and consistency; not a test.
//
//   eskf_replay FRAMES.txt|--synthetic-orbit[=SEED,...] [--every k] [--start-frame N] [--gap START LEN] [--verbose]
//               [--out PREFIX] [key=value ...]
//
// With motion_model=gyro or inertial the stream's IMU samples (and its
// extrinsic) drive the prediction exactly as in the nodelet: every sample up
// to a frame's stamp is applied before the frame, samples before the first
// frame are dropped. --out PREFIX writes PREFIX_estimate.tum (the filter's
// camera pose per frame, TUM: t x y z qx qy qz qw) and, with an IMU model,
// PREFIX_imu_rate.txt (the nodelet's IMU-rate output: t, pose as in TUM, then
// the camera-frame linear and angular velocity), PREFIX_covariance.txt (per
// frame, the 6x6 pose covariance as the odometry message states it) and
// PREFIX_frame_twist.txt (per frame: t, the filter's camera-frame linear and
// angular velocity) and PREFIX_anchor.txt (the instant and camera pose that
// define the filter's world: the first processed frame's), for
// tools/eval/accuracy.py, and PREFIX_map.txt (every map_publish_rate period
// of stream time, after the frame that ends it, the landmarks' positions in
// the filter's world, the frame of PREFIX_imu_rate.txt's poses, as the
// nodelet's map snapshot gives them: one line "t N x1 y1 z1 ... xN yN zN"),
// for surface_motion_replay.
//
// Without overrides it runs the default EskfSettings, i.e. the tuned filter of
// config/eskf.yaml. key=value overrides any EskfSettings field (same names as
// config/eskf.yaml; --help lists them with defaults and ranges).
// --every k processes every k-th frame (simulates a back end that drops frames).
// --start-frame N starts at the stream's frame N (0-based): the reset, the
// inertial alignment and the world come from there (how much a figure
// depends on where the filter started).
// --gap START LEN skips the frames in [START, START+LEN) s after the first
// one (simulates a front-end outage, e.g. a restart).
#include "hapi_eskf/backend/association.hpp"
#include "hapi_eskf/backend/measurement_model.hpp"
#include "hapi_eskf/covariance/covariance_backend.hpp"
#include "hapi_eskf/eskf/eskf.hpp"
#include "hapi_eskf/eskf/pose_propagator.hpp"
#include "hapi_eskf/eskf/storage_factory.hpp"
#include "landmark_stream.hpp"
#include "stream_source.hpp"

#include <hapi_nodelet_kit/sample_quantiles.hpp>

#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

using namespace hapi_eskf;

namespace {

// The nodelet's parameter defaults (ros/nodelet_params.def, plain types only).
struct NodeletDefaults {
#define HAPI_FIELD(type, name, default_value, range, unit, doc) type name = default_value;
#include "hapi_eskf/ros/nodelet_params.def"
#undef HAPI_FIELD
};

// Umeyama without scale: R, t minimising sum |R e + t - g|^2.
void alignRigid(const std::vector<Vec3>& e, const std::vector<Vec3>& g, Mat3* R, Vec3* t) {
  Vec3 me = Vec3::Zero(), mg = Vec3::Zero();
  for (std::size_t i = 0; i < e.size(); ++i) { me += e[i]; mg += g[i]; }
  me /= e.size();
  mg /= g.size();
  Mat3 cov = Mat3::Zero();
  for (std::size_t i = 0; i < e.size(); ++i) cov += (g[i] - mg) * (e[i] - me).transpose();
  Eigen::JacobiSVD<Mat3> svd(cov, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 D = Mat3::Identity();
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0) D(2, 2) = -1;
  *R = svd.matrixU() * D * svd.matrixV().transpose();
  *t = mg - *R * me;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string usage = std::string("usage: eskf_replay ") + tools::kStreamSourceUsage +
                            " [--every k] [--start-frame N] [--gap START LEN] [--gtcheck] [--verbose] [--out PREFIX] "
                            "[key=value ...]\n"
                            "       eskf_replay --help   (lists the settings key=value may set)\n";
  if (argc >= 2 && std::string(argv[1]) == "--help") {
    std::cout << usage << "settings (EskfSettings, config/eskf.yaml):\n";
    const EskfSettings defaults;
    forEachField(defaults, [](const FieldInfo& f, const auto& v) { std::cout << "  " << describeField(f, v) << "\n"; });
    return 0;
  }
  if (argc < 2) {
    std::cerr << usage;
    return 1;
  }
  EskfSettings s;
  int every = 1, start_frame = 0;
  double gap_start = -1.0, gap_len = 0.0;
  bool verbose = false;
  std::string out_prefix;
  bool gtcheck = false;  // association and measurement errors against the ground truth
  for (int i = 2; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--every" && i + 1 < argc) { every = std::stoi(argv[++i]); continue; }
    if (a == "--start-frame" && i + 1 < argc) { start_frame = std::max(0, std::stoi(argv[++i])); continue; }
    if (a == "--gap" && i + 2 < argc) {
      gap_start = std::stod(argv[++i]);
      gap_len = std::stod(argv[++i]);
      continue;
    }
    if (a == "--verbose") { verbose = true; continue; }
    if (a == "--out" && i + 1 < argc) { out_prefix = argv[++i]; continue; }
    if (a == "--gtcheck") { gtcheck = true; continue; }
    const auto eq = a.find('=');
    if (eq == std::string::npos) {
      std::cerr << "unknown argument " << a << "\n" << usage;
      return 1;
    }
    const std::string err = setFieldFromText(&s, a.substr(0, eq), a.substr(eq + 1));
    if (!err.empty()) {
      std::cerr << err << " (eskf_replay --help lists the settings)\n";
      return 1;
    }
  }
  if (!s.validate().empty()) { std::cerr << s.validate() << "\n"; return 1; }

  tools::LandmarkStream stream;
  std::string read_error;
  if (!tools::loadStreamSource(argv[1], &stream, &read_error)) {
    std::cerr << read_error << "\n";
    return 1;
  }
  // --start-frame: the stream begins there (the filter's reset and world).
  if (start_frame >= static_cast<int>(stream.frames.size())) {
    std::cerr << "--start-frame " << start_frame << " beyond the stream's " << stream.frames.size() << " frames\n";
    return 1;
  }
  stream.frames.erase(stream.frames.begin(), stream.frames.begin() + start_frame);
  const std::vector<StereoFrame>& frames = stream.frames;
  const std::vector<tools::TruePose>& gt = stream.truth;
  const Vec3 centre = stream.globe_centre;
  const double radius = stream.globe_radius;
  std::fprintf(stderr, "%zu frames, %zu IMU samples, %zu gt, globe r=%.3f\n", frames.size(), stream.imu.size(),
               gt.size(), radius);
  if (frames.empty()) return 1;
  const bool use_imu = s.motion_model != MotionModelKind::kConstantVelocity;
  if (use_imu && (stream.imu.empty() || !stream.extrinsic)) {
    std::cerr << "motion_model " << toString(s.motion_model) << " needs IMU samples and an extrinsic in the stream\n";
    return 1;
  }

  std::string err;
  auto backend = makeBackend(s, frames[0].descriptor_length, &err);
  if (!backend) { std::cerr << err << "\n"; return 1; }
  Eskf eskf(s, std::move(backend), stream.extrinsic.value_or(CameraExtrinsic()));
  eskf.reset(PoseState(), frames[0].stamp);
  // The instant that defines the filter's world (its first processed frame)
  // and the camera pose there: PREFIX_anchor.txt.
  std::FILE* anchor_file = out_prefix.empty() ? nullptr : std::fopen((out_prefix + "_anchor.txt").c_str(), "w");
  bool anchored = false;
  // The nodelet's order: IMU samples on the camera clock, every one up to a
  // frame's stamp applied before it; the IMU-rate output re-based after each
  // frame and stepped through the samples up to the next one.
  std::vector<ImuSample> imu;
  for (const ImuSample& m : stream.imu) imu.push_back(imuSampleOnCameraClock(m.stamp, m.gyro, m.accel, s));
  std::size_t next_imu = 0;
  PosePropagator imu_rate(s);
  std::FILE* est_file = out_prefix.empty() ? nullptr : std::fopen((out_prefix + "_estimate.tum").c_str(), "w");
  std::FILE* cov_file = out_prefix.empty() ? nullptr : std::fopen((out_prefix + "_covariance.txt").c_str(), "w");
  std::FILE* twist_file = out_prefix.empty() ? nullptr : std::fopen((out_prefix + "_frame_twist.txt").c_str(), "w");
  std::FILE* rate_file =
      out_prefix.empty() || !use_imu ? nullptr : std::fopen((out_prefix + "_imu_rate.txt").c_str(), "w");
  std::FILE* map_file = out_prefix.empty() ? nullptr : std::fopen((out_prefix + "_map.txt").c_str(), "w");
  // The nodelet's default ~map_publish_rate, in stream time.
  const double map_period = 1.0 / NodeletDefaults().map_publish_rate;
  double next_map_snapshot = -1e300;
  auto writeMapSnapshot = [&](double t) {
    if (map_file == nullptr || t < next_map_snapshot) return;
    next_map_snapshot = t + map_period;
    const auto lms = eskf.landmarks();
    std::fprintf(map_file, "%.9f %zu", t, lms.size());
    for (const auto& l : lms) std::fprintf(map_file, " %.6f %.6f %.6f", l.position.x(), l.position.y(), l.position.z());
    std::fprintf(map_file, "\n");
  };
  auto writePose = [](std::FILE* f, double t, const PoseState& x) {
    std::fprintf(f, "%.9f %.9f %.9f %.9f %.9f %.9f %.9f %.9f", t, x.p.x(), x.p.y(), x.p.z(), x.q.x(), x.q.y(),
                 x.q.z(), x.q.w());
  };
  // Written once, with the first processed frame, whose camera is the
  // filter's world (the reset for the camera models; the inertial model
  // aligns to gravity again at that frame: docs/DESIGN.md "Inertial
  // initialisation").
  auto writeAnchorOnce = [&] {
    if (anchor_file == nullptr || anchored) return;
    writePose(anchor_file, eskf.time(), eskf.pose());
    std::fprintf(anchor_file, "\n");
    anchored = true;
  };
  int imu_rejected = 0, awaiting = 0, vision_led = 0, scene_moving = 0, relocalised = 0, errors = 0;
  int frames_still = 0, zero_velocity_fused = 0;
  std::vector<double> still_speed;  // per frame with a verdict
  std::vector<double> frame_ms;  // the filter's wall time per processed frame

  std::vector<Vec3> est, ref;
  double sum_t = 0, nis_sum = 0;
  int nis_n = 0, n_proc = 0;
  std::map<uint64_t, Vec3> gt_point;  // landmark id -> true world point of its first measurement
  std::map<uint64_t, Mat3> gt_cov;    // landmark id -> world covariance of its first measurement
  std::map<uint64_t, Vec3> gt_z;      // landmark id -> its first measurement (camera frame)
  double rep_nees = 0, lat_sq = 0, ray_sq = 0, lat_pred = 0, ray_pred = 0;
  int rep_n = 0;
  std::vector<double> rep_all, rep_limb, rep_face, lat_ang;
  int n_assoc = 0, n_wrong = 0, n_meas = 0, n_meas_out = 0;
  double meas_nees = 0, ray_bias = 0, ray_rel = 0;
  for (std::size_t fi = 0; fi < frames.size(); fi += every) {
    const double t_rel = frames[fi].stamp - frames[0].stamp;
    if (t_rel >= gap_start && t_rel < gap_start + gap_len) continue;
    const tools::TruePose* g0 = nullptr;
    for (const tools::TruePose& g : gt)
      if (!g0 || std::abs(g.t - frames[fi].stamp) < std::abs(g0->t - frames[fi].stamp)) g0 = &g;
    const Mat3 Rg = g0->q.toRotationMatrix();
    if (gtcheck) {
      // Measurement vs the true surface point on its ray (front-end consistency).
      for (const auto& m : frames[fi].measurements) {
        const Vec3 d = m.z.normalized();
        const Vec3 o = Rg.transpose() * (centre - g0->p);  // centre in camera frame
        const double b = d.dot(o), c = o.squaredNorm() - radius * radius, disc = b * b - c;
        if (disc < 0) { ++n_meas_out; continue; }
        const Vec3 truth = (b - std::sqrt(disc)) * d;
        const Vec3 e = m.z - truth;
        const double nees = e.dot(m.Cz.ldlt().solve(e));
        if (nees <= 100) { ray_bias += m.z.norm() - truth.norm(); ray_rel += (m.z.norm() - truth.norm()) / truth.norm(); }
        ++n_meas;
        if (nees > 100) ++n_meas_out; else meas_nees += nees;
      }
      eskf.predictTo(frames[fi].stamp);  // processFrame then predicts over dt = 0
      std::vector<Vec3> pos;
      std::vector<uint64_t> ids;
      for (const auto& l : eskf.landmarks()) { pos.push_back(l.position); ids.push_back(l.id); }
      Association as;
      associate(frames[fi], eskf.pose(), eskf.motionModel().cameraJacobian(eskf.state()), pos, eskf.backend(), s,
                &as);
      int wrong = 0, tot = 0;
      for (std::size_t i = 0; i < as.slot.size(); ++i) {
        if (as.slot[i] < 0) continue;
        ++tot;
        const Vec3 w = Rg * frames[fi].measurements[i].z + g0->p;
        const uint64_t id = ids[as.slot[i]];
        const Vec3 e = w - gt_point[id];
        if (e.norm() > 0.015) { ++wrong; continue; }
        // Repeatability: the same physical point measured twice (this frame and
        // the first observation), both mapped to the world with the true poses.
        const StereoMeasurement& m = frames[fi].measurements[i];
        const Mat3 S = Rg * m.Cz * Rg.transpose() + gt_cov[id];
        const double nees_i = e.dot(S.ldlt().solve(e));
        rep_nees += nees_i;
        rep_all.push_back(nees_i);
        {
          // Incidence: cosine between the viewing ray and the sphere normal (0 = limb).
          const Vec3 X = gt_point[id] - centre;
          const double inc = std::abs(X.normalized().dot((gt_point[id] - g0->p).normalized()));
          (inc < 0.4 ? rep_limb : rep_face).push_back(nees_i);
        }
        const Vec3 ray = (Rg * m.z).normalized();
        const double er = e.dot(ray);
        {
          // Lateral angular difference per axis (two orthogonal axes to the ray).
          const Vec3 a1 = ray.unitOrthogonal(), a2 = ray.cross(a1);
          const double dep = (w - g0->p).norm();
          lat_ang.push_back(std::abs(e.dot(a1)) / dep);
          lat_ang.push_back(std::abs(e.dot(a2)) / dep);
        }
        ray_sq += er * er;
        lat_sq += (e - er * ray).squaredNorm() / 2;
        ray_pred += ray.dot(S * ray);
        lat_pred += (S.trace() - ray.dot(S * ray)) / 2;
        ++rep_n;
      }
      n_assoc += tot;
      n_wrong += wrong;
      if (verbose) std::printf("  assoc %d wrong %d\n", tot, wrong);
    }
    // IMU samples up to this frame: the IMU-rate output between frames, then the filter.
    for (; use_imu && next_imu < imu.size() && imu[next_imu].stamp <= frames[fi].stamp; ++next_imu) {
      const ImuSample& m = imu[next_imu];
      if (m.stamp <= eskf.time()) continue;
      if (rate_file && imu_rate.valid() && m.stamp > imu_rate.time() && imu_rate.step(m) == Status::kOk &&
          imu_rate.publishable()) {
        writePose(rate_file, m.stamp, imu_rate.pose());
        const PoseState c = imu_rate.pose();
        std::fprintf(rate_file, " %.9f %.9f %.9f %.9f %.9f %.9f\n", c.v.x(), c.v.y(), c.v.z(), c.w.x(), c.w.y(),
                     c.w.z());
      }
      if (eskf.addImu(m) != Status::kOk) ++imu_rejected;
    }
    std::map<uint64_t, int> before;
    for (const auto& l : eskf.landmarks()) before[l.id] = 1;
    IterationReport rep;
    const Status st = eskf.processFrame(frames[fi], &rep);
    if (st == Status::kAwaitingImu) {
      ++awaiting;
      continue;
    }
    if (est_file && !rep.relocalising) {
      writePose(est_file, frames[fi].stamp, eskf.pose());
      std::fprintf(est_file, "\n");
      // The odometry message's convention (tools/eval trajectory_io.read_covariances).
      const Mat6 C = poseCovarianceInWorldAxes(eskf.pose(), eskf.cameraCovariance());
      std::fprintf(cov_file, "%.9f", frames[fi].stamp);
      for (int r = 0; r < 6; ++r)
        for (int c = 0; c < 6; ++c) std::fprintf(cov_file, " %.9g", C(r, c));
      std::fprintf(cov_file, "\n");
      const PoseState c = eskf.pose();
      std::fprintf(twist_file, "%.9f %.9f %.9f %.9f %.9f %.9f %.9f\n", frames[fi].stamp, c.v.x(), c.v.y(), c.v.z(),
                   c.w.x(), c.w.y(), c.w.z());
    }
    relocalised += rep.relocalised;
    if (st == Status::kOk && !rep.relocalising) writeAnchorOnce();
    if (st == Status::kOk) writeMapSnapshot(frames[fi].stamp);
    if (use_imu && st == Status::kOk) imu_rate.rebase(eskf, rep.scene_moving);
    errors += st != Status::kOk;
    vision_led += rep.vision_led;
    scene_moving += rep.scene_moving;
    frames_still += rep.zero_velocity.still.still;
    zero_velocity_fused += rep.zero_velocity.fused;
    if (std::isfinite(rep.zero_velocity.still.median_speed))
      still_speed.push_back(rep.zero_velocity.still.median_speed);
    if (gtcheck)
      for (const auto& l : eskf.landmarks()) {
        if (before.count(l.id)) continue;
        for (const auto& m : frames[fi].measurements)
          if ((initLandmark(eskf.frameCamera(), m.z) - l.position).norm() < 1e-12) {
            gt_point[l.id] = Rg * m.z + g0->p;
            gt_cov[l.id] = Rg * m.Cz * Rg.transpose();
            gt_z[l.id] = m.z;
          }
      }
    ++n_proc;
    sum_t += rep.t_total_ms;
    frame_ms.push_back(rep.t_total_ms);
    if (rep.n_updated > 0) { nis_sum += rep.mean_nis; ++nis_n; }
    // Nearest ground truth (same stamps in the generated bags).
    const tools::TruePose* best = nullptr;
    for (const tools::TruePose& g : gt)
      if (!best || std::abs(g.t - frames[fi].stamp) < std::abs(best->t - frames[fi].stamp)) best = &g;
    // Frames held back while relocalising are not published by the nodelet.
    if (best && std::abs(best->t - frames[fi].stamp) < 0.006 && !rep.relocalising) {
      est.push_back(eskf.pose().p);
      ref.push_back(best->p);
    }
    if (verbose) {
      const NominalState& x = eskf.state();
      std::printf("t=%.2f st=%s meas=%d cand=%d gated=%d upd=%d add=%d rem=%d K=%d nis=%.2f ms=%.1f sig_p=%.4f%s"
                  " still_speed=%.4f%s v=(%.3f %.3f %.3f) b_g=(%.4f %.4f %.4f) b_a=(%.3f %.3f %.3f)"
                  " g=(%.3f %.3f %.3f)\n",
                  frames[fi].stamp - frames[0].stamp, toString(st), rep.n_measurements, rep.n_candidates,
                  rep.n_gated_out, rep.n_updated, rep.n_added, rep.n_removed, rep.n_landmarks, rep.mean_nis,
                  rep.t_total_ms, std::sqrt(eskf.poseCovariance().block<3, 3>(0, 0).trace()),
                  rep.vision_led ? " VISION" : "", rep.zero_velocity.still.median_speed,
                  rep.zero_velocity.fused ? " ZUPT" : (rep.zero_velocity.tested ? " ZUPT-gated" : ""), x.v.x(),
                  x.v.y(), x.v.z(), x.b_g.x(), x.b_g.y(), x.b_g.z(), x.b_a.x(), x.b_a.y(), x.b_a.z(), x.g.x(),
                  x.g.y(), x.g.z());
    }
  }
  if (est_file) std::fclose(est_file);
  if (cov_file) std::fclose(cov_file);
  if (anchor_file) std::fclose(anchor_file);
  if (twist_file) std::fclose(twist_file);
  std::printf("events: %d relocalisations, %d frames vision-led (%d scene moving), %d frames rejected\n",
              relocalised, vision_led, scene_moving, errors);
  if (rate_file) std::fclose(rate_file);
  if (map_file) std::fclose(map_file);
  if (use_imu) {
    std::printf("motion model %s: %d frames waited for the gravity alignment, %d IMU samples rejected, "
                "vision led in %d frames (scene moving in %d)\n",
                toString(s.motion_model), awaiting, imu_rejected, vision_led, scene_moving);
    std::sort(still_speed.begin(), still_speed.end());
    const auto pct = [&](double q) {
      return still_speed.empty() ? std::nan("")
                                     : still_speed[static_cast<std::size_t>(q * (still_speed.size() - 1))];
    };
    std::printf("still frames: %d of %d tested (median apparent speed p10 / p50 / p90 %.4f / %.4f / %.4f m/s), "
                "%d zero-velocity updates fused\n",
                frames_still, static_cast<int>(still_speed.size()), pct(0.1), pct(0.5), pct(0.9),
                zero_velocity_fused);
  }
  const CalibrationEstimate calib = eskf.calibration();
  if (calib.time_offset_valid)
    std::printf("calibration: time offset %.3f ms (sigma %.3f ms, configured %.3f ms)\n", calib.time_offset * 1e3,
                calib.time_offset_sigma * 1e3, s.imu_time_offset * 1e3);
  if (calib.extrinsic_valid) {
    constexpr double kDeg = 180.0 / M_PI;
    const Vec3 dr = calib.rotation_change * kDeg, sr = calib.rotation_sigma * kDeg;
    std::printf("calibration: rotation change %.4f %.4f %.4f deg (sigma %.4f %.4f %.4f), translation %.4f %.4f "
                "%.4f m (sigma %.2f %.2f %.2f mm)\n",
                dr.x(), dr.y(), dr.z(), sr.x(), sr.y(), sr.z(), calib.p_bc.x(), calib.p_bc.y(), calib.p_bc.z(),
                calib.p_bc_sigma.x() * 1e3, calib.p_bc_sigma.y() * 1e3, calib.p_bc_sigma.z() * 1e3);
  }
  if (use_imu && s.imu_noise_in_situ) {
    const ImuNoiseDensity& n = eskf.imuNoise();
    std::printf("IMU noise in situ: gyro %.3g %.3g %.3g rad/s/sqrt(Hz) (configured %.3g), accelerometer %.3g %.3g "
                "%.3g m/s^2/sqrt(Hz) (configured %.3g)\n",
                n.gyro.x(), n.gyro.y(), n.gyro.z(), s.gyro_noise_density, n.accel.x(), n.accel.y(), n.accel.z(),
                s.accel_noise_density);
  }
  if (est.size() < 3) { std::cerr << "too few poses\n"; return 1; }
  Mat3 R;
  Vec3 t;
  alignRigid(est, ref, &R, &t);
  double se = 0, dist = 0, emax = 0;
  for (std::size_t i = 0; i < est.size(); ++i) {
    const double e = (R * est[i] + t - ref[i]).norm();
    se += e * e;
    emax = std::max(emax, e);
    if (i) dist += (ref[i] - ref[i - 1]).norm();
  }
  const double ate = std::sqrt(se / est.size());
  double sm = 0;
  const auto lms = eskf.landmarks();
  double sm1 = 0, smn = 0;
  int n1 = 0, nn = 0, n_far = 0;
  double d_mean = 0;
  for (const auto& l : lms) {
    const double d = (R * l.position + t - centre).norm() - radius;
    sm += d * d;
    if (l.times_observed <= 1) { sm1 += d * d; ++n1; } else { smn += d * d; ++nn; }
    n_far += std::abs(d) > 0.01;
    d_mean += d / lms.size();
  }
  std::printf("map: seen once %d (rms %.4f m), seen more %d (rms %.4f m), |d| > 1 cm: %d, mean signed %.4f m\n", n1,
              n1 ? std::sqrt(sm1 / n1) : 0.0, nn, nn ? std::sqrt(smn / nn) : 0.0, n_far, d_mean);
  // Per-frame filter time distribution (nearest-rank percentiles).
  if (!frame_ms.empty()) {
    const auto pct = [&](double q) { return hapi_nodelet_kit::quantileNearestRank(frame_ms, q, 0.0); };
    std::printf("frame time [ms]: p50 %.2f p99 %.2f max %.2f over %zu frames (backend %s)\n", pct(0.5), pct(0.99),
                pct(1.0), frame_ms.size(), eskf.backend().name());
  }
  std::printf("frames=%d ate=%.4f m (%.2f %% of %.3f m) max=%.4f map_rms=%.4f m (%zu pts) mean_nis=%.2f mean_ms=%.1f\n",
              n_proc, ate, 100 * ate / dist, dist, emax, lms.empty() ? 0.0 : std::sqrt(sm / lms.size()), lms.size(),
              nis_n ? nis_sum / nis_n : 0.0, sum_t / n_proc);
  if (gtcheck && !rep_all.empty()) {
    std::sort(rep_all.begin(), rep_all.end());
    auto q = [&](double f) { return rep_all[static_cast<std::size_t>(f * (rep_all.size() - 1))]; };
    int over = 0;
    for (double v : rep_all) over += v > 11.345;
    std::printf("repeatability NEES quantiles: 50%% %.2f (chi2_3: 2.37) 90%% %.2f (6.25) 99%% %.2f (11.3); > 11.3: %.1f %%\n",
                q(0.5), q(0.9), q(0.99), 100.0 * over / rep_all.size());
  }
  if (!lat_ang.empty()) {
    std::sort(lat_ang.begin(), lat_ang.end());
    // Difference of two observations: per-observation sigma = 1.4826 MAD / sqrt(2).
    std::printf("lateral angular difference: median |d| %.3f mrad -> robust per-observation sigma %.3f mrad; "
                "90%% |d| %.3f mrad, 99%% %.3f mrad\n",
                1e3 * lat_ang[lat_ang.size() / 2], 1e3 * 1.4826 * lat_ang[lat_ang.size() / 2] / std::sqrt(2.0),
                1e3 * lat_ang[lat_ang.size() * 9 / 10], 1e3 * lat_ang[lat_ang.size() * 99 / 100]);
  }
  for (auto* v : {&rep_limb, &rep_face}) {
    if (v->empty()) continue;
    std::sort(v->begin(), v->end());
    std::printf("  %s: n=%zu median %.2f 90%% %.2f\n", v == &rep_limb ? "grazing (cos<0.4)" : "facing", v->size(),
                (*v)[v->size() / 2], (*v)[v->size() * 9 / 10]);
  }
  if (gtcheck)
    std::printf("repeatability of correct associations (%d): NEES %.2f (3 if consistent); rms along ray %.2f mm "
                "(predicted %.2f), lateral per axis %.2f mm (predicted %.2f)\n",
                rep_n, rep_nees / std::max(1, rep_n), 1e3 * std::sqrt(ray_sq / rep_n), 1e3 * std::sqrt(ray_pred / rep_n),
                1e3 * std::sqrt(lat_sq / rep_n), 1e3 * std::sqrt(lat_pred / rep_n));
  if (gtcheck)
    std::printf("gtcheck: associations %d wrong %d (%.1f %%); measurements %d, mean NEES vs true surface %.2f "
                "(outliers > 100 or off-sphere: %d); mean range error %.3f mm (%.3f %%)\n",
                n_assoc, n_wrong, 100.0 * n_wrong / std::max(1, n_assoc), n_meas,
                meas_nees / std::max(1, n_meas - n_meas_out), n_meas_out,
                1e3 * ray_bias / std::max(1, n_meas - n_meas_out), 100 * ray_rel / std::max(1, n_meas - n_meas_out));
  return 0;
}
