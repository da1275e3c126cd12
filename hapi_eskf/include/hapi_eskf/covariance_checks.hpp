// The one test of "this matrix is a covariance": finite, symmetric within a
// relative tolerance, and positive definite (its Cholesky factor exists).
// The nodelet's message validation, Eskf's frame check and the backends'
// input checks all use it, so a covariance accepted at one stage is accepted
// at every later one.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace hapi_eskf {

// Relative: covariances come in m^2 from 1e-8 to 1e-2, so no absolute
// tolerance suits them all. Round-off of a symmetric computation is far below
// it; a corrupted or transposed-wrong matrix far above.
constexpr double kSymmetryTolerance = 1e-9;

// max |M - M^T| <= kSymmetryTolerance * max |M|.
template <typename Derived>
bool isNearlySymmetric(const Eigen::MatrixBase<Derived>& M) {
  return (M - M.transpose()).cwiseAbs().maxCoeff() <= kSymmetryTolerance * M.cwiseAbs().maxCoeff();
}

// Finite, nearly symmetric and positive definite (Cholesky of the lower
// triangle succeeds: the factorisation the filter itself relies on).
template <typename Derived>
bool isSymmetricPositiveDefinite(const Eigen::MatrixBase<Derived>& M) {
  if (!M.allFinite() || !isNearlySymmetric(M)) return false;
  return Eigen::LLT<typename Derived::PlainObject>(M).info() == Eigen::Success;
}

}  // namespace hapi_eskf
