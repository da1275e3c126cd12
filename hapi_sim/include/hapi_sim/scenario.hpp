// hapi_sim: one simulated hand-held stereo + IMU recording (the suite's
// scenario): a scene, the device's motion and the scene's motion, the stereo
// rig, the camera-IMU extrinsic and time offset, image formation and the IMU
// model, and optionally the imaging camera (the stereo left camera at its
// own frame rate) with the surface-motion truth at its pixel. ROS-free;
// make_sim_bag and the ASL writer both read it.
//
// Frames and clocks (docs/DESIGN.md "Data"):
//  * inertial frame: gravity along -z; the device's IMU moves in it.
//  * scene frame = ground-truth "world": the scene's geometry is fixed in it;
//    it equals the inertial frame except where the scene moves (subject,
//    measurement_subject, stage).
//  * true time = the IMU clock, 0 at the first IMU sample. Frame k is exposed
//    around true time k / rate (mid-exposure); its camera stamp is
//    t_cam = t_imu - time_offset (Kalibr: t_imu = t_cam + timeshift_cam_imu),
//    i.e. with the default offset of -3 ms camera stamps are 3 ms late.
//    Imaging frame j is exposed around true time j / imaging_rate, stamped
//    in the same camera clock.
#pragma once
#include <opencv2/core.hpp>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "hapi_sim/image_formation.hpp"
#include "hapi_sim/imu_model.hpp"
#include "hapi_sim/motion.hpp"
#include "hapi_sim/perfusion_pattern.hpp"
#include "hapi_sim/realism.hpp"
#include "hapi_sim/scene.hpp"
#include "hapi_sim/surface_motion_truth.hpp"
#include "hapi_sim/trajectories.hpp"

namespace hapi_sim {

enum class SceneKind { Globe, Skin, Patch, Chessboard };
bool parseSceneKind(const std::string& name, SceneKind* kind);

// What the imaging camera records: the scene's texture through the same
// image formation as the stereo pair (mono8), or the known perfusion
// pattern of the skin (perfusion_pattern.hpp; 32FC1 in PU).
enum class ImagingContent { Texture, Perfusion };
bool parseImagingContent(const std::string& name, ImagingContent* content);

// First stamp of every simulated recording: fixed, never wall time.
constexpr int64_t kSimEpochNs = 1000000000LL * 1000000000LL;

struct ScenarioConfig {
  SceneKind scene = SceneKind::Skin;
  TrajectoryKind trajectory = TrajectoryKind::Handheld;
  uint32_t seed = 1;
  double duration = 30.0;     // s
  double rate = 10.0;         // stereo frames per second
  double imu_rate = 200.0;    // Hz
  double exposure = 0.006;    // s; motion blur over this window (0: none)
  int blur_samples = 8;       // sub-frame renders per image (>= 4 also anti-aliases 2x2)
  bool photometric = true;    // gain drift and steps
  bool image_noise = true;    // shot + read noise
  bool imu_noise = true;      // white noise, turn-on bias, bias random walk
  bool imu_saturation = true;
  double image_scale = 1.0;   // of the 640 x 480 rig (smaller for quick tests)
  Realism realism = Realism::Ideal;  // sensor and calibration imperfections (realism.hpp)
  std::string globe_texture = "/usr/share/xplanet/images/earth.jpg";
  double imaging_rate = 0.0;  // Hz, the imaging camera's frame rate (0: no imaging stream)
  // px, the imaging camera's surface-motion pixel; negative: the image centre.
  Eigen::Vector2d imaging_pixel = Eigen::Vector2d(-1.0, -1.0);
  ImagingContent imaging_content = ImagingContent::Texture;
  double stage_speed = kDefaultStageSpeed;  // m/s, the stage trajectory's speed
  // Broken set-ups, for the self-check tests (0: none): the right image
  // shifted down by this many pixels after rendering (a stereo calibration
  // gone wrong), and this offset added to every camera stamp (images and IMU
  // stamped by clocks that disagree; the truth and /ground_truth keep the
  // true time).
  double right_shift_px = 0.0;
  double camera_clock_offset = 0.0;  // s
  // A follow-up session (docs/DESIGN.md "Map file"): the scene placed
  // elsewhere in the inertial frame, turned by scene_yaw about the vertical
  // through its view centre and moved by scene_shift, the hand's path
  // following it (the trajectories are laid out around the scene's view;
  // another seed or trajectory gives another path over it); and another
  // lighting, every image's gain times lighting_gain. The truth in the scene
  // frame (/ground_truth/odometry) is then comparable between sessions; the
  // inertial truths differ by the placement.
  Eigen::Vector3d scene_shift = Eigen::Vector3d::Zero();  // m, inertial frame
  double scene_yaw = 0.0;                                 // rad
  double lighting_gain = 1.0;
  // Another skin (the skin scene's texture drawn from this seed; 0: the
  // reference skin): an unmapped arm for the false relocalisation check.
  uint32_t skin_texture_seed = 0;
  // "" when valid, else what is wrong (one rule for every front end).
  std::string validate() const;
};

// The true camera-IMU calibration of the simulated device.
struct CameraImuCalibration {
  Pose T_cam_imu;              // imu_link in the left optical frame: X_cam = T_cam_imu X_imu (Kalibr's T_cam_imu)
  int64_t time_offset_ns = 0;  // t_imu = t_cam + offset (Kalibr's timeshift_cam_imu)
  static CameraImuCalibration makeDefault();
  // This calibration made wrong by `error`, the error's directions drawn from the seed.
  CameraImuCalibration perturbed(const CalibrationError& error, uint32_t seed) const;
  std::string yaml(const ImuSpec& imu, double imu_rate) const;  // /ground_truth/calibration
};

class Scenario {
 public:
  explicit Scenario(const ScenarioConfig& config);
  ~Scenario();
  const ScenarioConfig& config() const { return cfg_; }
  const Scene& scene() const { return *scene_; }
  const StereoRigModel& rig() const { return rig_; }
  const CameraImuCalibration& calibration() const { return calib_; }  // the truth
  // What the filter is told (the bag's /tf_static and /calibration): the truth
  // except under --realism real.
  const CameraImuCalibration& believedCalibration() const { return believed_calib_; }
  const RealismProfile& realism() const { return profile_; }
  const ImuSpec& imuSpec() const { return imu_spec_; }
  std::string calibrationYaml() const { return calib_.yaml(imu_spec_, cfg_.imu_rate); }
  std::string believedCalibrationYaml() const { return believed_calib_.yaml(imu_spec_, cfg_.imu_rate); }

  int64_t frameCount() const { return n_frames_; }
  int64_t imuCount() const { return n_imu_; }
  int64_t frameTimeNs(int64_t k) const { return k * frame_ns_; }                     // true (IMU clock)
  int64_t frameStampNs(int64_t k) const { return k * frame_ns_ - calib_.time_offset_ns + clock_offset_ns_; }  // camera clock
  int64_t imuTimeNs(int64_t i) const { return i * imu_ns_; }
  // The imaging camera: the stereo left camera (same intrinsics, same pose:
  // its frame is the left optical frame), frames at imaging_rate.
  int64_t imagingCount() const { return n_imaging_; }
  int64_t imagingTimeNs(int64_t j) const { return j * imaging_ns_; }                      // true (IMU clock)
  int64_t imagingStampNs(int64_t j) const { return j * imaging_ns_ - calib_.time_offset_ns + clock_offset_ns_; }  // camera clock
  const CameraModel& imagingCamera() const { return rig_.left; }
  CameraInfoData imagingInfo() const { return rig_.leftInfo(); }
  Eigen::Vector2d imagingPixel() const;

  // Ground truth at true time t.
  MotionSample leftCameraInScene(double t) const;     // what an estimator should report
  MotionSample leftCameraInInertial(double t) const;
  MotionSample imuInInertial(double t) const;         // EuRoC's state ground truth
  MotionSample sceneInInertial(double t) const;
  // The surface motion at the imaging pixel at true time t.
  SurfaceMotionTruth surfaceMotion(double t) const;
  double gain(double t) const { return cfg_.lighting_gain * exposure_.gain(t); }

  // Frame k's images (mono8), deterministic per (seed, k).
  void renderStereo(int64_t k, cv::Mat* left, cv::Mat* right) const;
  // Imaging frame j: texture content (mono8) the left camera's image
  // formation at its time, deterministic per (seed, j); perfusion content
  // (32FC1, PU) the pattern at the mid-exposure pose.
  cv::Mat renderImaging(int64_t j) const;
  // The imaging camera's perfusion pattern (its truth; defined for every
  // scene, rendered only with ImagingContent::Perfusion).
  const PerfusionPattern& perfusionPattern() const { return perfusion_pattern_; }
  // A fresh IMU sample stream (call measure() in sample order).
  ImuModel makeImuModel() const;

  // Every IMU sample, every stereo frame and, given on_imaging, every
  // imaging frame once, in stamp order (IMU first at equal stamps, so a
  // filter can predict up to an image's time; then stereo, then imaging).
  using ImuSink = std::function<void(int64_t i, const ImuReading& reading)>;
  using FrameSink = std::function<void(int64_t k, const cv::Mat& left, const cv::Mat& right)>;
  using ImagingSink = std::function<void(int64_t j, const cv::Mat& image)>;
  void play(const ImuSink& on_imu, const FrameSink& on_frame, const ImagingSink& on_imaging = nullptr) const;

 private:
  ScenarioConfig cfg_;
  RealismProfile profile_;
  std::unique_ptr<Scene> scene_;
  StereoRigModel rig_;
  CameraImuCalibration calib_, believed_calib_;
  ImuSpec imu_spec_;
  std::unique_ptr<RigidMotion> device_, scene_motion_;
  ExposureModel exposure_;
  SensorNoise sensor_;
  std::unique_ptr<SceneRenderer> ren_l_, ren_r_;
  PerfusionPattern perfusion_pattern_;
  std::unique_ptr<PerfusionRenderer> perfusion_;  // with ImagingContent::Perfusion only
  int64_t frame_ns_ = 0, imu_ns_ = 0, n_frames_ = 0, n_imu_ = 0, imaging_ns_ = 0, n_imaging_ = 0;
  int64_t clock_offset_ns_ = 0;  // ScenarioConfig::camera_clock_offset
  Pose scene_placement_;          // ScenarioConfig::scene_shift, scene_yaw

  // The left camera's sub-frame poses in the scene over the exposure around t.
  std::vector<Pose> exposurePoses(double t) const;
};

}  // namespace hapi_sim
