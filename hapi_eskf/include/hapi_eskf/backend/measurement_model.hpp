// The stereo 3D measurement model (docs/DESIGN.md "Filter"), shared by the
// association and every back end: a world landmark seen from the camera, a
// new landmark placed from a camera-frame measurement, their Jacobians, and
// the re-detection covariance. Checked against central finite differences in
// test/test_jacobians.cpp.
#pragma once

#include "hapi_eskf/types.hpp"

namespace hapi_eskf {

// h(x) = R^T (m - p): landmark m (world) in the camera frame.
Vec3 measure(const PoseState& x, const Vec3& m);
// dh/d[dp, dtheta] (3 x 6) and dh/ddm (3 x 3).
void measurementJacobian(const PoseState& x, const Vec3& m, Mat36* H_pose, Mat3* H_landmark);

// Re-detection covariance of a keypoint across frames, added to the front
// end's C_z (settings.hpp measurement_angular_sigma): (s |z|)^2 (I - r r^T),
// r = z / |z|; zero for s <= 0. The ES-EKF and the graph built from its
// recorded stream use this one term.
Mat3 redetectionCovariance(const Vec3& z, double angular_sigma);

// m = p + R z: a new landmark from a camera-frame measurement z.
Vec3 initLandmark(const PoseState& x, const Vec3& z);
// dm/d[dp, dtheta] (3 x 6) and dm/dz (3 x 3).
void newLandmarkJacobian(const PoseState& x, const Vec3& z, Mat36* G_pose, Mat3* G_z);

}  // namespace hapi_eskf
