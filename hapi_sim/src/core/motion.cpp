// Rigid-motion kinematics of the simulator: jets -> exact derivatives, the
// lever-arm rule and the relative-motion rule (docs/DESIGN.md "Data").
#include "hapi_sim/motion.hpp"

namespace hapi_sim {
namespace {

Eigen::Matrix3d part(const M3<Jet2>& R, int k) {  // k = 0 value, 1 first, 2 second derivative
  Eigen::Matrix3d M;
  const V3<Jet2>* cols[3] = {&R.c0, &R.c1, &R.c2};
  for (int c = 0; c < 3; ++c) {
    const Jet2* e[3] = {&cols[c]->x, &cols[c]->y, &cols[c]->z};
    for (int r = 0; r < 3; ++r) M(r, c) = k == 0 ? e[r]->v : (k == 1 ? e[r]->d : e[r]->a);
  }
  return M;
}

Eigen::Vector3d part(const V3<Jet2>& p, int k) {
  auto g = [k](const Jet2& j) { return k == 0 ? j.v : (k == 1 ? j.d : j.a); };
  return {g(p.x), g(p.y), g(p.z)};
}

// vee of the skew-symmetric part (the exact matrices are skew; averaging
// removes rounding from the symmetric part).
Eigen::Vector3d veeSkew(const Eigen::Matrix3d& S) {
  return 0.5 * Eigen::Vector3d(S(2, 1) - S(1, 2), S(0, 2) - S(2, 0), S(1, 0) - S(0, 1));
}

}  // namespace

MotionSample RigidMotion::sample(double t) const { return motionFromJets(t, evaluate(Jet2::time(t))); }

PoseT<Jet2> StaticMotion::evaluate(const Jet2&) const {
  PoseT<Jet2> P;
  const Eigen::Matrix3d R = P_.q.toRotationMatrix();
  P.R = {V3<Jet2>(Eigen::Vector3d(R.col(0))), V3<Jet2>(Eigen::Vector3d(R.col(1))), V3<Jet2>(Eigen::Vector3d(R.col(2)))};
  P.p = V3<Jet2>(P_.p);
  return P;
}

MotionSample motionFromJets(double t, const PoseT<Jet2>& P) {
  MotionSample s;
  s.t = t;
  const Eigen::Matrix3d R = part(P.R, 0), Rd = part(P.R, 1), Rdd = part(P.R, 2);
  s.q = Eigen::Quaterniond(R).normalized();
  s.p = part(P.p, 0);
  s.v = part(P.p, 1);
  s.a = part(P.p, 2);
  s.omega = veeSkew(R.transpose() * Rd);
  s.alpha = veeSkew(Rd.transpose() * Rd + R.transpose() * Rdd);
  return s;
}

MotionSample attachedFrame(const MotionSample& A, const Pose& T_AB) {
  // p_B = p_A + R_A r; v_B = v_A + R_A (w x r);
  // a_B = a_A + R_A (alpha x r + w x (w x r)); w_B = R_AB^T w_A (docs/DESIGN.md "Data").
  MotionSample B;
  B.t = A.t;
  const Eigen::Matrix3d RA = A.q.toRotationMatrix();
  const Eigen::Vector3d& r = T_AB.p;
  const Eigen::Matrix3d RAB_T = T_AB.q.conjugate().toRotationMatrix();
  B.q = (A.q * T_AB.q).normalized();
  B.p = A.p + RA * r;
  B.v = A.v + RA * A.omega.cross(r);
  B.a = A.a + RA * (A.alpha.cross(r) + A.omega.cross(A.omega.cross(r)));
  B.omega = RAB_T * A.omega;
  B.alpha = RAB_T * A.alpha;
  return B;
}

MotionSample placedMotion(const Pose& T, const MotionSample& S) {
  MotionSample r = S;
  const Eigen::Matrix3d R = T.q.toRotationMatrix();
  r.q = (T.q * S.q).normalized();
  r.p = T.p + R * S.p;
  r.v = R * S.v;
  r.a = R * S.a;
  return r;
}

MotionSample relativeMotion(const MotionSample& S, const MotionSample& C) {
  // R_SC = R_S^T R_C, p_SC = R_S^T (p_C - p_S);
  // v_SC = R_S^T (v_C - v_S) - w_S x p_SC; w_SC = w_C - R_SC^T w_S (docs/DESIGN.md "Data").
  MotionSample r;
  r.t = C.t;
  const Eigen::Matrix3d RS_T = S.q.conjugate().toRotationMatrix();
  r.q = (S.q.conjugate() * C.q).normalized();
  r.p = RS_T * (C.p - S.p);
  r.v = RS_T * (C.v - S.v) - S.omega.cross(r.p);
  r.omega = C.omega - r.q.conjugate().toRotationMatrix() * S.omega;
  r.a.setZero();
  r.alpha.setZero();
  return r;
}

Pose inversePose(const Pose& P) {
  Pose r;
  r.q = P.q.conjugate();
  r.p = -(r.q * P.p);
  return r;
}

Pose composePoses(const Pose& A, const Pose& B) {
  Pose r;
  r.q = (A.q * B.q).normalized();
  r.p = A.p + A.q * B.p;
  return r;
}

}  // namespace hapi_sim
