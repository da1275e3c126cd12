// hapi_sim: rigid motions over time with exact derivatives, and the two
// kinematic rules the simulator needs: a frame rigidly attached to a moving
// one (camera -> IMU lever arm) and one moving frame seen from another
// (camera relative to a moving scene). Equations: docs/DESIGN.md "Data".
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "hapi_sim/globe_sim.hpp"
#include "hapi_sim/jet.hpp"

namespace hapi_sim {

// State of a body frame B in a reference frame R at time t.
struct MotionSample {
  double t = 0.0;
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();  // B -> R rotation
  Eigen::Vector3d p = Eigen::Vector3d::Zero();            // origin of B in R
  Eigen::Vector3d v = Eigen::Vector3d::Zero();            // dp/dt, in R
  Eigen::Vector3d a = Eigen::Vector3d::Zero();            // d2p/dt2, in R
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();        // angular velocity of B w.r.t. R, in B
  Eigen::Vector3d alpha = Eigen::Vector3d::Zero();        // d(omega)/dt, in B
  Pose pose() const { Pose P; P.q = q; P.p = p; return P; }
};

// An analytic C2 motion: one template evaluation at a Jet2 time gives the
// pose and its exact first and second derivatives.
class RigidMotion {
 public:
  virtual ~RigidMotion() = default;
  virtual PoseT<Jet2> evaluate(const Jet2& t) const = 0;
  MotionSample sample(double t) const;
  Pose pose(double t) const { return sample(t).pose(); }
};

// A motion that never moves (identity pose unless given).
class StaticMotion : public RigidMotion {
 public:
  explicit StaticMotion(const Pose& P = Pose()) : P_(P) {}
  PoseT<Jet2> evaluate(const Jet2& t) const override;
 private:
  Pose P_;
};

// R, R', R'' and p, p', p'' -> MotionSample (omega = vee(R^T R'),
// alpha = vee(R'^T R' + R^T R'')).
MotionSample motionFromJets(double t, const PoseT<Jet2>& P);

// Frame B rigidly attached to frame A with the fixed pose T_AB (B in A).
MotionSample attachedFrame(const MotionSample& A, const Pose& T_AB);

// Frame C as seen from frame S when both move in the same reference frame:
// pose of C in S, velocity in S, angular velocity of C w.r.t. S in C.
// Accelerations are not filled (left zero): no consumer needs them.
MotionSample relativeMotion(const MotionSample& S, const MotionSample& C);

// Motion S of a frame that is itself placed at the fixed pose T in the
// reference: the same motion seen from the reference (velocities and
// accelerations turned, body rates unchanged).
MotionSample placedMotion(const Pose& T, const MotionSample& S);

Pose inversePose(const Pose& P);
Pose composePoses(const Pose& A, const Pose& B);  // A * B

}  // namespace hapi_sim
