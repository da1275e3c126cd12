// The input checks written once for every stage: the covariance test
// (covariance_checks.hpp) and CovarianceBackend's validating public methods,
// which must reject bad input before any implementation runs.
#include "hapi_eskf/covariance/covariance_backend.hpp"
#include "hapi_eskf/covariance_checks.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace hapi_eskf {
namespace {

TEST(CovarianceChecks, SymmetricPositiveDefiniteAtAnyScale) {
  const Mat3 C = Vec3(1e-4, 2e-4, 5e-4).asDiagonal();
  EXPECT_TRUE(isSymmetricPositiveDefinite(C));
  EXPECT_TRUE(isSymmetricPositiveDefinite(Mat3(1e-12 * C)));  // tiny but valid
  Mat3 A = C;
  A(0, 1) = 1e-6;
  A(1, 0) = 1e-6 * (1 + 1e-12);  // round-off: accepted
  EXPECT_TRUE(isSymmetricPositiveDefinite(A));
  Mat3 B = 1e-6 * C;
  B(0, 1) = 1e-11;  // 2 % of the largest entry, tiny in absolute terms: refused
  EXPECT_FALSE(isNearlySymmetric(B));
  EXPECT_FALSE(isSymmetricPositiveDefinite(B));
  EXPECT_FALSE(isSymmetricPositiveDefinite(Mat3(-C)));
  EXPECT_FALSE(isSymmetricPositiveDefinite(Mat3::Zero().eval()));
  Mat3 D = C;
  D(2, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(isSymmetricPositiveDefinite(D));
  Mat12 P = 1e-6 * Mat12::Identity();
  EXPECT_TRUE(isSymmetricPositiveDefinite(P));
  P(11, 11) = 0;
  EXPECT_FALSE(isSymmetricPositiveDefinite(P));
}

// Counts the implementation calls that get through the interface's checks.
class RecordingBackend final : public CovarianceBackend {
 public:
  RecordingBackend() : CovarianceBackend(kCameraMotionDim) {}
  int calls = 0;
  int K = 3;
  const char* name() const override { return "recording"; }
  int capacity() const override { return 4; }
  int numLandmarks() const override { return K; }
  int descriptorLength() const override { return 8; }
  std::size_t memoryBytes() const override { return 0; }
  PoseMat poseCovariance() const override { return PoseMat::Identity(kCameraMotionDim, kCameraMotionDim); }
  std::vector<Mat3> landmarkCovariances() const override { return {}; }
  Eigen::MatrixXd denseCovariance() const override { return Eigen::MatrixXd(); }
  std::vector<uint8_t> descriptors() const override { return {}; }

 protected:
  Status doReset(const PoseMat&) override { return record(); }
  Status doPredict(const PoseMat&, const PoseMat&) override { return record(); }
  Status doMarginals(const std::vector<int>&, std::vector<Mat9>*) const override { return record(); }
  Status doUpdate(const std::vector<MeasurementBlock>&, Eigen::VectorXd*, double*) override { return record(); }
  Status doAddLandmarks(const std::vector<NewLandmarkBlock>&) override { return record(); }
  Status doRemoveLandmarks(const std::vector<int>&) override { return record(); }
  Status doMatchDescriptors(const uint8_t*, int, std::vector<DescriptorMatch>*) const override { return record(); }

 private:
  Status record() const {
    ++const_cast<RecordingBackend*>(this)->calls;
    return Status::kOk;
  }
};

TEST(BackendInterface, BadInputNeverReachesTheImplementation) {
  RecordingBackend b;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Eigen::VectorXd dx;
  std::vector<Mat9> M;
  std::vector<DescriptorMatch> matches;
  MeasurementBlock blk;
  blk.slot = 1;
  NewLandmarkBlock add;
  const uint8_t desc[8] = {};
  add.descriptor = desc;

  Mat12 asym = Mat12::Identity();
  asym(0, 1) = 0.5;
  EXPECT_EQ(b.reset(asym), Status::kInvalidArgument);
  EXPECT_EQ(b.reset(Mat12::Constant(nan)), Status::kNonFinite);
  EXPECT_EQ(b.reset(-Mat12::Identity()), Status::kNotPositiveDefinite);
  EXPECT_EQ(b.predict(Mat12::Constant(nan), Mat12::Zero()), Status::kNonFinite);
  // The pose block's size is the backend's: an 18 x 18 F, Q or C does not fit a 12-row block.
  const PoseMat I18 = PoseMat::Identity(kInertialDim, kInertialDim);
  EXPECT_EQ(b.reset(I18), Status::kInvalidArgument);
  EXPECT_EQ(b.predict(I18, I18), Status::kInvalidArgument);
  EXPECT_EQ(b.predict(Mat12::Identity(), I18), Status::kInvalidArgument);
  EXPECT_EQ(b.marginals({0, 3}, &M), Status::kInvalidArgument);
  EXPECT_EQ(b.marginals({0}, nullptr), Status::kInvalidArgument);
  EXPECT_EQ(b.update({}, &dx), Status::kEmptyInput);
  EXPECT_EQ(b.update({blk}, nullptr), Status::kInvalidArgument);
  EXPECT_EQ(b.update({blk, blk}, &dx), Status::kDuplicateId);
  EXPECT_EQ(b.update({blk, blk, blk, blk}, &dx), Status::kCapacityExceeded);  // 4 blocks > K = 3
  MeasurementBlock far = blk;
  far.slot = 3;
  EXPECT_EQ(b.update({far}, &dx), Status::kInvalidArgument);
  MeasurementBlock bad = blk;
  bad.innovation.x() = nan;
  EXPECT_EQ(b.update({bad}, &dx), Status::kNonFinite);
  EXPECT_EQ(b.addLandmarks({add, add}), Status::kCapacityExceeded);  // 3 + 2 > 4
  NewLandmarkBlock notpd = add;
  notpd.Cz = -Mat3::Identity();
  EXPECT_EQ(b.addLandmarks({notpd}), Status::kNotPositiveDefinite);
  NewLandmarkBlock nodesc = add;
  nodesc.descriptor = nullptr;
  EXPECT_EQ(b.addLandmarks({nodesc}), Status::kInvalidArgument);
  EXPECT_EQ(b.removeLandmarks({2, 2}), Status::kDuplicateId);
  EXPECT_EQ(b.removeLandmarks({-1}), Status::kInvalidArgument);
  EXPECT_EQ(b.matchDescriptors(nullptr, 1, &matches), Status::kInvalidArgument);
  EXPECT_EQ(b.matchDescriptors(desc, -1, &matches), Status::kInvalidArgument);
  EXPECT_EQ(b.calls, 0);

  // Trivial calls are answered by the interface itself.
  EXPECT_EQ(b.addLandmarks({}), Status::kOk);
  EXPECT_EQ(b.removeLandmarks({}), Status::kOk);
  EXPECT_EQ(b.marginals({}, &M), Status::kOk);
  EXPECT_TRUE(M.empty());
  b.K = 0;
  EXPECT_EQ(b.matchDescriptors(desc, 1, &matches), Status::kOk);
  ASSERT_EQ(matches.size(), 1u);
  EXPECT_EQ(matches[0].best_slot, -1);
  EXPECT_EQ(b.calls, 0);

  // Valid input gets through, once per call.
  b.K = 3;
  EXPECT_EQ(b.reset(Mat12::Identity()), Status::kOk);
  EXPECT_EQ(b.predict(Mat12::Identity(), Mat12::Zero()), Status::kOk);
  EXPECT_EQ(b.marginals({0, 2, 0}, &M), Status::kOk);
  EXPECT_EQ(M.size(), 3u);
  EXPECT_EQ(b.update({blk}, &dx), Status::kOk);
  EXPECT_EQ(b.addLandmarks({add}), Status::kOk);
  EXPECT_EQ(b.removeLandmarks({0, 2}), Status::kOk);
  EXPECT_EQ(b.matchDescriptors(desc, 1, &matches), Status::kOk);
  EXPECT_EQ(b.calls, 7);
}

}  // namespace
}  // namespace hapi_eskf
