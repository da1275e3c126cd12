// The velocity map (docs/DESIGN.md "Surface motion"): its Jacobian against
// central differences, and its quantities against finite differences of a
// simulated skin (a plane and a cylinder) moved by a known twist.
#include "hapi_eskf/surface_motion/camera_odometry.hpp"
#include "hapi_eskf/surface_motion/velocity_map.hpp"

#include "hapi_eskf/so3.hpp"
#include "surface_motion_scene.hpp"

#include <gtest/gtest.h>

#include <random>

namespace hapi_eskf {
namespace surface_motion {
namespace {

// The tests' camera made asymmetric (fx != fy, off-centre principal point).
ImagingCamera camera() {
  ImagingCamera c = test::testCamera();
  c.fx = 480;
  c.fy = 470;
  c.cx = 322;
  c.cy = 241;
  return c;
}

TEST(SurfaceMotionVelocityMap, JacobianMatchesCentralDifferences) {
  const ImagingCamera cam = camera();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 20; ++trial) {
    const Vec3 ray = Vec3(0.3 * u(rng), 0.3 * u(rng), 1).normalized();
    RayGeometry g;
    g.ray = ray;
    g.depth = 0.25 + 0.1 * u(rng);
    g.normal = (-ray + 0.4 * Vec3(u(rng), u(rng), u(rng))).normalized();
    const MapInput q = mapInput(0.02 * Vec3(u(rng), u(rng), u(rng)), 0.5 * Vec3(u(rng), u(rng), u(rng)),
                                0.01 * Vec3(u(rng), u(rng), u(rng)), g);
    const MapJacobian J = velocityMapJacobian(q, ray, cam);
    for (int i = 0; i < kMapInputs; ++i) {
      const double h = 1e-6;
      MapInput qp = q, qm = q;
      qp(i) += h;
      qm(i) -= h;
      const MapOutput fd = (evaluateVelocityMap(qp, ray, cam) - evaluateVelocityMap(qm, ray, cam)) / (2 * h);
      for (int r = 0; r < kMapOutputs; ++r)
        EXPECT_NEAR(J(r, i), fd(r), 1e-6 * (1 + std::abs(fd(r)))) << "output " << r << " input " << i;
    }
  }
}

// A rigid skin moving in the camera frame: X(h) = Exp(w h) X + v h.
struct Motion {
  Vec3 v, w;
  Vec3 apply(const Vec3& X, double h) const { return expSO3(w * h) * X + v * h; }
};

// The skin surface at time 0 in the camera frame; hit(): where the ray
// from the camera's origin meets the surface after the motion over h.
struct Plane {
  Vec3 point, normal;  // normal towards the camera
  Vec3 hit(const Vec3& ray, const Motion& m, double h) const {
    const Vec3 p = m.apply(point, h), n = expSO3(m.w * h) * normal;
    return ray * (n.dot(p) / n.dot(ray));
  }
  Vec3 normalAt(const Vec3&) const { return normal; }
};
struct Cylinder {
  Vec3 axis_point, axis;  // unit axis
  double radius;
  Vec3 hit(const Vec3& ray, const Motion& m, double h) const {
    const Vec3 c = m.apply(axis_point, h), a = expSO3(m.w * h) * axis;
    // |(t r - c) - ((t r - c) . a) a| = radius, nearer root.
    const Vec3 rp = ray - ray.dot(a) * a, cp = -(c - c.dot(a) * a);
    const double A = rp.squaredNorm(), B = 2 * rp.dot(cp), C = cp.squaredNorm() - radius * radius;
    const double t = (-B - std::sqrt(B * B - 4 * A * C)) / (2 * A);
    return t * ray;
  }
  Vec3 normalAt(const Vec3& X) const {
    const Vec3 d = X - axis_point;
    return (d - d.dot(axis) * axis).normalized();  // outwards = towards a camera outside
  }
};

template <typename Surface>
void checkAgainstSimulation(const Surface& surface, const Vec3& ray, const Motion& m, bool camera_moves) {
  const ImagingCamera cam = camera();
  const Vec3 X = surface.hit(ray, m, 0);
  RayGeometry g;
  g.ray = ray;
  g.depth = X.norm();
  g.normal = surface.normalAt(X);
  ASSERT_LT(g.normal.dot(ray), 0);
  // The same relative motion as the camera's twist (v, w) = -(motion) with
  // e = 0, or as e with the camera still.
  const Vec3 Xd_true = m.v + m.w.cross(X);
  const MapInput q = camera_moves ? mapInput(-m.v, -m.w, Vec3::Zero(), g) : mapInput(Vec3::Zero(), Vec3::Zero(), Xd_true, g);
  MapInputCovariance Cq = MapInputCovariance::Zero();
  const SurfaceVelocity sv = mapVelocity(q, Cq, ray, cam);

  const double h = 1e-5;
  const Vec3 Xd_fd = (m.apply(X, h) - m.apply(X, -h)) / (2 * h);
  // The skin slides under the ray: the material point moves away from the
  // ray's hit point at s.
  const Vec3 s_fd = ((m.apply(X, h) - surface.hit(ray, m, h)) - (m.apply(X, -h) - surface.hit(ray, m, -h))) / (2 * h);
  const Vec2 iv_fd = (cam.projectPinhole(m.apply(X, h)) - cam.projectPinhole(m.apply(X, -h))) / (2 * h) / cam.frame_rate;

  EXPECT_LT((sv.surface_velocity - 1000 * s_fd).norm(), 1e-4 * (1 + 1000 * s_fd.norm()));
  EXPECT_NEAR(sv.normal_velocity, 1000 * Xd_fd.dot(g.normal), 1e-4);
  EXPECT_LT((sv.image_velocity - iv_fd).norm(), 1e-6 * (1 + iv_fd.norm()));
  EXPECT_NEAR(sv.surface_velocity.dot(g.normal), 0, 1e-9);  // s . n == 0
  EXPECT_LT((sv.point - X).norm(), 1e-12);
}

TEST(SurfaceMotionVelocityMap, MatchesAMovedPlaneAndCylinder) {
  const Vec3 ray = Vec3(0.12, -0.08, 1).normalized();
  const Motion m{Vec3(0.009, -0.004, 0.003), Vec3(0.05, -0.08, 0.12)};
  const Plane tilted{Vec3(0, 0, 0.3), Vec3(0.3, -0.2, -1).normalized()};
  const Cylinder arm{Vec3(0.01, 0, 0.38), Vec3(1, 0.2, 0.1).normalized(), 0.05};
  for (bool camera_moves : {false, true}) {
    SCOPED_TRACE(camera_moves ? "camera moves" : "skin moves");
    checkAgainstSimulation(tilted, ray, m, camera_moves);
    checkAgainstSimulation(arm, ray, m, camera_moves);
  }
}

TEST(SurfaceMotionVelocityMap, SurfaceVelocityIsTangentAndItsCovarianceToo) {
  const ImagingCamera cam = camera();
  RayGeometry g;
  g.ray = Vec3(0.1, 0.05, 1).normalized();
  g.depth = 0.3;
  g.normal = Vec3(0.2, 0.1, -1).normalized();
  g.covariance = 1e-6 * Mat4::Identity();
  MapInputCovariance Cq = 1e-4 * MapInputCovariance::Identity();
  const SurfaceVelocity sv = mapVelocity(mapInput(Vec3(0.01, 0.002, -0.003), Vec3(0.1, 0, 0.2), Vec3::Zero(), g), Cq,
                                         g.ray, cam);
  EXPECT_NEAR(sv.surface_velocity.dot(g.normal), 0, 1e-12);
  EXPECT_GT(sv.speed(), 1.0);
  // The covariance is symmetric and positive semi-definite.
  EXPECT_LT((sv.surface_velocity_covariance - sv.surface_velocity_covariance.transpose()).norm(), 1e-9);
  EXPECT_GT(sv.surface_velocity_covariance.trace(), 0);
  EXPECT_GT(sv.normal_velocity_variance, 0);
  EXPECT_GT(sv.image_velocity_covariance.determinant(), 0);
}

TEST(SurfaceMotionImagingCamera, UndistortInvertsPlumbBob) {
  ImagingCamera cam = camera();
  cam.distortion = {-0.28, 0.07, 1e-3, -5e-4, 0.01};
  for (double u : {5.0, 200.0, 322.0, 630.0})
    for (double v : {3.0, 241.0, 470.0}) {
      const Vec3 r = cam.ray(Vec2(u, v));
      EXPECT_LT((cam.project(r) - Vec2(u, v)).norm(), 1e-8);
    }
  // projectJacobian against central differences.
  const Vec3 X(0.05, -0.03, 0.3);
  const Mat23 J = cam.projectJacobian(X);
  for (int i = 0; i < 3; ++i) {
    Vec3 d = Vec3::Zero();
    d(i) = 1e-7;
    const Vec2 fd = (cam.project(X + d) - cam.project(X - d)) / 2e-7;
    EXPECT_LT((J.col(i) - fd).norm(), 1e-4 * (1 + fd.norm()));
  }
}

// The twist of a camera fixed to the odometry's camera: against finite
// differences of the two poses under a known motion (camera-frame twist).
TEST(SurfaceMotionCameraOdometry, RigidlyAttachedTwistMatchesFiniteDifferences) {
  CameraOdometry odom;
  odom.T_world_cam.linear() = expSO3(Vec3(0.2, -0.1, 0.3));
  odom.T_world_cam.translation() = Vec3(0.1, 0.2, -0.05);
  odom.v = Vec3(0.02, -0.01, 0.005);
  odom.w = Vec3(0.3, -0.2, 0.5);
  odom.twist_covariance = 1e-4 * Mat6::Identity();
  Eigen::Isometry3d T_cam_other = Eigen::Isometry3d::Identity();
  T_cam_other.linear() = expSO3(Vec3(0.0, 0.4, -0.2));
  T_cam_other.translation() = Vec3(0.05, -0.02, 0.01);
  auto poseAt = [&](double h) {  // the camera moved by its twist over h, then the other camera
    Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
    step.linear() = expSO3(odom.w * h);
    step.translation() = odom.v * h;
    return odom.T_world_cam * step * T_cam_other;
  };
  const CameraOdometry other = toRigidlyAttached(odom, T_cam_other);
  const double h = 1e-6;
  const Eigen::Isometry3d Tp = poseAt(h), Tm = poseAt(-h), T0 = poseAt(0);
  EXPECT_LT((other.T_world_cam.matrix() - T0.matrix()).norm(), 1e-12);
  const Vec3 v_fd = T0.linear().transpose() * (Tp.translation() - Tm.translation()) / (2 * h);
  const Mat3 dR = Tm.linear().transpose() * Tp.linear();  // Exp(2 h w_other)
  const Eigen::AngleAxisd aa(dR);
  const Vec3 w_fd = aa.angle() * aa.axis() / (2 * h);
  EXPECT_LT((other.v - v_fd).norm(), 1e-7);
  EXPECT_LT((other.w - w_fd).norm(), 1e-6);
  // The covariance keeps its trace under a pure rotation of the twist's
  // angular part and grows by the lever arm for the linear part.
  const Mat3 Cv = other.twist_covariance.topLeftCorner<3, 3>(), Cw = other.twist_covariance.bottomRightCorner<3, 3>();
  EXPECT_GT(Cv.trace(), 3e-4);
  EXPECT_NEAR(Cw.trace(), 3e-4, 1e-15);
}

}  // namespace
}  // namespace surface_motion
}  // namespace hapi_eskf
