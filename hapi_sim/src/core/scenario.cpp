// Scenario: assembles one simulated recording from the catalogue and answers
// for its timing, ground truth and sensor data (docs/DESIGN.md "Data").
#include <algorithm>
#include <cmath>
#include <sstream>

#include "hapi_sim/scenario.hpp"

#include <opencv2/imgproc.hpp>
#include "hapi_sim/text_format.hpp"

namespace hapi_sim {
namespace {

void setLens(const LensDistortion& d, CameraModel* c) {
  c->k1 = d.k1; c->k2 = d.k2; c->p1 = d.p1; c->p2 = d.p2; c->k3 = d.k3;
}

// The rig at a fraction of its resolution: focal lengths scale, the
// principal point keeps its place in the image (pixel centres at integers).
// The profile's lens, where it has one.
StereoRigModel scaledRig(double s, const RealismProfile& profile) {
  StereoRigModel rig = StereoRigModel::makeDefault();
  if (profile.real_lens) {
    setLens(profile.left_lens, &rig.left);
    setLens(profile.right_lens, &rig.right);
  }
  for (CameraModel* c : {&rig.left, &rig.right}) {
    c->width = static_cast<int>(std::lround(c->width * s));
    c->height = static_cast<int>(std::lround(c->height * s));
    c->fx *= s; c->fy *= s;
    c->cx = (c->cx + 0.5) * s - 0.5;
    c->cy = (c->cy + 0.5) * s - 0.5;
  }
  return rig;
}

constexpr double kRightGainRatio = 0.97;  // the right sensor is 3 % less sensitive
constexpr uint32_t kImagingCamera = 2;     // noise seeds: left 0, right 1, imaging 2

std::unique_ptr<Scene> makeScene(const ScenarioConfig& c) {
  switch (c.scene) {
    case SceneKind::Globe: return makeGlobeSimScene(c.globe_texture);
    case SceneKind::Skin: return makeSkinScene(c.skin_texture_seed);
    case SceneKind::Patch: return makePatchScene();
    case SceneKind::Chessboard: return makeChessboardScene();
  }
  return nullptr;
}

int64_t countAt(double duration, double rate) {
  return std::max<int64_t>(1, static_cast<int64_t>(std::floor(duration * rate + 1e-9)));
}

}  // namespace

bool parseSceneKind(const std::string& name, SceneKind* kind) {
  if (name == "globe") { *kind = SceneKind::Globe; return true; }
  if (name == "skin") { *kind = SceneKind::Skin; return true; }
  if (name == "patch") { *kind = SceneKind::Patch; return true; }
  if (name == "chessboard") { *kind = SceneKind::Chessboard; return true; }
  return false;
}

bool parseImagingContent(const std::string& name, ImagingContent* content) {
  if (name == "texture") { *content = ImagingContent::Texture; return true; }
  if (name == "perfusion") { *content = ImagingContent::Perfusion; return true; }
  return false;
}

std::string ScenarioConfig::validate() const {
  if (!(duration > 0 && duration <= 3600)) return "duration must be in (0, 3600] s";
  if (!(rate > 0 && rate <= 100)) return "rate must be in (0, 100] Hz";
  if (!(imu_rate >= rate && imu_rate <= 2000)) return "imu rate must be in [rate, 2000] Hz";
  if (!(exposure >= 0 && exposure < 1.0 / rate)) return "exposure must be in [0, 1/rate) s";
  if (!(blur_samples >= 1 && blur_samples <= 64)) return "blur samples must be in [1, 64]";
  if (!(image_scale >= 0.1 && image_scale <= 1.0)) return "image scale must be in [0.1, 1]";
  if (!(imaging_rate == 0 || (imaging_rate >= 1 && imaging_rate <= 500 && exposure < 1.0 / imaging_rate)))
    return "imaging rate must be 0 (none) or in [1, 500] Hz, a frame longer than the exposure";
  const CameraModel cam = scaledRig(image_scale, RealismProfile::ideal()).left;
  if ((imaging_pixel.x() >= 0 || imaging_pixel.y() >= 0) &&
      !(imaging_pixel.x() >= 0 && imaging_pixel.x() <= cam.width - 1 && imaging_pixel.y() >= 0 &&
        imaging_pixel.y() <= cam.height - 1))
    return "imaging pixel must lie in the " + std::to_string(cam.width) + " x " + std::to_string(cam.height) +
           " image";
  if (!(stage_speed >= 0 && stage_speed <= 0.1)) return "stage speed must be in [0, 100] mm/s";
  if (!(std::abs(right_shift_px) <= 20)) return "right image shift must be in [-20, 20] px";
  if (!(std::abs(camera_clock_offset) <= 100)) return "camera clock offset must be in [-100, 100] s";
  if (!(scene_shift.allFinite() && scene_shift.norm() <= 1.0)) return "scene shift must be at most 1 m";
  if (!(std::abs(scene_yaw) <= M_PI)) return "scene yaw must be in [-180, 180] deg";
  if (!(lighting_gain >= 0.2 && lighting_gain <= 5.0)) return "lighting gain must be in [0.2, 5]";
  return "";
}

CameraImuCalibration CameraImuCalibration::makeDefault() {
  CameraImuCalibration c;
  // IMU axes (REP-103 body: x forward, y left, z up) in the optical frame
  // (x right, y down, z forward), then a mounting error of a few degrees.
  Eigen::Matrix3d nominal;
  nominal.col(0) = Eigen::Vector3d(0, 0, 1);
  nominal.col(1) = Eigen::Vector3d(-1, 0, 0);
  nominal.col(2) = Eigen::Vector3d(0, -1, 0);
  const double deg = M_PI / 180.0;
  const Eigen::Matrix3d error = (Eigen::AngleAxisd(1.5 * deg, Eigen::Vector3d::UnitX()) *
                                 Eigen::AngleAxisd(-2.0 * deg, Eigen::Vector3d::UnitY()) *
                                 Eigen::AngleAxisd(1.0 * deg, Eigen::Vector3d::UnitZ())).toRotationMatrix();
  c.T_cam_imu.q = Eigen::Quaterniond(error * nominal).normalized();
  // Lever arm: the IMU sits 3 cm right (mid-baseline), 1.2 cm above and
  // 2.5 cm behind the left camera's optical centre.
  c.T_cam_imu.p = Eigen::Vector3d(0.03, -0.012, -0.025);
  c.time_offset_ns = -3000000;  // camera stamps 3 ms late
  return c;
}

CameraImuCalibration CameraImuCalibration::perturbed(const CalibrationError& e, uint32_t seed) const {
  if (!e.any()) return *this;
  GaussianRng rng(mixSeed(seed, 0xFFFFFF06u, 19));
  auto direction = [&rng] {
    Eigen::Vector3d d;
    for (int i = 0; i < 3; ++i) d[i] = rng.normal();
    return d.normalized();
  };
  CameraImuCalibration c = *this;
  const Eigen::Vector3d axis = direction(), shift = direction();
  c.T_cam_imu.q = (Eigen::Quaterniond(Eigen::AngleAxisd(e.rotation_rad, axis)) * T_cam_imu.q).normalized();
  c.T_cam_imu.p = T_cam_imu.p + e.translation_m * shift;
  const double sign = rng.uniform01() < 0.5 ? -1.0 : 1.0;
  c.time_offset_ns = time_offset_ns + std::llround(sign * e.time_offset_s * 1e9);
  return c;
}

std::string CameraImuCalibration::yaml(const ImuSpec& imu, double imu_rate) const {
  std::ostringstream y;
  y << "# X_cam = T_cam_imu * X_imu (Kalibr's T_cam_imu): imu_link in stereo_left_optical_frame, 4x4 row-major\n"
    << "T_cam_imu: [" << formatMatrix4(T_cam_imu) << "]\n"
    << "# t_imu = t_cam + time_offset_s (Kalibr's timeshift_cam_imu); negative: camera stamps are late\n"
    << "time_offset_s: " << formatNumber(time_offset_ns * 1e-9) << "\n"
    << "cam_frame_id: stereo_left_optical_frame\n"
    << "imu_frame_id: imu_link\n"
    << "imu_part: " << imu.part << "\n"
    << "imu_rate_hz: " << formatNumber(imu_rate) << "\n"
    << "gyroscope_noise_density: " << formatNumber(imu.gyro_noise_density) << "  # rad/s/sqrt(Hz)\n"
    << "gyroscope_random_walk: " << formatNumber(imu.gyro_random_walk) << "  # rad/s^2/sqrt(Hz)\n"
    << "accelerometer_noise_density: " << formatNumber(imu.accel_noise_density) << "  # m/s^2/sqrt(Hz)\n"
    << "accelerometer_random_walk: " << formatNumber(imu.accel_random_walk) << "  # m/s^3/sqrt(Hz)\n"
    << "gravity: " << formatNumber(kGravity) << "  # m/s^2 along -z of the inertial frame\n";
  return y.str();
}

Scenario::Scenario(const ScenarioConfig& config)
    : cfg_(config),
      profile_(RealismProfile::forLevel(config.realism)),
      scene_(makeScene(config)),
      rig_(scaledRig(config.image_scale, profile_)),
      calib_(CameraImuCalibration::makeDefault()),
      believed_calib_(calib_.perturbed(profile_.calibration, config.seed)),
      imu_spec_(ImuSpec::adis16448()),
      device_(makeDeviceMotion(config.trajectory, scene_->view(), config.seed)),
      scene_motion_(makeSceneMotion(config.trajectory, scene_->view(), config.seed, config.stage_speed)),
      exposure_(config.seed, config.photometric) {
  sensor_.enabled = config.image_noise;
  ren_l_ = std::make_unique<SceneRenderer>(*scene_, rig_.left);
  ren_r_ = std::make_unique<SceneRenderer>(*scene_, rig_.right);
  perfusion_pattern_ = PerfusionPattern::forView(scene_->view());
  if (cfg_.imaging_content == ImagingContent::Perfusion)
    perfusion_ = std::make_unique<PerfusionRenderer>(*scene_, rig_.left, perfusion_pattern_);
  frame_ns_ = std::llround(1e9 / cfg_.rate);
  clock_offset_ns_ = std::llround(1e9 * cfg_.camera_clock_offset);
  // p -> c + R (p - c) + shift: the turn about the view centre c.
  const Eigen::Vector3d c = scene_->view().centre;
  scene_placement_.q = Eigen::Quaterniond(Eigen::AngleAxisd(cfg_.scene_yaw, Eigen::Vector3d::UnitZ()));
  scene_placement_.p = c - scene_placement_.q * c + cfg_.scene_shift;
  imu_ns_ = std::llround(1e9 / cfg_.imu_rate);
  n_frames_ = countAt(cfg_.duration, cfg_.rate);
  n_imu_ = static_cast<int64_t>(std::floor(cfg_.duration * cfg_.imu_rate + 1e-9));
  if (cfg_.imaging_rate > 0) {
    imaging_ns_ = std::llround(1e9 / cfg_.imaging_rate);
    n_imaging_ = countAt(cfg_.duration, cfg_.imaging_rate);
  }
}

Scenario::~Scenario() = default;

MotionSample Scenario::leftCameraInInertial(double t) const {
  return placedMotion(scene_placement_, device_->sample(t));
}
MotionSample Scenario::sceneInInertial(double t) const {
  return placedMotion(scene_placement_, scene_motion_->sample(t));
}
MotionSample Scenario::leftCameraInScene(double t) const {
  return relativeMotion(sceneInInertial(t), leftCameraInInertial(t));
}
MotionSample Scenario::imuInInertial(double t) const { return attachedFrame(leftCameraInInertial(t), calib_.T_cam_imu); }

Eigen::Vector2d Scenario::imagingPixel() const {
  if (cfg_.imaging_pixel.x() >= 0) return cfg_.imaging_pixel;
  return {0.5 * (rig_.left.width - 1), 0.5 * (rig_.left.height - 1)};
}

SurfaceMotionTruth Scenario::surfaceMotion(double t) const {
  return surfaceMotionTruth(*scene_, imagingCamera(), imagingPixel(), cfg_.imaging_rate, leftCameraInScene(t));
}

std::vector<Pose> Scenario::exposurePoses(double t) const {
  const double e = cfg_.exposure;
  const int n = cfg_.blur_samples;
  std::vector<Pose> poses;
  for (int j = 0; j < n; ++j) poses.push_back(leftCameraInScene(t - 0.5 * e + (j + 0.5) * e / n).pose());
  return poses;
}

void Scenario::renderStereo(int64_t k, cv::Mat* left, cv::Mat* right) const {
  const double t = frameTimeNs(k) * 1e-9;
  const std::vector<Pose> pl = exposurePoses(t);
  std::vector<Pose> pr;
  for (const Pose& P : pl) pr.push_back(rig_.rightPose(P));
  const double g = gain(t);
  const uint32_t frame = static_cast<uint32_t>(k);
  *left = sensor_.expose(ren_l_->radiance(pl), g, mixSeed(cfg_.seed, frame, 0));
  *right = sensor_.expose(ren_r_->radiance(pr), g * kRightGainRatio, mixSeed(cfg_.seed, frame, 1));
  if (cfg_.right_shift_px != 0.0) {
    const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, 0, 0, 1, cfg_.right_shift_px);
    cv::warpAffine(*right, *right, shift, right->size(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  }
}

cv::Mat Scenario::renderImaging(int64_t j) const {
  const double t = imagingTimeNs(j) * 1e-9;
  if (cfg_.imaging_content == ImagingContent::Perfusion) return perfusion_->render(leftCameraInScene(t).pose());
  return sensor_.expose(ren_l_->radiance(exposurePoses(t)), gain(t),
                        mixSeed(cfg_.seed, static_cast<uint32_t>(j), kImagingCamera));
}

ImuModel Scenario::makeImuModel() const {
  return ImuModel(imu_spec_, cfg_.imu_rate, cfg_.seed, cfg_.imu_noise, cfg_.imu_saturation, profile_.imu);
}

void Scenario::play(const ImuSink& on_imu, const FrameSink& on_frame, const ImagingSink& on_imaging) const {
  ImuModel imu = makeImuModel();
  const int64_t n_imaging = on_imaging ? n_imaging_ : 0;
  int64_t next_frame = 0, next_imu = 0, next_imaging = 0;
  while (next_frame < n_frames_ || next_imu < n_imu_ || next_imaging < n_imaging) {
    const int64_t tf = next_frame < n_frames_ ? frameStampNs(next_frame) : INT64_MAX;
    const int64_t ti = next_imu < n_imu_ ? imuTimeNs(next_imu) : INT64_MAX;
    const int64_t tg = next_imaging < n_imaging ? imagingStampNs(next_imaging) : INT64_MAX;
    if (ti <= tf && ti <= tg) {
      on_imu(next_imu, imu.measure(imuInInertial(ti * 1e-9)));
      ++next_imu;
    } else if (tg < tf) {
      on_imaging(next_imaging, renderImaging(next_imaging));
      ++next_imaging;
    } else {
      cv::Mat l, r;
      renderStereo(next_frame, &l, &r);
      on_frame(next_frame, l, r);
      ++next_frame;
    }
  }
}

}  // namespace hapi_sim
