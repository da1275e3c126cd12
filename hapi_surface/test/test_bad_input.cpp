// Bad input to the surface core: an error code, and nothing it was given
// to update changes (volume, keyframes, projected values).
#include "hapi_surface/surface_mapper.hpp"

#include "synthetic_scene.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace hapi_surface {
namespace {

using test::lookAt;
using test::Scene;
using test::testCamera;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

class BadInput : public ::testing::Test {
 protected:
  void SetUp() override {
    s_ = test::volumeOf(0.05, 0.05, 0.02);
    scene_.addPlane(Eigen::Vector3d(0, 0, 1), 0.25);
    good_.camera = testCamera();
    good_.depth = scene_.depth(good_.camera, Eigen::Isometry3d::Identity());
    mapper_ = std::make_unique<SurfaceMapper>(s_);
    FrameUse use;
    ASSERT_EQ(mapper_->addDepthFrame(0.0, good_, Eigen::Isometry3d::Identity(), &use), SurfaceStatus::kOk);
    image_ = scene_.pattern(good_.camera, Eigen::Isometry3d::Identity(), [](const Eigen::Vector3d&) { return 5.0; });
    ASSERT_EQ(mapper_->addImagingFrame(image_, good_.camera, Eigen::Isometry3d::Identity()).status, SurfaceStatus::kOk);
    snapshot();
  }

  void snapshot() {
    tsdf_ = mapper_->volume()->tsdf();
    weight_ = mapper_->volume()->weight();
    keyframes_ = mapper_->keyframes().size();
    values_ = mapper_->mesh().values;
  }

  // A keyframe candidate 1 s later (past keyframe_interval).
  SurfaceStatus addDepth(const DepthFrame& f, const std::optional<Eigen::Isometry3d>& pose) {
    FrameUse use;
    const SurfaceStatus st = mapper_->addDepthFrame(1.0, f, pose, &use);
    EXPECT_EQ(use, st == SurfaceStatus::kOk ? FrameUse::kKeyframe : FrameUse::kRejected);
    return st;
  }

  void expectUnchanged() {
    EXPECT_EQ(mapper_->volume()->tsdf(), tsdf_);
    EXPECT_EQ(mapper_->volume()->weight(), weight_);
    EXPECT_EQ(mapper_->keyframes().size(), keyframes_);
    const std::vector<float>& v = mapper_->mesh().values;
    ASSERT_EQ(v.size(), values_.size());
    for (std::size_t i = 0; i < v.size(); ++i)
      ASSERT_TRUE(v[i] == values_[i] || (std::isnan(v[i]) && std::isnan(values_[i]))) << i;
  }

  SurfaceSettings s_;
  Scene scene_;
  DepthFrame good_;
  FloatImage image_;
  std::unique_ptr<SurfaceMapper> mapper_;
  std::vector<float> tsdf_, weight_, values_;
  std::size_t keyframes_ = 0;
};

TEST_F(BadInput, AllNaNDepth) {
  DepthFrame f = good_;
  std::fill(f.depth.data.begin(), f.depth.data.end(), kNaN);
  EXPECT_EQ(addDepth(f, Eigen::Isometry3d::Identity()), SurfaceStatus::kNoValidDepth);
  expectUnchanged();
}

TEST_F(BadInput, NaNConfidenceOnValidDepth) {
  DepthFrame f = good_;
  f.weight.width = f.depth.width;
  f.weight.height = f.depth.height;
  f.weight.data.assign(f.depth.data.size(), 1.f);
  f.weight.data[1000] = kNaN;
  EXPECT_EQ(addDepth(f, Eigen::Isometry3d::Identity()), SurfaceStatus::kNonFiniteValue);
  expectUnchanged();
}

TEST_F(BadInput, SizeMismatch) {
  DepthFrame f = good_;
  f.camera.width = 320;
  EXPECT_EQ(addDepth(f, Eigen::Isometry3d::Identity()), SurfaceStatus::kSizeMismatch);
  DepthFrame g = good_;
  g.weight.width = 10;
  g.weight.height = 10;
  g.weight.data.assign(100, 1.f);
  EXPECT_EQ(addDepth(g, Eigen::Isometry3d::Identity()), SurfaceStatus::kSizeMismatch);
  FloatImage small = image_;
  small.width = 320;
  small.data.resize(320 * 480);
  EXPECT_EQ(mapper_->addImagingFrame(small, good_.camera, Eigen::Isometry3d::Identity()).status,
            SurfaceStatus::kSizeMismatch);
  expectUnchanged();
}

TEST_F(BadInput, PoseMissingOrInvalid) {
  EXPECT_EQ(addDepth(good_, std::nullopt), SurfaceStatus::kNoPose);
  Eigen::Isometry3d nan_pose = Eigen::Isometry3d::Identity();
  nan_pose.translation().x() = kNaN;
  EXPECT_EQ(addDepth(good_, nan_pose), SurfaceStatus::kBadPose);
  Eigen::Isometry3d sheared = Eigen::Isometry3d::Identity();
  sheared.linear()(0, 1) = 0.1;
  EXPECT_EQ(addDepth(good_, sheared), SurfaceStatus::kBadPose);
  EXPECT_EQ(mapper_->addImagingFrame(image_, good_.camera, std::nullopt).status, SurfaceStatus::kNoPose);
  EXPECT_EQ(mapper_->addImagingFrame(image_, good_.camera, nan_pose).status, SurfaceStatus::kBadPose);
  expectUnchanged();
}

TEST_F(BadInput, BadIntrinsics) {
  DepthFrame f = good_;
  f.camera.fx = kNaN;
  EXPECT_EQ(addDepth(f, Eigen::Isometry3d::Identity()), SurfaceStatus::kBadCamera);
  PinholeCamera c = good_.camera;
  c.fy = 0;
  EXPECT_EQ(mapper_->addImagingFrame(image_, c, Eigen::Isometry3d::Identity()).status, SurfaceStatus::kBadCamera);
  c = good_.camera;
  c.k2 = kNaN;
  EXPECT_EQ(mapper_->addImagingFrame(image_, c, Eigen::Isometry3d::Identity()).status, SurfaceStatus::kBadCamera);
  // Depth must be rectified: a depth camera with distortion is refused.
  f = good_;
  f.camera.k1 = -0.05;
  EXPECT_EQ(addDepth(f, Eigen::Isometry3d::Identity()), SurfaceStatus::kBadCamera);
  expectUnchanged();
}

TEST_F(BadInput, NaNPixelsOfTheImagingFrameGiveNoValue) {
  FloatImage nan_image = image_;
  std::fill(nan_image.data.begin(), nan_image.data.end(), kNaN);
  const ProjectionResult r = mapper_->addImagingFrame(nan_image, good_.camera, Eigen::Isometry3d::Identity());
  EXPECT_EQ(r.status, SurfaceStatus::kOk);
  EXPECT_EQ(r.voxels_updated, 0u);
  expectUnchanged();
}

TEST(BadSettings, RangesAndRules) {
  SurfaceSettings s;
  EXPECT_EQ(s.validate(), "");
  s.voxel_size = 0;
  EXPECT_NE(s.validate().find("voxel_size must be"), std::string::npos) << s.validate();
  s = SurfaceSettings();
  s.max_depth = 0.05;
  EXPECT_EQ(s.validate(), "max_depth must be > min_depth");
  s = SurfaceSettings();
  s.voxel_size = 0.0001;  // 2000 x 1000 x 400 voxels
  EXPECT_NE(s.validate().find("max_voxels"), std::string::npos);
}

}  // namespace
}  // namespace hapi_surface
