// Random but well-posed inputs for the backend tests (CPU reference tests and
// the CPU-vs-GPU parity tests draw from the same generator).
#pragma once

#include "hapi_eskf/covariance/covariance_backend.hpp"
#include "hapi_eskf/random_draw.hpp"
#include "hapi_eskf/so3.hpp"
#include "hapi_eskf/types.hpp"

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

namespace hapi_eskf {
namespace testing_random {

struct Rng {
  std::mt19937 gen;
  explicit Rng(unsigned seed) : gen(seed) {}
  double n(double s = 1.0) { return std::normal_distribution<double>(0, s)(gen); }
  int i(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(gen); }
  Vec3 v3(double s = 1.0) {
    // A fresh distribution per draw, as n() (a shared one would hand out the
    // cached second value of its pairs: another sample).
    auto fresh = [s](std::mt19937& g) { return std::normal_distribution<double>(0, s)(g); };
    return drawVec3(fresh, gen);
  }
  Mat3 spd3(double scale) {
    Mat3 A;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) A(r, c) = n();
    return scale * (A * A.transpose() + 0.5 * Mat3::Identity());
  }
  // A well-conditioned P x P covariance (a pose block of any model).
  PoseMat spd(int P, double scale) {
    PoseMat A(P, P);
    for (int r = 0; r < P; ++r)
      for (int c = 0; c < P; ++c) A(r, c) = n();
    return scale * (A * A.transpose() / static_cast<double>(P) + 0.1 * PoseMat::Identity(P, P));
  }
  Mat12 spd12(double scale) { return spd(kCameraMotionDim, scale); }
  std::vector<uint8_t> bytes(std::size_t len) {
    std::vector<uint8_t> b(len);
    for (auto& x : b) x = static_cast<uint8_t>(i(0, 255));
    return b;
  }
  // `count` distinct slots of [0, K), in random order.
  std::vector<int> distinct(int K, int count) {
    std::vector<int> all(K);
    for (int k = 0; k < K; ++k) all[k] = k;
    std::shuffle(all.begin(), all.end(), gen);
    all.resize(std::min(count, K));
    return all;
  }
};

// Measurement block shaped like docs/DESIGN.md "Measurement": -R^T, [h]x, R^T.
inline MeasurementBlock randomBlock(Rng& r, int slot, double noise) {
  MeasurementBlock b;
  b.slot = slot;
  const Mat3 Rt = expSO3(r.v3(1.0)).transpose();
  b.H_pose << -Rt, skew(r.v3(3.0));
  b.H_landmark = Rt;
  b.R = r.spd3(noise);
  b.innovation = r.v3(0.05);
  return b;
}

// New landmark shaped like docs/DESIGN.md "New landmark": m = p + R z.
inline NewLandmarkBlock randomNewBlock(Rng& r, const std::vector<uint8_t>& d) {
  NewLandmarkBlock b;
  const Mat3 R = expSO3(r.v3(1.0));
  b.G_pose << Mat3::Identity(), -R * skew(r.v3(3.0));
  b.G_z = R;
  b.Cz = r.spd3(0.01);
  b.descriptor = d.data();
  return b;
}

}  // namespace testing_random
}  // namespace hapi_eskf
