// The FastSLAM 2.0 particle step (particle.hpp; equations: docs/DESIGN.md
// "FastSLAM 2.0"). With the known landmarks' measurements stacked,
// r = z - h(x^, mu), A = dh/dx (3n x 6), D = blockdiag(S_j),
// S_j = Cz_j + H_m Sigma_j H_m^T, and Q = L L^T:
//   proposal   Sigma_p = (Q^-1 + A^T D^-1 A)^-1 = L M^-1 L^T, M = I + L^T A^T D^-1 A,
//              mean    = Sigma_p A^T D^-1 r;
//   weight     log N(r; 0, D + A Q A^T) = -1/2 (r^T D^-1 r - b^T Sigma_p b + log det D + log det M)
//              with b = A^T D^-1 r (Woodbury and the determinant lemma),
// which needs neither Q^-1 (Q may be singular) nor a 3n x 3n matrix. A and r
// are those of the last linearisation of the iterated proposal (r moved to
// delta = 0, see below).
#include "hapi_eskf/fastslam/particle.hpp"

#include "hapi_eskf/backend/measurement_model.hpp"
#include "hapi_eskf/so3.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <cmath>

namespace hapi_eskf {
namespace fastslam {
namespace {

using Vec6 = Eigen::Matrix<double, 6, 1>;

// Gauss-Newton iterations of the proposal's mean (at most; it stops when converged).
constexpr int kProposalIterations = 5;

// L with L L^T = Q for a symmetric PSD Q (eigen-decomposition: Q may be singular).
Mat6 psdSqrt(const Mat6& Q) {
  const Eigen::SelfAdjointEigenSolver<Mat6> es(0.5 * (Q + Q.transpose()));
  const Vec6 d = es.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  return es.eigenvectors() * d.asDiagonal();
}

}  // namespace

bool stepParticle(const std::vector<SlotMeasurement>& measurements, double dt, const Mat6& Q, std::mt19937& rng,
                  Particle* particle) {
  Particle& x = *particle;
  PoseState pred;
  pred.p = x.p + x.v * dt;
  pred.q = (x.q * quatExp(x.w * dt)).normalized();

  // The proposal's mean by Gauss-Newton (an iterated EKF step): linearised
  // at the current mean delta_i, the stacked model is r_i ~ A (delta - delta_i),
  // so the prior's and the measurements' quadratic is minimised by
  // (Q^-1 + A^T D^-1 A) delta = A^T D^-1 (r_i + A delta_i). One step is the
  // textbook proposal; the iterations remove the linearisation error of a
  // poor prediction (a fast turn), where the stereo points pin the pose far
  // tighter than the motion prior.
  const Mat6 L = psdSqrt(Q);
  Vec6 delta_i = Vec6::Zero(), b = Vec6::Zero(), mean = Vec6::Zero();
  Mat6 Sigma_p = Mat6::Zero();
  Eigen::LLT<Mat6> mllt;
  double rDr = 0.0, logdetD = 0.0;
  for (int it = 0; it < kProposalIterations; ++it) {
    PoseState lin = pred;
    lin.p += delta_i.head<3>();
    lin.q = (lin.q * quatExp(delta_i.tail<3>())).normalized();
    Mat6 AtDA = Mat6::Zero();
    b.setZero();
    rDr = 0.0;
    logdetD = 0.0;
    for (const SlotMeasurement& m : measurements) {
      if (m.is_new) continue;
      const LandmarkEkf& l = *x.map[m.slot];
      Mat36 Hx;
      Mat3 Hm;
      measurementJacobian(lin, l.mean, &Hx, &Hm);
      const Mat3 S = m.Cz + Hm * l.cov * Hm.transpose();
      const Eigen::LLT<Mat3> llt(S);
      if (llt.info() != Eigen::Success) return false;
      // The residual of the model linearised here, evaluated at delta = 0.
      const Vec3 r = m.z - measure(lin, l.mean) + Hx * delta_i;
      const Eigen::Matrix<double, 6, 3> HtSi = llt.solve(Hx).transpose();
      AtDA += HtSi * Hx;
      b += HtSi * r;
      rDr += r.dot(llt.solve(r));
      logdetD += 2.0 * llt.matrixLLT().diagonal().array().log().sum();
    }
    mllt.compute(Mat6::Identity() + L.transpose() * AtDA * L);
    if (mllt.info() != Eigen::Success) return false;
    Sigma_p = L * mllt.solve(L.transpose());
    mean = Sigma_p * b;
    if (!mean.allFinite()) return false;
    const bool converged = (mean - delta_i).norm() < 1e-9;
    delta_i = mean;
    if (converged) break;
  }
  // Sample: with M = L_M L_M^T (Eigen's LLT, U = L_M^T), u = U^-1 n has
  // covariance M^-1, so L u has L M^-1 L^T = Sigma_p.
  std::normal_distribution<double> n01(0.0, 1.0);
  Vec6 n;
  for (int i = 0; i < 6; ++i) n(i) = n01(rng);
  const Vec6 u = mllt.matrixU().solve(n);
  const Vec6 delta = mean + L * u;
  if (!delta.allFinite()) return false;
  const double logdetM = 2.0 * mllt.matrixLLT().diagonal().array().log().sum();
  const double log_lik = -0.5 * (rDr - b.dot(Sigma_p * b) + logdetD + logdetM);
  if (!std::isfinite(log_lik)) return false;

  // The sampled pose; the landmarks' EKFs at it.
  PoseState s = pred;
  s.p += delta.head<3>();
  s.q = (s.q * quatExp(delta.tail<3>())).normalized();
  std::vector<std::shared_ptr<const LandmarkEkf>> map = x.map;
  const Mat3 R = s.q.toRotationMatrix();
  for (const SlotMeasurement& m : measurements) {
    if (m.is_new) {
      auto l = std::make_shared<LandmarkEkf>();
      l->mean = initLandmark(s, m.z);
      l->cov = R * m.Cz * R.transpose();
      map.push_back(std::move(l));
      continue;
    }
    const LandmarkEkf& old = *map[m.slot];
    const Mat3 Hm = R.transpose();
    const Mat3 S = Hm * old.cov * Hm.transpose() + m.Cz;
    const Eigen::LLT<Mat3> llt(S);
    if (llt.info() != Eigen::Success) return false;
    const Mat3 K = llt.solve(Hm * old.cov).transpose();  // Sigma H^T S^-1 (S, Sigma symmetric)
    auto l = std::make_shared<LandmarkEkf>();
    l->mean = old.mean + K * (m.z - measure(s, old.mean));
    const Mat3 IKH = Mat3::Identity() - K * Hm;
    l->cov = IKH * old.cov * IKH.transpose() + K * m.Cz * K.transpose();  // Joseph form
    l->cov = (0.5 * (l->cov + l->cov.transpose())).eval();
    map[m.slot] = std::move(l);
  }
  if (dt > 0.0) {
    x.v = (s.p - x.p) / dt;
    x.w = logSO3(x.q.toRotationMatrix().transpose() * R) / dt;
  }
  x.p = s.p;
  x.q = s.q;
  x.map = std::move(map);
  x.log_weight += log_lik;
  return true;
}

}  // namespace fastslam
}  // namespace hapi_eskf
