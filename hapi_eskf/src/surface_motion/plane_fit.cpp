#include "hapi_eskf/surface_motion/plane_fit.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace hapi_eskf {
namespace surface_motion {
namespace {

// Weighted total least squares: the normal is the smallest eigenvector of
// the weighted scatter about the weighted centroid.
bool weightedPlane(const std::vector<Vec3>& pts, const std::vector<double>& w, Vec3* n, double* c) {
  double sw = 0;
  Vec3 m = Vec3::Zero();
  for (std::size_t i = 0; i < pts.size(); ++i) {
    sw += w[i];
    m += w[i] * pts[i];
  }
  if (sw <= 0) return false;
  m /= sw;
  Mat3 S = Mat3::Zero();
  for (std::size_t i = 0; i < pts.size(); ++i) S += w[i] * (pts[i] - m) * (pts[i] - m).transpose();
  Eigen::SelfAdjointEigenSolver<Mat3> es(S);
  // Collinear points: two vanishing eigenvalues, no plane.
  if (es.eigenvalues()(1) <= 1e-12 * std::max(es.eigenvalues()(2), 1e-300)) return false;
  *n = es.eigenvectors().col(0).normalized();
  *c = n->dot(m);
  return true;
}

double median(std::vector<double> v) {
  const std::size_t k = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

// Least median of squares over point triples (every triple of a small set,
// else a fixed pseudo-random choice of kTriples): the plane that half the
// points fit best, whatever the other half. Scale-free, so it needs no
// threshold; false when every triple is degenerate.
bool lmedsPlane(const std::vector<Vec3>& pts, Vec3* n_best, double* c_best, double* med_best) {
  constexpr int kTriples = 100;
  const std::size_t n = pts.size();
  std::vector<double> absr(n);
  *med_best = std::numeric_limits<double>::infinity();
  std::uint32_t lcg = 12345u;
  auto next = [&]() {
    lcg = lcg * 1664525u + 1013904223u;
    return static_cast<std::size_t>(lcg >> 8) % n;
  };
  const bool all = n * (n - 1) * (n - 2) / 6 <= static_cast<std::size_t>(kTriples);
  std::size_t i = 0, j = 1, k = 1;
  for (int trial = 0; trial < kTriples; ++trial) {
    if (all) {  // the next triple i < j < k
      if (++k >= n) {
        if (++j >= n - 1) {
          if (++i >= n - 2) break;
          j = i + 1;
        }
        k = j + 1;
      }
    } else {
      i = next();
      j = next();
      k = next();
    }
    const Vec3 nn = (pts[j] - pts[i]).cross(pts[k] - pts[i]);
    if (nn.norm() < 1e-12) continue;
    const Vec3 nu = nn.normalized();
    const double c = nu.dot(pts[i]);
    for (std::size_t m = 0; m < n; ++m) absr[m] = std::abs(nu.dot(pts[m]) - c);
    const double med = median(absr);
    if (med < *med_best) {
      *med_best = med;
      *n_best = nu;
      *c_best = c;
    }
  }
  return std::isfinite(*med_best);
}

}  // namespace

PlaneFit fitPlane(const std::vector<Vec3>& pts, double huber_k, int iterations, double sigma_floor) {
  PlaneFit f;
  if (pts.size() < 3) return f;
  std::vector<double> w(pts.size(), 1.0), absr(pts.size());
  Vec3 n;
  double c = 0, med = 0, scale = sigma_floor;
  // Start: the least-median plane's inliers (2.5 robust sigmas), fitted.
  if (!lmedsPlane(pts, &n, &c, &med)) return f;
  const double keep = 2.5 * std::max(1.4826 * med, sigma_floor);
  for (std::size_t i = 0; i < pts.size(); ++i) w[i] = std::abs(n.dot(pts[i]) - c) <= keep ? 1.0 : 0.0;
  if (!weightedPlane(pts, w, &n, &c)) return f;
  for (int it = 0; it < iterations; ++it) {
    for (std::size_t i = 0; i < pts.size(); ++i) absr[i] = std::abs(n.dot(pts[i]) - c);
    scale = std::max(1.4826 * median(absr), sigma_floor);
    const double k = huber_k * scale;
    for (std::size_t i = 0; i < pts.size(); ++i) w[i] = absr[i] <= k ? 1.0 : k / absr[i];
    if (!weightedPlane(pts, w, &n, &c)) return f;
  }
  // Residual variance of the weighted fit (3 parameters), floored.
  double sw = 0, swr2 = 0;
  f.inliers = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const double r = n.dot(pts[i]) - c;
    sw += w[i];
    swr2 += w[i] * r * r;
    f.inliers += std::abs(r) <= huber_k * scale;
  }
  const double dof = std::max(sw - 3.0, 1.0);
  f.sigma = std::max(std::sqrt(swr2 / dof), sigma_floor);
  f.normal = n;
  f.offset = c;
  f.t1 = n.unitOrthogonal();
  f.t2 = n.cross(f.t1);
  // r_i(a, b, c) = (n + a t1 + b t2) . X_i - c: d r_i / d(a, b, c) = [t1 . X_i, t2 . X_i, -1].
  Mat3 H = Mat3::Zero();
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const Vec3 J(f.t1.dot(pts[i]), f.t2.dot(pts[i]), -1.0);
    H += w[i] * J * J.transpose();
  }
  Eigen::LDLT<Mat3> ldlt(H);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().array() > 0).all()) return f;
  f.covariance = f.sigma * f.sigma * ldlt.solve(Mat3::Identity());
  f.covariance = 0.5 * (f.covariance + f.covariance.transpose()).eval();
  f.ok = f.covariance.allFinite();
  return f;
}

}  // namespace surface_motion
}  // namespace hapi_eskf
