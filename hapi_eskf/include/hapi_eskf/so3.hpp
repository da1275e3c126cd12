// SO(3) helpers used by the error-state formulation (R = R_hat Exp(dtheta)).
#pragma once

#include "hapi_eskf/types.hpp"

namespace hapi_eskf {

Mat3 skew(const Vec3& v);                 // [v]x
Mat3 expSO3(const Vec3& phi);             // Rodrigues, exact near 0
Vec3 logSO3(const Mat3& R);
Mat3 rightJacobianSO3(const Vec3& phi);   // J_r: Exp(phi + d) ~ Exp(phi) Exp(J_r d)
Eigen::Quaterniond quatExp(const Vec3& phi);
// Finite, orthonormal to 1e-6 and of determinant +1 (a given extrinsic's
// rotation; the filter and the nodelet's ~T_cam_imu check use this one rule).
bool isRotation(const Mat3& R);

}  // namespace hapi_eskf
