// Every analytic Jacobian of backend/measurement_model.hpp and
// backend/pose_kinematics.hpp against central finite differences
// on the manifold (docs/DESIGN.md "Jacobian checks").
// Error convention: R = R^ Exp(dtheta), the others additive.
#include "hapi_eskf/backend/measurement_model.hpp"
#include "hapi_eskf/backend/pose_kinematics.hpp"
#include "hapi_eskf/random_draw.hpp"
#include "hapi_eskf/settings.hpp"
#include "hapi_eskf/so3.hpp"

#include <gtest/gtest.h>

#include <random>

namespace hapi_eskf {
namespace {

using VecX = Eigen::VectorXd;
using MatX = Eigen::MatrixXd;
using Vec12 = Eigen::Matrix<double, 12, 1>;

// x [+] d for the 12-dim pose error.
PoseState boxplus(const PoseState& x, const Vec12& d) {
  PoseState y = x;
  y.p += d.segment<3>(kIdxP);
  y.q = Eigen::Quaterniond(x.q.toRotationMatrix() * expSO3(d.segment<3>(kIdxTheta)));
  y.v += d.segment<3>(kIdxV);
  y.w += d.segment<3>(kIdxW);
  return y;
}

// y [-] x: the error d with y = x [+] d.
Vec12 boxminus(const PoseState& y, const PoseState& x) {
  Vec12 d;
  d.segment<3>(kIdxP) = y.p - x.p;
  d.segment<3>(kIdxTheta) = logSO3(x.q.toRotationMatrix().transpose() * y.q.toRotationMatrix());
  d.segment<3>(kIdxV) = y.v - x.v;
  d.segment<3>(kIdxW) = y.w - x.w;
  return d;
}

// Central difference of f: R^n -> R^m at 0.
template <typename F>
MatX numericJacobian(F f, int n, double eps = 1e-6) {
  const VecX f0 = f(VecX::Zero(n));
  MatX J(f0.size(), n);
  for (int i = 0; i < n; ++i) {
    VecX d = VecX::Zero(n);
    d[i] = eps;
    const VecX fp = f(d);
    d[i] = -eps;
    const VecX fm = f(d);
    J.col(i) = (fp - fm) / (2 * eps);
  }
  return J;
}

// Relative error: max |A - N| / max(1, max |N|).
double relErr(const MatX& A, const MatX& N) {
  return (A - N).cwiseAbs().maxCoeff() / std::max(1.0, N.cwiseAbs().maxCoeff());
}

PoseState randomPose(std::mt19937& rng) {
  std::normal_distribution<double> g(0, 1);
  PoseState x;
  x.p = drawVec3(g, rng) * 3;
  x.q = Eigen::Quaterniond(expSO3(drawVec3(g, rng)));
  x.v = drawVec3(g, rng);
  x.w = drawVec3(g, rng) * 0.7;
  return x;
}

Vec3 randVec(std::mt19937& rng, double s) {
  std::normal_distribution<double> g(0, s);
  return drawVec3(g, rng);
}

TEST(Jacobians, So3ExpLogRoundTripAndRightJacobian) {
  std::mt19937 rng(1);
  for (int t = 0; t < 50; ++t) {
    const Vec3 phi = randVec(rng, 0.8);
    EXPECT_LT((logSO3(expSO3(phi)) - phi).norm(), 1e-12);
    EXPECT_LT((quatExp(phi).toRotationMatrix() - expSO3(phi)).norm(), 1e-12);
    // Exp(phi + d) ~ Exp(phi) Exp(J_r d): d Log(Exp(phi)^T Exp(phi + d)) / dd = J_r.
    auto f = [&](const VecX& d) -> VecX { return logSO3(expSO3(phi).transpose() * expSO3(phi + d)); };
    EXPECT_LT(relErr(rightJacobianSO3(phi), numericJacobian(f, 3)), 1e-6);
  }
  // Tiny angles use the series branches.
  const Vec3 tiny(1e-10, -2e-10, 3e-11);
  EXPECT_LT((logSO3(expSO3(tiny)) - tiny).norm(), 1e-20);
  EXPECT_LT((rightJacobianSO3(tiny) - Mat3::Identity()).norm(), 1e-9);
}

TEST(Jacobians, PredictFMatchesFiniteDifferences) {
  std::mt19937 rng(2);
  EskfSettings s;
  for (double damping : {1.0, 0.6}) {
    s.velocity_damping = damping;
    s.angular_velocity_damping = damping * 0.9;
    for (double dt : {0.01, 0.1, 0.5}) {
      for (int t = 0; t < 10; ++t) {
        const PoseState x = randomPose(rng);
        const PoseState y0 = predictPose(x, dt, s);
        auto f = [&](const VecX& d) -> VecX { return boxminus(predictPose(boxplus(x, d), dt, s), y0); };
        const double e = relErr(predictJacobian(x, dt, s), numericJacobian(f, 12));
        EXPECT_LT(e, 1e-6) << "dt " << dt << " damping " << damping;
      }
    }
  }
}

TEST(Jacobians, PredictNominalModel) {
  EskfSettings s;
  s.velocity_damping = 0.5;
  PoseState x;
  x.v = Vec3(1, 0, 0);
  x.w = Vec3(0, 0, 0.2);
  const PoseState y = predictPose(x, 2.0, s);
  EXPECT_LT((y.p - Vec3(2, 0, 0)).norm(), 1e-15);               // p + R v dt
  EXPECT_LT((y.v - Vec3(0.25, 0, 0)).norm(), 1e-15);            // Gamma^dt v
  EXPECT_LT((y.q.toRotationMatrix() - expSO3(Vec3(0, 0, 0.4))).norm(), 1e-14);  // R Exp(w dt)
}

TEST(Jacobians, ProcessNoiseIsRandomWalkOnVelocities) {
  EskfSettings s;
  s.sigma_acceleration = 0.3;
  s.sigma_angular_acceleration = 0.2;
  const Mat12 Q = processNoise(0.5, s);
  EXPECT_DOUBLE_EQ(Q(kIdxV, kIdxV), 0.09 * 0.5);
  EXPECT_DOUBLE_EQ(Q(kIdxW + 2, kIdxW + 2), 0.04 * 0.5);
  EXPECT_EQ((Q.topLeftCorner<6, 6>().cwiseAbs().maxCoeff()), 0.0);
  EXPECT_EQ((Q - Q.transpose()).cwiseAbs().maxCoeff(), 0.0);
}

TEST(Jacobians, MeasurementHMatchesFiniteDifferences) {
  std::mt19937 rng(3);
  for (int t = 0; t < 30; ++t) {
    const PoseState x = randomPose(rng);
    const Vec3 m = x.p + randVec(rng, 5.0);
    Mat36 Hp;
    Mat3 Hm;
    measurementJacobian(x, m, &Hp, &Hm);
    // Error vector [dp, dtheta, dm].
    auto f = [&](const VecX& d) -> VecX {
      Vec12 d12 = Vec12::Zero();
      d12.head<6>() = d.head<6>();
      return measure(boxplus(x, d12), m + d.tail<3>());
    };
    MatX H(3, 9);
    H << Hp, Hm;
    EXPECT_LT(relErr(H, numericJacobian(f, 9)), 1e-6);
  }
}

TEST(Jacobians, NewLandmarkGMatchesFiniteDifferences) {
  std::mt19937 rng(4);
  for (int t = 0; t < 30; ++t) {
    const PoseState x = randomPose(rng);
    const Vec3 z = randVec(rng, 4.0) + Vec3(0, 0, 6);
    Mat36 Gp;
    Mat3 Gz;
    newLandmarkJacobian(x, z, &Gp, &Gz);
    auto f = [&](const VecX& d) -> VecX {
      Vec12 d12 = Vec12::Zero();
      d12.head<6>() = d.head<6>();
      return initLandmark(boxplus(x, d12), z + d.tail<3>());
    };
    MatX G(3, 9);
    G << Gp, Gz;
    EXPECT_LT(relErr(G, numericJacobian(f, 9)), 1e-6);
    // Consistency: measuring the new landmark from the same pose gives z back.
    EXPECT_LT((measure(x, initLandmark(x, z)) - z).norm(), 1e-12);
  }
}

TEST(Jacobians, InjectionIsTheBoxplusOfTheErrorConvention) {
  std::mt19937 rng(5);
  for (int t = 0; t < 30; ++t) {
    const PoseState x = randomPose(rng);
    Vec12 d;
    for (int i = 0; i < 12; ++i) d[i] = std::normal_distribution<double>(0, 0.3)(rng);
    PoseState y = x;
    injectPose(&y, d);
    // injectPose(x, d) [-] x == d: the injected state carries exactly the error d.
    EXPECT_LT((boxminus(y, x) - d).norm(), 1e-12);
    // Its Jacobian d(inject(x, d) [-] x)/dd at d is the identity (central differences).
    auto f = [&](const VecX& e) -> VecX {
      PoseState z = x;
      injectPose(&z, d + e);
      return boxminus(z, x);
    };
    EXPECT_LT(relErr(Mat12::Identity(), numericJacobian(f, 12)), 1e-6);
    EXPECT_NEAR(y.q.norm(), 1.0, 1e-14);
  }
}

}  // namespace
}  // namespace hapi_eskf
