// Stereo matcher on synthetic pairs: known correspondences, epipolar and
// disparity rejection, ratio test, cross-check and the documented
// tie-breaking (stereo_match_core.hpp) that the GPU matcher must reproduce.
#include "hapi_frontend/cpu_stereo_matcher.hpp"
#include "hapi_frontend/stereo_match_core.hpp"

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <Eigen/LU>

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

// The documented contract, written as the naive O(n_l * n_r) loop over j in
// ascending order. stereo_match_core (y-band search, order-independent
// rules) must return exactly this -- as must the CUDA matcher.
namespace {
std::vector<MatchCoreResult> referenceMatch(const std::vector<uint8_t>& dl, const std::vector<float>& pl,
                                            const std::vector<uint8_t>& dr, const std::vector<float>& pr, int bytes,
                                            const double F[9], const MatchCoreParams& p) {
  const int nl = static_cast<int>(pl.size() / 2), nr = static_cast<int>(pr.size() / 2);
  const int kInf = 1 << 30;
  std::vector<int> rb(nr, kInf), ri(nr, -1);
  std::vector<MatchCoreResult> pre;
  for (int i = 0; i < nl; ++i) {
    const double x = pl[2 * i], y = pl[2 * i + 1];
    const double l0 = F[0] * x + F[1] * y + F[2], l1 = F[3] * x + F[4] * y + F[5], l2 = F[6] * x + F[7] * y + F[8];
    int b = kInf, s = kInf, bj = -1;
    for (int j = 0; j < nr; ++j) {
      const double disp = x - pr[2 * j];
      const double e = l0 * pr[2 * j] + l1 * pr[2 * j + 1] + l2;
      if (disp < p.min_disparity || disp > p.max_disparity || e * e > p.max_epipolar_px * p.max_epipolar_px * (l0 * l0 + l1 * l1))
        continue;
      const int d = hamming_distance(&dl[i * bytes], &dr[j * bytes], bytes);
      if (d < b) { s = b; b = d; bj = j; } else if (d < s) { s = d; }
      if (d < rb[j]) { rb[j] = d; ri[j] = i; }
    }
    if (bj >= 0 && b <= p.max_hamming && (s == kInf || double(b) < p.ratio * double(s))) pre.push_back({i, bj, b});
  }
  std::vector<MatchCoreResult> out;
  for (const auto& m : pre)
    if (!p.cross_check || ri[m.right] == m.left) out.push_back(m);
  return out;
}
}  // namespace

TEST(StereoMatchCore, EqualsNaiveReferenceIncludingTies) {
  std::mt19937 rng(17);
  for (int trial = 0; trial < 12; ++trial) {
    const int nl = 400, nr = 420, bytes = trial % 3 == 0 ? 61 : 32;
    std::uniform_real_distribution<float> X(0, 640), Y(0, 480);
    // Few distinct descriptors (4 random bits) -> many exact distance ties.
    std::uniform_int_distribution<int> B(0, 15);
    std::vector<uint8_t> dl(nl * bytes, 0), dr(nr * bytes, 0);
    for (auto& v : dl) v = static_cast<uint8_t>(B(rng) == 0 ? 1 : 0);
    for (auto& v : dr) v = static_cast<uint8_t>(B(rng) == 0 ? 1 : 0);
    std::vector<float> pl(2 * nl), pr(2 * nr);
    for (int i = 0; i < nl; ++i) { pl[2 * i] = X(rng); pl[2 * i + 1] = std::round(Y(rng) / 4) * 4; }
    for (int j = 0; j < nr; ++j) { pr[2 * j] = X(rng); pr[2 * j + 1] = std::round(Y(rng) / 4) * 4 + (j % 3) * 0.5f; }
    // Rectified, slightly rotated, and (trial 5) vertical-baseline geometry.
    const Eigen::Matrix3d E = trial == 5 ? (Eigen::Matrix3d() << 0, 0, 1, 0, 0, 0, -1, 0, 0).finished()
                                         : (Eigen::Matrix3d() << 0, 0, 0, 0, 0, -1, 0, 1, 0).finished();
    Eigen::Matrix3d K;
    K << 500, 0, 320, 0, 500, 240, 0, 0, 1;
    const Eigen::Matrix3d R = Eigen::AngleAxisd(0.002 * trial, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const Eigen::Matrix3d F = K.inverse().transpose() * E * R * K.inverse();
    double f[9];
    for (int k = 0; k < 9; ++k) f[k] = F(k / 3, k % 3) / F.norm();
    MatchCoreParams p;
    p.max_epipolar_px = 1.0 + 0.5 * (trial % 4);
    p.min_disparity = trial == 5 ? -640 : 0.5;
    p.cross_check = trial % 2 == 0;
    p.ratio = trial % 4 == 1 ? 1.0 : 0.8;
    p.max_hamming = 64;
    const auto got = stereo_match_core(dl.data(), pl.data(), nl, dr.data(), pr.data(), nr, bytes, f, p);
    const auto want = referenceMatch(dl, pl, dr, pr, bytes, f, p);
    ASSERT_EQ(got.size(), want.size()) << "trial " << trial;
    for (size_t k = 0; k < got.size(); ++k) {
      EXPECT_EQ(got[k].left, want[k].left);
      EXPECT_EQ(got[k].right, want[k].right);
      EXPECT_EQ(got[k].distance, want[k].distance);
    }
    if (trial == 0) EXPECT_GT(got.size(), 5u) << "test data too sparse to be meaningful";
  }
}
