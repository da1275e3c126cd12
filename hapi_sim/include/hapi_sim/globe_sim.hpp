// hapi_sim: ROS-free deterministic renderer of a textured globe seen by a
// calibrated stereo rig (Eigen + OpenCV core/imgproc/imgcodecs only).
//
// Conventions
//  * World frame "map": z up. The globe's texture frame is parallel to it
//    (latitude from +z, longitude = atan2(y, x)).
//  * Poses are camera->world (T_wc): X_w = q * X_c + p. Camera frames are
//    optical (x right, y down, z forward).
//  * Pixel centres are at integer coordinates (OpenCV convention).
//  * Distortion: plumb_bob (k1, k2, p1, p2, k3) as in OpenCV / ROS.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <array>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "hapi_dataset/camera_info.hpp"

namespace hapi_sim {

struct Pose {
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();  // camera -> world rotation
  Eigen::Vector3d p = Eigen::Vector3d::Zero();            // camera centre in world
};

struct CameraModel {
  int width = 640, height = 480;
  double fx = 500.0, fy = 500.0, cx = 319.5, cy = 239.5;
  double k1 = 0.0, k2 = 0.0, p1 = 0.0, p2 = 0.0, k3 = 0.0;
};

// Plain mirror of sensor_msgs/CameraInfo, the recording tools' one type.
using CameraInfoData = hapi_dataset::CameraInfoData;

// Stereo rig: right camera = left camera translated by +baseline along the
// left x axis, identity relative rotation. Images are NOT rectified (they carry
// the lens distortion) but the pair is exactly parallel, so undistorting
// keypoints gives a rectified geometry with R = I.
struct StereoRigModel {
  CameraModel left, right;
  double baseline = 0.06;
  static StereoRigModel makeDefault();  // 640x480, f~500, mild distortion, 6 cm
  Pose rightPose(const Pose& left_pose) const;
  // ROS convention: P_right[3] = -fx * baseline.
  CameraInfoData leftInfo() const;
  CameraInfoData rightInfo() const;
};

// Distortion of normalised image coordinates (z = 1) and its iterative inverse.
// The template serves any scalar with + and * (double, hapi_sim::Jet2 for
// exact time derivatives of a projection).
template <class T>
void distortNormalized(const CameraModel& c, const T& x, const T& y, T* xd, T* yd) {
  const T r2 = x * x + y * y;
  const T rad = T(1.0) + r2 * (T(c.k1) + r2 * (T(c.k2) + r2 * T(c.k3)));
  *xd = x * rad + T(2 * c.p1) * x * y + T(c.p2) * (r2 + T(2.0) * x * x);
  *yd = y * rad + T(c.p1) * (r2 + T(2.0) * y * y) + T(2 * c.p2) * x * y;
}
Eigen::Vector2d distortNormalized(const CameraModel& cam, const Eigen::Vector2d& xn);
Eigen::Vector2d undistortNormalized(const CameraModel& cam, const Eigen::Vector2d& xd);
// Pixel -> unit ray in the camera frame (distortion removed).
Eigen::Vector3d pixelToRay(const CameraModel& cam, const Eigen::Vector2d& px);

class GlobeScene {
 public:
  double radius = 0.2;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  cv::Mat texture;                // CV_32FC1, equirectangular, row 0 = north pole, values 0..255
  std::string texture_source;     // file path or "generated"

  // Loads texture_path in grey levels; if missing/unreadable, a generated
  // deterministic texture (texture_source = "generated").
  static GlobeScene makeDefault(const std::string& texture_path = "/usr/share/xplanet/images/earth.jpg",
                                double radius = 0.2, const Eigen::Vector3d& centre = Eigen::Vector3d::Zero());
  static cv::Mat generateTexture(int width = 2048, int height = 1024, uint32_t seed = 7);

  // Surface point <-> (lat, lon) in radians.
  Eigen::Vector3d pointFromLatLon(double lat, double lon) const;
  void latLonFromPoint(const Eigen::Vector3d& X, double* lat, double* lon) const;
  // Texture coordinates (u, v) in texel units, texel centres at integers.
  Eigen::Vector2d texelFromLatLon(double lat, double lon) const;
  float sample(double lat, double lon) const;  // bilinear, wraps in longitude
  // Nearest intersection of the ray o + t d (t > 0, d unit) with the sphere.
  bool intersect(const Eigen::Vector3d& o, const Eigen::Vector3d& d, Eigen::Vector3d* hit) const;
};

// World point -> distorted pixel. False if behind the camera.
bool project(const Eigen::Vector3d& X_w, const Pose& T_wc, const CameraModel& cam, Eigen::Vector2d* px);
// Pixel -> first sphere hit in world coordinates (ground-truth 3D). False on miss.
bool castRay(const Eigen::Vector2d& px, const Pose& T_wc, const CameraModel& cam, const GlobeScene& scene,
             Eigen::Vector3d* X_w);
// Is the world point on the visible (front) side of the sphere, i.e. not occluded?
bool isVisible(const Eigen::Vector3d& X_w, const Pose& T_wc, const GlobeScene& scene);

struct TrajectorySample {
  double t = 0.0;
  Pose T_wc;                                    // left optical frame -> world
  Eigen::Vector3d v_w = Eigen::Vector3d::Zero();      // velocity, world
  Eigen::Vector3d a_w = Eigen::Vector3d::Zero();      // acceleration, world (no gravity)
  Eigen::Vector3d omega_c = Eigen::Vector3d::Zero();  // angular velocity, camera frame
};

// Smooth analytic path around the globe, always looking roughly at it
// (globe_orbit.hpp); exact derivatives. kPan: the default data set's
// orbit/pan; kSpiral: the long run that keeps seeing new surface.
enum class GlobePath { kPan, kSpiral };
class Trajectory {
 public:
  explicit Trajectory(const GlobeScene& scene, GlobePath orbit = GlobePath::kPan)
      : centre_(scene.centre), radius_(scene.radius), orbit_(orbit) {}
  Pose pose(double t) const;
  TrajectorySample at(double t) const;

 private:
  Eigen::Vector3d centre_;
  double radius_;
  GlobePath orbit_;
};

// Deterministic N(0,1) from std::mt19937 with a hand-rolled Box-Muller
// (std::normal_distribution is implementation-defined).
class GaussianRng {
 public:
  explicit GaussianRng(uint32_t seed) : rng_(seed) {}
  double uniform01();  // in (0, 1)
  double normal();
 private:
  std::mt19937 rng_;
  bool has_spare_ = false;
  double spare_ = 0.0;
};

// Per-image seed derived from (dataset seed, frame index, camera index).
uint32_t mixSeed(uint32_t seed, uint32_t frame, uint32_t camera);

// Ray-casting renderer with ss x ss supersampling; ray table cached per camera.
class Renderer {
 public:
  Renderer(const GlobeScene& scene, const CameraModel& cam, int supersample = 2);
  // mono8 image; noise_sigma in grey levels (0: none); seed drives the noise only.
  cv::Mat render(const Pose& T_wc, uint32_t seed, double noise_sigma = 2.0) const;
  // Noise-free float image (CV_32FC1).
  cv::Mat renderFloat(const Pose& T_wc) const;
  static float background(int u, int v);  // dark, low-texture, deterministic

 private:
  const GlobeScene& scene_;
  CameraModel cam_;
  int ss_;
  std::vector<Eigen::Vector3f> rays_;  // (h*ss) x (w*ss) unit rays in camera frame
};

}  // namespace hapi_sim
