// Robust local affine flow fit with covariance (affine_flow_fit.hpp).
#include "hapi_frontend/affine_flow_fit.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace hapi_frontend {
namespace {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
// Parameter indices of the u and v components in the message's order.
constexpr int kU[3] = {0, 2, 3};
constexpr int kV[3] = {1, 4, 5};

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  const std::size_t k = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

struct Problem {
  std::vector<Vec3> rows;          // [1, x_u - u, x_v - v]
  std::vector<Eigen::Vector2d> d;  // displacements
};

// Residual of track i under the parameters p_u, p_v.
Eigen::Vector2d residual(const Problem& pb, std::size_t i, const Vec3& pu, const Vec3& pv) {
  return pb.d[i] - Eigen::Vector2d(pb.rows[i].dot(pu), pb.rows[i].dot(pv));
}

// 1.4826 x the median absolute residual component: sigma of Gaussian
// residuals, insensitive to up to half of them being outliers.
double robustScale(const Problem& pb, const Vec3& pu, const Vec3& pv, double floor) {
  std::vector<double> a;
  a.reserve(2 * pb.rows.size());
  for (std::size_t i = 0; i < pb.rows.size(); ++i) {
    const Eigen::Vector2d r = residual(pb, i, pu, pv);
    a.push_back(std::fabs(r.x()));
    a.push_back(std::fabs(r.y()));
  }
  return std::max(floor, 1.4826 * median(a));
}

// Weighted least squares of both components with per-equation weights; false
// when the weighted points do not span the plane.
bool weightedSolve(const Problem& pb, const std::vector<double>& wu, const std::vector<double>& wv, Vec3* pu,
                   Vec3* pv) {
  Mat3 nu = Mat3::Zero(), nv = Mat3::Zero();
  Vec3 bu = Vec3::Zero(), bv = Vec3::Zero();
  for (std::size_t i = 0; i < pb.rows.size(); ++i) {
    const Vec3& a = pb.rows[i];
    nu.noalias() += wu[i] * a * a.transpose();
    nv.noalias() += wv[i] * a * a.transpose();
    bu += wu[i] * pb.d[i].x() * a;
    bv += wv[i] * pb.d[i].y() * a;
  }
  // Relative conditioning: collinear or coincident points leave a gradient
  // direction undetermined.
  for (const Mat3* n : {&nu, &nv}) {
    const Eigen::SelfAdjointEigenSolver<Mat3> es(*n, Eigen::EigenvaluesOnly);
    if (!(es.eigenvalues()(0) > 1e-9 * std::max(1.0, es.eigenvalues()(2)))) return false;
  }
  *pu = nu.ldlt().solve(bu);
  *pv = nv.ldlt().solve(bv);
  return pu->allFinite() && pv->allFinite();
}

// The exact fit of three tracks (both components); false when they are
// (nearly) collinear.
bool exactFit(const Problem& pb, const std::size_t idx[3], Vec3* pu, Vec3* pv) {
  Mat3 a;
  Vec3 bu, bv;
  for (int r = 0; r < 3; ++r) {
    a.row(r) = pb.rows[idx[r]].transpose();
    bu(r) = pb.d[idx[r]].x();
    bv(r) = pb.d[idx[r]].y();
  }
  const Eigen::FullPivLU<Mat3> lu(a);
  if (lu.rank() < 3 || std::fabs(lu.determinant()) < 1e-6) return false;
  *pu = lu.solve(bu);
  *pv = lu.solve(bv);
  return true;
}

// Least median of squares (Rousseeuw): of kSamples exact fits to three
// tracks, the one whose median squared residual is smallest; the median
// displacement when none is usable. Robust to almost half of the tracks
// being wrong, which the Huber fit alone is not (its influence is bounded,
// not zero). Samples from a fixed-seed generator: the same tracks give the
// same flow.
void leastMedianStart(const Problem& pb, Vec3* pu, Vec3* pv) {
  const std::size_t n = pb.rows.size();
  std::vector<double> du(n), dv(n), r2(n);
  for (std::size_t i = 0; i < n; ++i) du[i] = pb.d[i].x(), dv[i] = pb.d[i].y();
  *pu = Vec3(median(du), 0, 0);
  *pv = Vec3(median(dv), 0, 0);
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) r2[i] = residual(pb, i, *pu, *pv).squaredNorm();
  best = median(r2);
  constexpr int kSamples = 64;
  std::mt19937 rng(12345);
  std::uniform_int_distribution<std::size_t> pick(0, n - 1);
  for (int k = 0; k < kSamples; ++k) {
    const std::size_t idx[3] = {pick(rng), pick(rng), pick(rng)};
    if (idx[0] == idx[1] || idx[1] == idx[2] || idx[0] == idx[2]) continue;
    Vec3 u, v;
    if (!exactFit(pb, idx, &u, &v)) continue;
    for (std::size_t i = 0; i < n; ++i) r2[i] = residual(pb, i, u, v).squaredNorm();
    const double med = median(r2);
    if (med < best) {
      best = med;
      *pu = u;
      *pv = v;
    }
  }
}

double huberWeight(double r, double threshold) {
  const double a = std::fabs(r);
  return a <= threshold ? 1.0 : threshold / a;
}

}  // namespace

AffineFlowFit fitAffineFlow(const std::vector<Eigen::Vector2d>& from, const std::vector<Eigen::Vector2d>& displacement,
                            const Eigen::Vector2d& centre, const AffineFitSettings& s) {
  AffineFlowFit fit;
  const std::size_t n = std::min(from.size(), displacement.size());
  fit.inlier.assign(from.size(), false);
  if (static_cast<int>(n) < std::max(4, s.min_inliers)) return fit;
  Problem pb;
  for (std::size_t i = 0; i < n; ++i) {
    if (!from[i].allFinite() || !displacement[i].allFinite()) return fit;
    pb.rows.emplace_back(1.0, from[i].x() - centre.x(), from[i].y() - centre.y());
    pb.d.push_back(displacement[i]);
  }

  // Start: least median of squares over minimal samples, then Huber IRLS.
  Vec3 pu, pv;
  leastMedianStart(pb, &pu, &pv);
  // The scale stays that of the start: re-estimated from the Huber fit, it
  // grows with the pull of the outliers and lets them in (a third of the
  // tracks wrong by 1-5 px moved the flow by 0.6 px, AffineFlowFit test).
  std::vector<double> wu(n, 1.0), wv(n, 1.0);
  const double scale = robustScale(pb, pu, pv, s.min_sigma);
  for (int it = 0; it < 30; ++it) {
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector2d r = residual(pb, i, pu, pv);
      wu[i] = huberWeight(r.x(), s.huber_k * scale);
      wv[i] = huberWeight(r.y(), s.huber_k * scale);
    }
    Vec3 nu, nv;
    if (!weightedSolve(pb, wu, wv, &nu, &nv)) return fit;
    const double step = std::max((nu - pu).cwiseAbs().maxCoeff(), (nv - pv).cwiseAbs().maxCoeff());
    pu = nu;
    pv = nv;
    if (step < 1e-7) break;
  }

  // Inliers, then plain least squares on them.
  std::vector<double> w(n, 0.0);
  int m = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d r = residual(pb, i, pu, pv);
    if (r.cwiseAbs().maxCoeff() <= s.outlier_sigmas * scale) {
      w[i] = 1.0;
      fit.inlier[i] = true;
      ++m;
    }
  }
  fit.inliers = m;
  if (m < std::max(4, s.min_inliers)) return fit;
  if (!weightedSolve(pb, w, w, &pu, &pv)) return fit;
  double ss = 0;
  Mat3 normal = Mat3::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    if (w[i] == 0.0) continue;
    ss += residual(pb, i, pu, pv).squaredNorm();
    normal.noalias() += pb.rows[i] * pb.rows[i].transpose();
  }
  fit.sigma = std::max(s.min_sigma, std::sqrt(ss / (2.0 * m - 6.0)));
  const Mat3 block = fit.sigma * fit.sigma * normal.inverse();
  for (int r = 0; r < 3; ++r) {
    fit.affine(kU[r]) = pu(r);
    fit.affine(kV[r]) = pv(r);
    for (int c = 0; c < 3; ++c) {
      fit.covariance(kU[r], kU[c]) = block(r, c);
      fit.covariance(kV[r], kV[c]) = block(r, c);
    }
  }
  fit.ok = fit.affine.allFinite() && fit.covariance.allFinite();
  return fit;
}

}  // namespace hapi_frontend
