// The inertial motion model (motion_model.hpp, docs/DESIGN.md "Inertial
// prediction"): the IMU body state [p, theta, v, b_g, b_a, g] with the
// standard quaternion ES-EKF step, and the left camera seen through the
// camera-IMU extrinsic, with the online calibration's rows after them
// (docs/DESIGN.md "Online calibration") and then the scanned surface's motion
// (docs/DESIGN.md "Scene motion state"). Error convention as everywhere in
// the filter:
//   p = p^ + dp, R = R^ Exp(dtheta), v = v^ + dv, b = b^ + db, g = g^ + dg,
//   R_bc = R_bc^ Exp(dtheta_bc), p_bc = p_bc^ + dp_bc, t_d = t_d^ + dt_d,
//   u_s = u_s^ + du_s, w_s = w_s^ + dw_s.
// Every Jacobian is checked against central finite differences in
// test/test_motion_models.cpp.
#include "hapi_eskf/eskf/motion_model.hpp"
#include "motion_models.hpp"
#include "hapi_eskf/so3.hpp"

namespace hapi_eskf {
namespace {

using Mat12xP = Eigen::Matrix<double, 12, Eigen::Dynamic>;

class InertialMotionModel final : public MotionModel {
 public:
  InertialMotionModel(const EskfSettings& s, const CameraExtrinsic& e)
      : MotionModel(e), s_(s), calib_(calibrationLayout(s)), scene_(sceneMotionLayout(s)), dim_(hapi_eskf::poseDim(s)) {}

  MotionModelKind kind() const override { return MotionModelKind::kInertial; }
  int poseDim() const override { return dim_; }
  bool usesImu() const override { return true; }
  CalibrationLayout calibration() const override { return calib_; }
  SceneMotionLayout sceneMotion() const override { return scene_; }

  // Body at rest under the camera, gravity straight down the world z axis
  // (the alignment, inertial_alignment.hpp, sets the real start); the
  // calibration at its configured prior.
  NominalState fromCamera(const PoseState& camera) const override {
    NominalState x;
    x.R_bc = extrinsic_.R_imu_cam;
    x.p_bc = extrinsic_.p_imu_cam;
    x.t_d = s_.imu_time_offset;
    moveCameraTo(&x, camera.p, camera.q);
    x.g = Vec3(0, 0, -s_.gravity_magnitude);
    return x;
  }

  PoseMat initialCovariance() const override {
    PoseMat C = PoseMat::Zero(dim_, dim_);
    auto var = [&](int idx, double sigma) { C.diagonal().segment<3>(idx).setConstant(sigma * sigma); };
    var(kIdxP, s_.initial_sigma_position);
    var(kIdxTheta, s_.initial_sigma_orientation);
    var(kIdxV, s_.initial_sigma_velocity);
    var(kIdxBg, s_.initial_sigma_gyro_bias);
    var(kIdxBa, s_.initial_sigma_accel_bias);
    var(kIdxG, s_.initial_sigma_gravity);
    if (calib_.extrinsic >= 0) {
      var(calib_.extrinsic, s_.calib_extrinsic_rotation_sigma);
      var(calib_.extrinsic + 3, s_.calib_extrinsic_translation_sigma);
    }
    if (calib_.time_offset >= 0)
      C(calib_.time_offset, calib_.time_offset) = s_.calib_time_offset_sigma * s_.calib_time_offset_sigma;
    if (scene_.any()) {
      var(scene_.row, s_.scene_velocity_sigma);
      var(scene_.row + 3, s_.scene_rate_sigma);
    }
    return C;
  }

  // R_wc = R_wb R_bc, p_wc = p + R_wb p_bc; the camera's angular rate is the
  // body's (w - b_g) in camera axes; its velocity adds the lever arm,
  // v_wc = v + R_wb (omega x p_bc). With the surface's motion, both are
  // relative to the surface: the rate less w_s, the velocity less the
  // surface's at the camera, u_s + w_s x R_wb p_bc (u_s is its velocity at
  // the body).
  PoseState camera(const NominalState& x) const override {
    const Mat3 R_wb = x.q.toRotationMatrix(), &R_bc = rotationBc(x);
    const Vec3& p_bc = translationBc(x);
    const Vec3 omega = rate(x);
    PoseState c;
    c.q = (x.q * Eigen::Quaterniond(R_bc)).normalized();
    c.p = x.p + R_wb * p_bc;
    c.w = R_bc.transpose() * omega;
    c.v = (R_wb * R_bc).transpose() * (x.v + R_wb * omega.cross(p_bc));
    if (scene_.any()) {
      c.w -= (R_wb * R_bc).transpose() * x.w_s;
      c.v -= (R_wb * R_bc).transpose() * (x.u_s + x.w_s.cross(R_wb * p_bc));
    }
    return c;
  }

  // dp_c     = dp - R_wb [p_bc]x dtheta
  // dtheta_c = R_bc^T dtheta
  // dv_c     = R_bc^T [R_wb^T v]x dtheta + R_bc^T R_wb^T dv + R_bc^T [p_bc]x db_g
  // dw_c     = -R_bc^T db_g
  // (without a sample the reported rate is 0, independent of b_g).
  // Calibration columns (docs/DESIGN.md "Online calibration"):
  //   dp_c = R_wb dp_bc,  dtheta_c = dtheta_bc,
  //   dv_c = [v_c]x dtheta_bc + R_bc^T [omega]x dp_bc,  dw_c = [w_c]x dtheta_bc;
  //   dt_d: dp_c = R_wc v_c dt_d, dtheta_c = w_c dt_d (the camera's motion
  //   over the offset; its velocity's change is second order).
  Mat12xP cameraStateJacobian(const NominalState& x) const override {
    const Mat3 R_wb = x.q.toRotationMatrix(), &R_bc = rotationBc(x);
    const Vec3& p_bc = translationBc(x);
    const Mat3 Rcb = R_bc.transpose();
    Mat12xP T = Mat12xP::Zero(12, dim_);
    T.block<3, 3>(0, kIdxP).setIdentity();
    T.block<3, 3>(0, kIdxTheta) = -R_wb * skew(p_bc);
    T.block<3, 3>(3, kIdxTheta) = Rcb;
    T.block<3, 3>(6, kIdxTheta) = Rcb * skew(R_wb.transpose() * x.v);
    T.block<3, 3>(6, kIdxV) = Rcb * R_wb.transpose();
    if (x.has_imu) {
      T.block<3, 3>(6, kIdxBg) = Rcb * skew(p_bc);
      T.block<3, 3>(9, kIdxBg) = -Rcb;
    }
    if (scene_.any()) addSceneColumns(x, &T);
    if (!calib_.any()) return T;
    const PoseState c = camera(x);
    if (calib_.extrinsic >= 0) {
      const int e = calib_.extrinsic;
      T.block<3, 3>(0, e + 3) = R_wb;
      T.block<3, 3>(3, e).setIdentity();
      T.block<3, 3>(6, e) = skew(c.v);
      T.block<3, 3>(6, e + 3) = Rcb * skew(rate(x)) - Rcb * R_wb.transpose() * skew(x.w_s) * R_wb;
      T.block<3, 3>(9, e) = skew(c.w);
    }
    if (calib_.time_offset >= 0) {
      T.block<3, 1>(0, calib_.time_offset) = c.q * c.v;
      T.block<3, 1>(3, calib_.time_offset) = c.w;
    }
    return T;
  }

  void moveCameraTo(NominalState* x, const Vec3& p, const Eigen::Quaterniond& q) const override {
    x->q = (q * Eigen::Quaterniond(rotationBc(*x)).conjugate()).normalized();
    x->p = p - x->q.toRotationMatrix() * translationBc(*x);
  }

  // t_cam = t_imu - t_d; the sample came with t_imu - imu_time_offset.
  ImuSample onEstimatedClock(const ImuSample& sample, const NominalState& x) const override {
    if (calib_.time_offset < 0) return sample;
    ImuSample out = sample;
    out.stamp -= x.t_d - s_.imu_time_offset;
    return out;
  }

  void stop(NominalState* x) const override {
    x->v.setZero();
    x->u_s.setZero();
    x->w_s.setZero();
  }
  // v is the body's world-frame velocity; the camera's displacement is the
  // body's (rotation changes are taken by the pose). A held device did not
  // move: the surface did, by -dp_world (d/dt p = v - u_s).
  void correctVelocity(NominalState* x, const Vec3& dp_world, double dt, bool scene_moving) const override {
    if (scene_moving && scene_.any())
      x->u_s -= dp_world / dt;
    else
      x->v += dp_world / dt;
  }

  // With the sample (the midpoint of it and the previous one, or the last
  // one held; before any sample, a sample of a body at rest):
  // omega = w_m - b_g, a = f_m - b_a, a_w = R a + g,
  //   p' = p + v dt + a_w dt^2 / 2,  v' = v + a_w dt,  R' = R Exp(omega dt).
  // Error state, first order:
  //   dp'     = dp + dv dt + (-R [a]x dtheta - R db_a + dg) dt^2 / 2
  //   dv'     = dv + (-R [a]x dtheta - R db_a + dg) dt
  //   dtheta' = Exp(omega dt)^T dtheta - J_r(omega dt) dt db_g
  // Noise: accelerometer white noise n_a (its mean over dt has variance
  // n_a^2 / dt) enters v as -R dt and p as -R dt^2 / 2; gyro noise n_g
  // enters theta as -J_r dt; the biases random-walk. n_a, n_g per IMU axis:
  // imuNoiseDensities (the datasheet's or the in-situ ones, if larger).
  void step(const NominalState& x, double dt, const ImuSample* imu, NominalState* next, PoseMat* F,
            PoseMat* Q) const override {
    *next = x;
    const Mat3 R = x.q.toRotationMatrix();
    Vec3 w_m, f_m;
    if (imu != nullptr) {
      // Midpoint rule: the sample at the end of the step and the previous
      // one average to the rate at the step's middle (second-order accurate;
      // the end sample alone lags half a sample period, which in 8-12 Hz
      // tremor and 1-3 Hz sway is a mm-level error per frame at 200 Hz).
      w_m = x.has_imu ? Vec3(0.5 * (x.w + imu->gyro)) : imu->gyro;
      f_m = x.has_imu ? Vec3(0.5 * (x.f + imu->accel)) : imu->accel;
      next->w = imu->gyro;
      next->f = imu->accel;
      next->has_imu = true;
    } else if (x.has_imu) {
      w_m = x.w;
      f_m = x.f;
    } else {
      w_m = x.b_g;
      f_m = x.b_a - R.transpose() * x.g;
    }
    const Vec3 omega = w_m - x.b_g, a = f_m - x.b_a;
    const Vec3 a_w = R * a + x.g;
    const double dt2 = 0.5 * dt * dt;
    next->p = x.p + x.v * dt + a_w * dt2;
    next->v = x.v + a_w * dt;
    next->q = (x.q * quatExp(omega * dt)).normalized();
    if (scene_.any()) stepScene(x, dt, next);

    const Mat3 I = Mat3::Identity(), Ra = -R * skew(a), Jr = rightJacobianSO3(omega * dt);
    *F = PoseMat::Identity(dim_, dim_);
    F->block<3, 3>(kIdxP, kIdxTheta) = Ra * dt2;
    F->block<3, 3>(kIdxP, kIdxV) = I * dt;
    F->block<3, 3>(kIdxP, kIdxBa) = -R * dt2;
    F->block<3, 3>(kIdxP, kIdxG) = I * dt2;
    F->block<3, 3>(kIdxV, kIdxTheta) = Ra * dt;
    F->block<3, 3>(kIdxV, kIdxBa) = -R * dt;
    F->block<3, 3>(kIdxV, kIdxG) = I * dt;
    F->block<3, 3>(kIdxTheta, kIdxTheta) = expSO3(omega * dt).transpose();
    F->block<3, 3>(kIdxTheta, kIdxBg) = -Jr * dt;

    const ImuNoiseDensity n = imuNoiseDensities(x, s_);
    *Q = PoseMat::Zero(dim_, dim_);
    if (isotropic(n.accel) && isotropic(n.gyro)) {
      const double na2 = n.accel.x() * n.accel.x(), ng2 = n.gyro.x() * n.gyro.x();
      Q->block<3, 3>(kIdxP, kIdxP) = I * (na2 * dt * dt * dt / 4.0);
      Q->block<3, 3>(kIdxP, kIdxV) = I * (na2 * dt * dt / 2.0);
      Q->block<3, 3>(kIdxV, kIdxP) = I * (na2 * dt * dt / 2.0);
      Q->block<3, 3>(kIdxV, kIdxV) = I * (na2 * dt);
      Q->block<3, 3>(kIdxTheta, kIdxTheta) = Jr * Jr.transpose() * (ng2 * dt);
    } else {
      // Densities per IMU axis (the in-situ ones differ between axes): the
      // accelerometer's noise in the world R diag(n_a^2) R^T, the gyro's
      // J_r diag(n_g^2) J_r^T.
      const Mat3 Na = R * n.accel.cwiseAbs2().asDiagonal() * R.transpose();
      const Mat3 Ng = Jr * n.gyro.cwiseAbs2().asDiagonal() * Jr.transpose();
      Q->block<3, 3>(kIdxP, kIdxP) = Na * (dt * dt * dt / 4.0);
      Q->block<3, 3>(kIdxP, kIdxV) = Na * (dt * dt / 2.0);
      Q->block<3, 3>(kIdxV, kIdxP) = Na * (dt * dt / 2.0);
      Q->block<3, 3>(kIdxV, kIdxV) = Na * dt;
      Q->block<3, 3>(kIdxTheta, kIdxTheta) = Ng * dt;
    }
    Q->block<3, 3>(kIdxBg, kIdxBg) = I * (s_.gyro_random_walk * s_.gyro_random_walk * dt);
    Q->block<3, 3>(kIdxBa, kIdxBa) = I * (s_.accel_random_walk * s_.accel_random_walk * dt);
    if (scene_.any()) sceneTransition(x, *next, dt, F, Q);
  }

  // First estimates (docs/DESIGN.md "First-estimate Jacobians"): with the
  // global rotation's null space N = [dp -[p]x, dtheta R^T, dv -[v]x,
  // dg -[g]x] at (p, R, v, g), F N(lin) = N(next) needs
  //   F_thth = R_next^T R_lin,
  //   F_vth  = -[v_next - v_lin - g_lin dt]x R_lin,
  //   F_pth  = -[p_next - p_lin - v_lin dt - g_lin dt^2 / 2]x R_lin,
  // which equal step()'s blocks when lin is the step's start; the bias
  // columns take R_lin as well.
  void firstEstimateTransition(const NominalState& lin, const NominalState& next, double dt,
                               PoseMat* F) const override {
    const Mat3 R = lin.q.toRotationMatrix(), Rn = next.q.toRotationMatrix();
    const double dt2 = 0.5 * dt * dt;
    const Vec3 dv = next.v - lin.v - lin.g * dt;
    const Vec3 dp = next.p - lin.p - lin.v * dt - lin.g * dt2;
    F->block<3, 3>(kIdxTheta, kIdxTheta) = Rn.transpose() * R;
    F->block<3, 3>(kIdxV, kIdxTheta) = -skew(dv) * R;
    F->block<3, 3>(kIdxP, kIdxTheta) = -skew(dp) * R;
    F->block<3, 3>(kIdxP, kIdxBa) = -R * dt2;
    F->block<3, 3>(kIdxV, kIdxBa) = -R * dt;
  }

  void inject(NominalState* x, const Eigen::Ref<const Eigen::VectorXd>& dx) const override {
    x->p += dx.segment<3>(kIdxP);
    x->q = (x->q * quatExp(dx.segment<3>(kIdxTheta))).normalized();
    x->v += dx.segment<3>(kIdxV);
    x->b_g += dx.segment<3>(kIdxBg);
    x->b_a += dx.segment<3>(kIdxBa);
    x->g += dx.segment<3>(kIdxG);
    if (calib_.extrinsic >= 0) {
      x->R_bc = Eigen::Quaterniond(x->R_bc * expSO3(dx.segment<3>(calib_.extrinsic))).normalized().toRotationMatrix();
      x->p_bc += dx.segment<3>(calib_.extrinsic + 3);
    }
    if (calib_.time_offset >= 0) x->t_d += dx(calib_.time_offset);
    if (scene_.any()) {
      x->u_s += dx.segment<3>(scene_.row);
      x->w_s += dx.segment<3>(scene_.row + 3);
    }
  }

  Eigen::VectorXd errorBetween(const NominalState& x, const NominalState& x_hat) const override {
    Eigen::VectorXd e(dim_);
    e.segment<3>(kIdxP) = x.p - x_hat.p;
    e.segment<3>(kIdxTheta) = logSO3((x_hat.q.conjugate() * x.q).toRotationMatrix());
    e.segment<3>(kIdxV) = x.v - x_hat.v;
    e.segment<3>(kIdxBg) = x.b_g - x_hat.b_g;
    e.segment<3>(kIdxBa) = x.b_a - x_hat.b_a;
    e.segment<3>(kIdxG) = x.g - x_hat.g;
    if (calib_.extrinsic >= 0) {
      e.segment<3>(calib_.extrinsic) = logSO3(x_hat.R_bc.transpose() * x.R_bc);
      e.segment<3>(calib_.extrinsic + 3) = x.p_bc - x_hat.p_bc;
    }
    if (calib_.time_offset >= 0) e(calib_.time_offset) = x.t_d - x_hat.t_d;
    if (scene_.any()) {
      e.segment<3>(scene_.row) = x.u_s - x_hat.u_s;
      e.segment<3>(scene_.row + 3) = x.w_s - x_hat.w_s;
    }
    return e;
  }

 private:
  // Equal densities on every axis (the datasheet's alone) keep the
  // isotropic form: bit for bit the filter without the in-situ noise.
  static bool isotropic(const Vec3& d) { return d.x() == d.y() && d.y() == d.z(); }
  static Vec3 rate(const NominalState& x) { return x.has_imu ? Vec3(x.w - x.b_g) : Vec3::Zero(); }

  // The surface's motion over a step (docs/DESIGN.md "Scene motion state"):
  // the world frame turns by w_s in the inertial one and its point at the
  // body moves by u_s, so in it the device's pose, inertial velocity and
  // gravity turn the other way, R' = Exp(-w_s dt) R Exp(omega dt),
  // v' -= (w_s x v) dt, g' -= (w_s x g) dt, and the device moves relative
  // to it, p' -= u_s dt; u_s and w_s decay by exp(-dt / tau).
  void stepScene(const NominalState& x, double dt, NominalState* next) const {
    next->q = (quatExp(-x.w_s * dt) * next->q).normalized();
    next->p -= x.u_s * dt;
    next->v -= x.w_s.cross(x.v) * dt;
    next->g -= x.w_s.cross(x.g) * dt;
    const double phi = std::exp(-dt / s_.scene_time_constant);
    next->u_s = phi * x.u_s;
    next->w_s = phi * x.w_s;
  }

  // stepScene's blocks of F and Q: the -[w_s]x dt terms on v and g, their
  // w_s columns [v]x dt, [g]x dt, u_s's -I dt on p, the rotation's
  // -(R Exp(omega dt))^T J_r(-w_s dt) dt (the left turn seen in the body
  // frame), and the Gauss-Markov decay phi with stationary variance
  // sigma^2, Q = sigma^2 (1 - phi^2).
  void sceneTransition(const NominalState& x, const NominalState& next, double dt, PoseMat* F, PoseMat* Q) const {
    const int u = scene_.row, w = scene_.row + 3;
    const Mat3 Ws = skew(x.w_s) * dt, I = Mat3::Identity();
    F->block<3, 3>(kIdxV, kIdxV) -= Ws;
    F->block<3, 3>(kIdxG, kIdxG) -= Ws;
    F->block<3, 3>(kIdxP, u) = -I * dt;
    F->block<3, 3>(kIdxV, w) = skew(x.v) * dt;
    F->block<3, 3>(kIdxG, w) = skew(x.g) * dt;
    const Mat3 R_turned = quatExp(-x.w_s * dt).conjugate() * next.q.toRotationMatrix();
    F->block<3, 3>(kIdxTheta, w) = -R_turned.transpose() * rightJacobianSO3(-x.w_s * dt) * dt;
    const double phi = std::exp(-dt / s_.scene_time_constant), keep = 1.0 - phi * phi;
    F->block<3, 3>(u, u) = I * phi;
    F->block<3, 3>(w, w) = I * phi;
    Q->block<3, 3>(u, u) = I * (s_.scene_velocity_sigma * s_.scene_velocity_sigma * keep);
    Q->block<3, 3>(w, w) = I * (s_.scene_rate_sigma * s_.scene_rate_sigma * keep);
  }

  // cameraStateJacobian's terms of the surface's motion, from camera()'s
  // c.v -= R_cw y with y = u_s + w_s x R_wb p_bc (the surface's velocity at
  // the camera) and c.w -= R_cw w_s, R_cw = R_bc^T R_wb^T:
  //   dv_c += (-R_bc^T [R_wb^T y]x + R_cw [w_s]x R_wb [p_bc]x) dtheta
  //           - R_cw du_s + R_cw [R_wb p_bc]x dw_s,
  //   dw_c += -R_bc^T [R_wb^T w_s]x dtheta - R_cw dw_s
  // (the extrinsic's dp_bc column in cameraStateJacobian).
  void addSceneColumns(const NominalState& x, Mat12xP* T) const {
    const Mat3 R_wb = x.q.toRotationMatrix(), &R_bc = rotationBc(x);
    const Vec3& p_bc = translationBc(x);
    const Mat3 R_cw = (R_wb * R_bc).transpose(), Rcb = R_bc.transpose();
    const Vec3 lever = R_wb * p_bc;
    const Vec3 y = x.u_s + x.w_s.cross(lever);  // the surface's velocity at the camera
    const int u = scene_.row, w = scene_.row + 3;
    T->block<3, 3>(6, kIdxTheta) += -Rcb * skew(R_wb.transpose() * y) + R_cw * skew(x.w_s) * R_wb * skew(p_bc);
    T->block<3, 3>(9, kIdxTheta) -= Rcb * skew(R_wb.transpose() * x.w_s);
    T->block<3, 3>(6, u) = -R_cw;
    T->block<3, 3>(6, w) = R_cw * skew(lever);
    T->block<3, 3>(9, w) = -R_cw;
  }
  // The extrinsic camera(x) uses: the state's when calibrated, else the
  // configured one.
  const Mat3& rotationBc(const NominalState& x) const {
    return calib_.extrinsic >= 0 ? x.R_bc : extrinsic_.R_imu_cam;
  }
  const Vec3& translationBc(const NominalState& x) const {
    return calib_.extrinsic >= 0 ? x.p_bc : extrinsic_.p_imu_cam;
  }

  EskfSettings s_;
  CalibrationLayout calib_;
  SceneMotionLayout scene_;
  int dim_;
};

}  // namespace

std::unique_ptr<MotionModel> makeInertialMotionModel(const EskfSettings& s, const CameraExtrinsic& e) {
  return std::make_unique<InertialMotionModel>(s, e);
}

}  // namespace hapi_eskf
