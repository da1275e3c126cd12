// GPU stereo matcher == stereo_match_core (CPU), match for match, on
// synthetic descriptor sets built to stress every rule (ties, ratio,
// max Hamming, cross-check, epipolar/disparity limits, padded descriptor
// lengths) and on ORB features of procedural stereo pairs.
#include "hapi_frontend/cuda/orb_cuda.hpp"
#include "hapi_frontend/cuda/stereo_match_cuda.hpp"
#include "hapi_frontend/orb_core.hpp"
#include "hapi_frontend/stereo_match_core.hpp"

#include "frames.hpp"
#include "hapi_test/skip.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

namespace hapi_frontend {
namespace {

class StereoMatchCudaIdentity : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string info;
    if (!cudaDeviceAvailable(&info)) HAPI_SKIP_WITHOUT_GPU("no CUDA device: " + info);
  }
};

struct Rng {
  uint64_t s;
  explicit Rng(uint64_t seed) : s(seed ^ 0x9E3779B97F4A7C15ULL) {}
  uint32_t next() {
    s = s * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<uint32_t>(s >> 33);
  }
  double uni() { return next() / 4294967296.0; }
};

struct Sets {
  int bytes = 32;
  std::vector<uint8_t> dl, dr;
  std::vector<float> pl, pr;
  int nl() const { return static_cast<int>(pl.size() / 2); }
  int nr() const { return static_cast<int>(pr.size() / 2); }
};

// n_true planted pairs (descriptor with `flips` random bit flips, disparity
// 1..80, y jitter), n_extra unrelated points on each side, few image rows so
// many pairs share an epipolar band, and exact duplicates for tie-breaking.
Sets makeSets(uint64_t seed, int n_true, int n_extra, int bytes, int flips) {
  Rng r(seed);
  Sets s;
  s.bytes = bytes;
  auto randDesc = [&](std::vector<uint8_t>& d) {
    for (int k = 0; k < bytes; ++k) d.push_back(static_cast<uint8_t>(r.next()));
  };
  for (int k = 0; k < n_true; ++k) {
    const float x = static_cast<float>(100 + 500 * r.uni()), y = static_cast<float>(20 * (r.next() % 12) + 0.25 * r.uni());
    s.pl.push_back(x);
    s.pl.push_back(y);
    randDesc(s.dl);
  }
  for (int k = 0; k < n_extra; ++k) {
    s.pl.push_back(static_cast<float>(640 * r.uni()));
    s.pl.push_back(static_cast<float>(20 * (r.next() % 12) + 3 * r.uni()));
    randDesc(s.dl);
  }
  // Right side in a shuffled order.
  std::vector<int> order(n_true + n_extra);
  for (size_t k = 0; k < order.size(); ++k) order[k] = static_cast<int>(k);
  for (size_t k = order.size(); k > 1; --k) std::swap(order[k - 1], order[r.next() % k]);
  for (int idx : order) {
    if (idx < n_true) {
      s.pr.push_back(s.pl[2 * idx] - static_cast<float>(1 + 79 * r.uni()));
      s.pr.push_back(s.pl[2 * idx + 1] + static_cast<float>(1.5 * (r.uni() - 0.5)));
      std::vector<uint8_t> d(s.dl.begin() + static_cast<size_t>(idx) * bytes, s.dl.begin() + static_cast<size_t>(idx + 1) * bytes);
      for (int f = 0; f < flips; ++f) {
        const int bit = r.next() % (bytes * 8);
        d[bit / 8] ^= static_cast<uint8_t>(1u << (bit % 8));
      }
      s.dr.insert(s.dr.end(), d.begin(), d.end());
    } else {
      s.pr.push_back(static_cast<float>(640 * r.uni()));
      s.pr.push_back(static_cast<float>(20 * (r.next() % 12) + 3 * r.uni()));
      randDesc(s.dr);
    }
  }
  // Exact duplicates on both sides (identical distance -> index tie-breaks).
  const int nr = s.nr(), nl = s.nl();
  for (int k = 0; k < std::min(nr, 20); ++k) {
    const int j = r.next() % nr;
    s.pr.push_back(s.pr[2 * j] + (k % 2 ? 0.f : 0.5f));
    s.pr.push_back(s.pr[2 * j + 1]);
    s.dr.insert(s.dr.end(), s.dr.begin() + static_cast<size_t>(j) * bytes, s.dr.begin() + static_cast<size_t>(j + 1) * bytes);
  }
  for (int k = 0; k < std::min(nl, 20); ++k) {
    const int i = r.next() % nl;
    s.pl.push_back(s.pl[2 * i]);
    s.pl.push_back(s.pl[2 * i + 1]);
    s.dl.insert(s.dl.end(), s.dl.begin() + static_cast<size_t>(i) * bytes, s.dl.begin() + static_cast<size_t>(i + 1) * bytes);
  }
  return s;
}

bool equal(const std::vector<MatchCoreResult>& a, const std::vector<MatchCoreResult>& b) {
  if (a.size() != b.size()) return false;
  for (size_t k = 0; k < a.size(); ++k)
    if (a[k].left != b[k].left || a[k].right != b[k].right || a[k].distance != b[k].distance) return false;
  return true;
}

// Rectified rig: l_r = (0, -1, y_l), i.e. e = y_l - y_r.
const double kRectF[9] = {0, 0, 0, 0, 0, -1, 0, 1, 0};

TEST_F(StereoMatchCudaIdentity, SyntheticSetsAllRules) {
  // A slightly rotated, scaled general F: exercises the double arithmetic.
  const double th = 0.01;
  const double genF[9] = {0, -std::sin(th) * 1e-3, 0.02 * std::sin(th), std::sin(th) * 1e-3, 0, -std::cos(th),
                          -0.02 * std::sin(th), std::cos(th), 0.3};
  StereoMatchCuda gpu;
  int cases = 0, total_matches = 0;
  for (int bytes : {32, 61, 8}) {
    for (int flips : {4, 20, 60}) {
      for (uint64_t seed : {1u, 2u, 3u}) {
        const Sets s = makeSets(seed * 31 + bytes + flips, 150 + 50 * static_cast<int>(seed), 120, bytes, flips);
        for (const double* F : {kRectF, genF}) {
          for (int variant = 0; variant < 4; ++variant) {
            MatchCoreParams p;
            p.cross_check = variant % 2 == 0;
            p.ratio = variant < 2 ? 0.8 : 1.0;
            p.max_hamming = variant == 3 ? bytes * 8 : bytes * 2;
            p.max_epipolar_px = variant == 1 ? 0.3 : 2.0;
            const auto ref = stereo_match_core(s.dl.data(), s.pl.data(), s.nl(), s.dr.data(), s.pr.data(), s.nr(),
                                               bytes, F, p);
            const auto got = gpu.match(s.dl.data(), s.pl.data(), s.nl(), s.dr.data(), s.pr.data(), s.nr(), bytes, F, p);
            EXPECT_TRUE(equal(ref, got)) << "bytes " << bytes << " flips " << flips << " seed " << seed << " variant "
                                         << variant << ": CPU " << ref.size() << " GPU " << got.size();
            ++cases;
            total_matches += static_cast<int>(ref.size());
          }
        }
      }
    }
  }
  std::printf("[ matcher ] %d synthetic cases, %d CPU matches, GPU identical in every case unless reported above\n",
              cases, total_matches);
  EXPECT_GT(total_matches, 1000);  // the sets do produce matches
}

TEST_F(StereoMatchCudaIdentity, EmptyAndSingle) {
  StereoMatchCuda gpu;
  MatchCoreParams p;
  std::vector<uint8_t> d(32, 0x5A);
  std::vector<float> pl{100.f, 50.f}, pr{90.f, 50.f};
  EXPECT_TRUE(gpu.match(d.data(), pl.data(), 0, d.data(), pr.data(), 1, 32, kRectF, p).empty());
  EXPECT_TRUE(gpu.match(d.data(), pl.data(), 1, d.data(), pr.data(), 0, 32, kRectF, p).empty());
  const auto one = gpu.match(d.data(), pl.data(), 1, d.data(), pr.data(), 1, 32, kRectF, p);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0].left, 0);
  EXPECT_EQ(one[0].right, 0);
  EXPECT_EQ(one[0].distance, 0);
  // Negative disparity: rejected by both.
  std::vector<float> pr2{110.f, 50.f};
  EXPECT_TRUE(gpu.match(d.data(), pl.data(), 1, d.data(), pr2.data(), 1, 32, kRectF, p).empty());
  EXPECT_TRUE(stereo_match_core(d.data(), pl.data(), 1, d.data(), pr2.data(), 1, 32, kRectF, p).empty());
}

TEST_F(StereoMatchCudaIdentity, OrbFeaturesOfStereoPairs) {
  OrbParams op;
  op.n_features = 1000;
  OrbCpuCore orb(op);
  StereoMatchCuda gpu;
  MatchCoreParams p;
  int total = 0;
  for (uint32_t seed = 0; seed < 6; ++seed) {
    gpu_test::Frame l, r;
    gpu_test::renderStereoPair(640, 480, 500 + seed, 48, 2, l, r);
    const OrbResult a = orb.extract({l.pixels.data(), l.width, l.height, l.width});
    const OrbResult b = orb.extract({r.pixels.data(), r.width, r.height, r.width});
    std::vector<float> pa, pb;
    for (const auto& k : a.keypoints) pa.insert(pa.end(), {k.x, k.y});
    for (const auto& k : b.keypoints) pb.insert(pb.end(), {k.x, k.y});
    const int na = static_cast<int>(a.keypoints.size()), nb = static_cast<int>(b.keypoints.size());
    const auto ref = stereo_match_core(a.descriptors.data(), pa.data(), na, b.descriptors.data(), pb.data(), nb,
                                       kOrbDescBytes, kRectF, p);
    const auto got = gpu.match(a.descriptors.data(), pa.data(), na, b.descriptors.data(), pb.data(), nb,
                               kOrbDescBytes, kRectF, p);
    EXPECT_TRUE(equal(ref, got)) << "pair " << seed << ": CPU " << ref.size() << " GPU " << got.size();
    total += static_cast<int>(ref.size());
  }
  EXPECT_GT(total, 6 * 50);  // textured pairs give many stereo matches
}

}  // namespace
}  // namespace hapi_frontend
