// Test/benchmark frames for the GPU machine, which has neither OpenCV nor
// hapi_sim: deterministic procedural "rendered-like" stereo pairs (layered
// textured shapes, blur, sensor noise) and 8-bit PGM frames from a folder.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace hapi_frontend {
namespace gpu_test {

struct Frame {
  int width = 0, height = 0;
  std::vector<uint8_t> pixels;  // row-major, stride = width
  std::string name;
};

// One stereo pair of a random scene (seed): textured discs/rectangles on a
// shaded background, each shape at its own disparity (max_disparity px), 3x3
// binomial blur twice, then +-noise grey levels of uniform noise. The right
// image sees every shape shifted left by its disparity (rectified rig).
void renderStereoPair(int width, int height, uint32_t seed, int max_disparity, int noise, Frame& left, Frame& right);

// Reads a binary 8-bit PGM (P5, maxval <= 255); false with `err` set otherwise.
bool loadPgm(const std::string& path, Frame& f, std::string* err);

// Sorted *.pgm paths in `dir` (empty if it does not exist).
std::vector<std::string> listPgm(const std::string& dir);

}  // namespace gpu_test
}  // namespace hapi_frontend
