// ROS- and OpenCV-free ORB core shared by the CPU reference and the CUDA path.
// Everything that decides *which* keypoints and *which* descriptor bits come out
// is integer arithmetic (pyramid, smoothing, FAST score, NMS, ranking, moments,
// steered sampling); the only floating-point step, the orientation bin, is a
// double atan2 of integer moments quantised to 12-degree bins. This makes the
// CUDA implementation reproduce the CPU results bit for bit.
#pragma once

#include <cstdint>
#include <vector>

namespace hapi_frontend {

// Plain non-owning 8-bit single-channel image view.
struct ImageView8 {
  const uint8_t* data = nullptr;
  int width = 0, height = 0;
  int stride = 0;  // bytes per row
};

struct OrbParams {
  int n_features = 200;     // total over all levels
  int n_levels = 4;
  float scale_factor = 1.2f;
  int fast_threshold = 20;  // FAST-9 intensity threshold
  int edge = 19;            // border [px] per level where nothing is detected
};

// One keypoint in level coordinates (integers) plus level-0 values.
struct OrbKeypoint {
  int lx = 0, ly = 0;   // position in its pyramid level
  int level = 0;
  int score = 0;        // FAST score (largest threshold for which it is a corner)
  int angle_bin = 0;    // 0..kOrbAngleBins-1, angle = bin * 360 / kOrbAngleBins
  float x = 0.f, y = 0.f, size = 31.f, angle = 0.f;  // level-0 position, patch size, degrees
};

constexpr int kOrbAngleBins = 30;
constexpr int kOrbDescBytes = 32;
constexpr int kOrbHalfPatch = 15;

struct OrbResult {
  std::vector<OrbKeypoint> keypoints;
  std::vector<uint8_t> descriptors;  // keypoints.size() * 32
};

// Size and feature quota of each pyramid level, shared by both paths.
struct OrbLevelPlan {
  std::vector<int> width, height, quota;
  std::vector<float> scale;  // level-to-level-0 factor
};
OrbLevelPlan orb_plan_levels(int width, int height, const OrbParams& p);

// Fixed-point bilinear resampling tables (x or y axis): for dst index i,
// src index idx[i] (and idx[i]+1 clamped) with 8-bit weight w[i] of the second.
void orb_resize_table(int src, int dst, std::vector<int>& idx, std::vector<int>& w);

// The 256 sampling pairs (x1,y1,x2,y2) in [-13,13], deterministic.
const int8_t* orb_pattern();
// Rotated pattern for each angle bin: kOrbAngleBins * 256 * 4 int8 values.
const int8_t* orb_rotated_patterns();
// Half-widths of the circular orientation patch, rows 0..15.
const int* orb_umax();

// Angle bin of the intensity centroid (m10, m01).
int orb_angle_bin(long long m10, long long m01);

// Fills x, y, size, angle of a keypoint from its level values.
void orb_finalize_keypoint(OrbKeypoint& k, const OrbLevelPlan& plan);

// Deterministic ranking key: score descending, then y, then x.
inline uint64_t orb_rank_key(int score, int y, int x) {
  return (static_cast<uint64_t>(255 - score) << 40) | (static_cast<uint64_t>(y) << 20) | static_cast<uint64_t>(x);
}

// CPU reference implementation (single thread).
class OrbCpuCore {
 public:
  explicit OrbCpuCore(const OrbParams& p = OrbParams()) : p_(p) {}
  OrbResult extract(const ImageView8& img);
  const OrbParams& params() const { return p_; }

 private:
  OrbParams p_;
  std::vector<std::vector<uint8_t>> levels_, smooth_;
  std::vector<uint8_t> score_;
  std::vector<uint16_t> tmp_;
};

}  // namespace hapi_frontend
