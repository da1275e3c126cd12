// Stereo matcher on synthetic pairs: known correspondences, epipolar and
// disparity rejection, ratio test, cross-check and the documented
// tie-breaking (stereo_match_core.hpp) that the GPU matcher must reproduce.
#include "hapi_frontend/cpu_stereo_matcher.hpp"
#include "hapi_frontend/stereo_match_core.hpp"

#include <gtest/gtest.h>

#include <random>

using namespace hapi_frontend;

namespace {
// Rectified rig: epipolar lines are image rows; F ~ [e]x with e = (1,0,0).
Eigen::Matrix3d rectifiedF() {
  Eigen::Matrix3d F;
  F << 0, 0, 0, 0, 0, -1, 0, 1, 0;
  return F;
}

struct Pair {
  FeatureSet left, right;
  std::vector<Eigen::Vector2d> ul, ur;
  std::vector<int> truth;  // truth[i] = right index of left i, -1 if none
};

void addKeypoint(FeatureSet* fs, std::vector<Eigen::Vector2d>* pts, const Eigen::Vector2d& p, const uint8_t* d) {
  Feature f;
  f.x = static_cast<float>(p.x());
  f.y = static_cast<float>(p.y());
  fs->keypoints.push_back(f);
  pts->push_back(p);
  cv::Mat row(1, 32, CV_8U);
  std::memcpy(row.data, d, 32);
  fs->descriptors.push_back(row);
}

// n true correspondences (right = left shifted by a disparity, a few bits
// flipped, small y noise) plus unmatched distractors on both sides, shuffled.
Pair makePair(int n, int distractors, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> ux(100, 600), uy(20, 460), ud(2, 80), uyn(-0.7, 0.7);
  std::uniform_int_distribution<int> byte(0, 255), bit(0, 255);
  Pair p;
  struct R { Eigen::Vector2d pt; std::array<uint8_t, 32> d; int left; };
  std::vector<R> rights;
  for (int i = 0; i < n; ++i) {
    std::array<uint8_t, 32> d;
    for (auto& b : d) b = static_cast<uint8_t>(byte(rng));
    const Eigen::Vector2d pl(ux(rng), uy(rng));
    addKeypoint(&p.left, &p.ul, pl, d.data());
    std::array<uint8_t, 32> dr = d;
    for (int k = 0; k < 8; ++k) { const int b = bit(rng); dr[b / 8] ^= static_cast<uint8_t>(1u << (b % 8)); }
    rights.push_back({Eigen::Vector2d(pl.x() - ud(rng), pl.y() + uyn(rng)), dr, i});
  }
  for (int i = 0; i < distractors; ++i) {
    std::array<uint8_t, 32> d;
    for (auto& b : d) b = static_cast<uint8_t>(byte(rng));
    addKeypoint(&p.left, &p.ul, Eigen::Vector2d(ux(rng), uy(rng)), d.data());
    for (auto& b : d) b = static_cast<uint8_t>(byte(rng));
    rights.push_back({Eigen::Vector2d(ux(rng), uy(rng)), d, -1});
  }
  std::shuffle(rights.begin(), rights.end(), rng);
  p.truth.assign(p.left.keypoints.size(), -1);
  for (size_t j = 0; j < rights.size(); ++j) {
    addKeypoint(&p.right, &p.ur, rights[j].pt, rights[j].d.data());
    if (rights[j].left >= 0) p.truth[rights[j].left] = static_cast<int>(j);
  }
  return p;
}
}  // namespace

TEST(StereoMatcher, RecoversKnownCorrespondences) {
  const Pair p = makePair(300, 300, 1);
  CpuStereoMatcher m;
  StereoMatchParams sp;
  const auto matches = m.match(p.left, p.ul, p.right, p.ur, rectifiedF(), sp);
  int correct = 0;
  for (const auto& mt : matches) {
    EXPECT_EQ(mt.right, p.truth[mt.left]) << "left " << mt.left;
    correct += mt.right == p.truth[mt.left];
    EXPECT_EQ(mt.distance, hamming_distance(p.left.descriptors.ptr(mt.left), p.right.descriptors.ptr(mt.right), 32));
  }
  EXPECT_GE(correct, 295);  // 8 flipped bits vs ~128 for random descriptors
  for (size_t k = 1; k < matches.size(); ++k) EXPECT_LT(matches[k - 1].left, matches[k].left);
}

TEST(StereoMatcher, GeometryRejection) {
  Pair p = makePair(50, 0, 2);
  CpuStereoMatcher m;
  StereoMatchParams sp;
  ASSERT_EQ(m.match(p.left, p.ul, p.right, p.ur, rectifiedF(), sp).size(), 50u);
  // Off the epipolar line by 3 px (> max_epipolar_px = 2): no match.
  Pair off = p;
  for (auto& u : off.ur) u.y() += 3.0;
  EXPECT_TRUE(m.match(off.left, off.ul, off.right, off.ur, rectifiedF(), sp).empty());
  // Negative disparity (right point to the right of the left one): no match.
  Pair neg = p;
  for (size_t i = 0; i < neg.ul.size(); ++i) neg.ur[p.truth[i]].x() = neg.ul[i].x() + 5.0;
  EXPECT_TRUE(m.match(neg.left, neg.ul, neg.right, neg.ur, rectifiedF(), sp).empty());
  // Disparity above the maximum.
  sp.max_disparity = 1.5;
  EXPECT_TRUE(m.match(p.left, p.ul, p.right, p.ur, rectifiedF(), sp).empty());
}

TEST(StereoMatcher, RatioTestAndHammingBound) {
  // One left keypoint, two right candidates on its row at distances 10 and 12.
  const uint8_t zero[32] = {0};
  uint8_t d10[32] = {0}, d12[32] = {0};
  d10[0] = 0xFF; d10[1] = 0x03;   // 10 bits
  d12[0] = 0xFF; d12[1] = 0x0F;   // 12 bits
  FeatureSet L, R;
  std::vector<Eigen::Vector2d> ul, ur;
  addKeypoint(&L, &ul, {300, 200}, zero);
  addKeypoint(&R, &ur, {280, 200}, d12);
  addKeypoint(&R, &ur, {250, 200}, d10);
  CpuStereoMatcher m;
  StereoMatchParams sp;
  sp.ratio = 0.8;  // 10 < 0.8 * 12 = 9.6 fails
  EXPECT_TRUE(m.match(L, ul, R, ur, rectifiedF(), sp).empty());
  sp.ratio = 0.9;  // 10 < 10.8 passes
  auto r = m.match(L, ul, R, ur, rectifiedF(), sp);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].right, 1);
  EXPECT_EQ(r[0].distance, 10);
  sp.max_hamming = 9;
  EXPECT_TRUE(m.match(L, ul, R, ur, rectifiedF(), sp).empty());
  // Equal best and second distances are ambiguous for any ratio <= 1.
  sp.max_hamming = 64;
  sp.ratio = 1.0;
  R.descriptors.row(0).setTo(0);
  R.descriptors.row(1).setTo(0);
  EXPECT_TRUE(m.match(L, ul, R, ur, rectifiedF(), sp).empty());
}

TEST(StereoMatcher, CrossCheckAndTieBreaking) {
  // Two left keypoints on one row both prefer the single right keypoint.
  uint8_t a[32] = {0}, b[32] = {0}, r0[32] = {0};
  b[5] = 0x01;  // left 1 is 1 bit away from the right keypoint, left 0 is 0 bits
  FeatureSet L, R;
  std::vector<Eigen::Vector2d> ul, ur;
  addKeypoint(&L, &ul, {300, 100}, b);
  addKeypoint(&L, &ul, {310, 100}, a);
  addKeypoint(&R, &ur, {250, 100}, r0);
  CpuStereoMatcher m;
  StereoMatchParams sp;
  auto r = m.match(L, ul, R, ur, rectifiedF(), sp);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].left, 1);  // the mutual best
  sp.cross_check = false;
  EXPECT_EQ(m.match(L, ul, R, ur, rectifiedF(), sp).size(), 2u);
  // Right-side tie (both lefts at distance 0): the SMALLEST left index wins.
  std::memcpy(L.descriptors.ptr(0), a, 32);
  sp.cross_check = true;
  r = m.match(L, ul, R, ur, rectifiedF(), sp);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].left, 0);
}

TEST(StereoMatcher, MalformedInputGivesNoMatches) {
  Pair p = makePair(10, 0, 3);
  CpuStereoMatcher m;
  StereoMatchParams sp;
  std::vector<Eigen::Vector2d> short_ul(p.ul.begin(), p.ul.begin() + 5);
  EXPECT_TRUE(m.match(p.left, short_ul, p.right, p.ur, rectifiedF(), sp).empty());
  FeatureSet empty;
  EXPECT_TRUE(m.match(empty, {}, p.right, p.ur, rectifiedF(), sp).empty());
}
