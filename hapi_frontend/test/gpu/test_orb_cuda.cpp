// GPU ORB == CPU ORB (OrbCpuCore), keypoint by keypoint and bit by bit.
// Frames: procedural rendered-like stereo images (several sizes, parameter
// sets, strides) and, when HAPI_TEST_FRAMES names a folder, its PGM frames
// (e.g. left/right images of the globe bag). Skips without a CUDA device.
#include "hapi_frontend/cuda/orb_cuda.hpp"
#include "hapi_frontend/orb_core.hpp"

#include "frames.hpp"
#include "hapi_test/skip.hpp"
#include "orb_compare.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace hapi_frontend {
namespace {

using gpu_test::compareOrb;
using gpu_test::Frame;
using gpu_test::OrbIdentity;

class OrbCudaIdentity : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string info;
    if (!cudaDeviceAvailable(&info)) HAPI_SKIP_WITHOUT_GPU("no CUDA device: " + info);
    std::printf("[ device ] %s\n", info.c_str());
  }
};

ImageView8 view(const Frame& f) {
  ImageView8 v;
  v.data = f.pixels.data();
  v.width = f.width;
  v.height = f.height;
  v.stride = f.width;
  return v;
}

// Runs both cores on the frames, prints per-run identity, returns the total.
OrbIdentity runFrames(const OrbParams& p, const std::vector<Frame>& frames, const char* label) {
  OrbCpuCore cpu(p);
  OrbCudaCore gpu(p);  // one instance for all frames: buffer reuse is exercised
  OrbIdentity tot;
  for (const Frame& f : frames) {
    const OrbResult a = cpu.extract(view(f));
    const OrbResult b = gpu.extract(view(f));
    const OrbIdentity id = compareOrb(a, b);
    tot.n_ref += id.n_ref;
    tot.n_test += id.n_test;
    tot.identical += id.identical;
    EXPECT_EQ(id.n_ref, id.n_test) << label << " " << f.name;
    EXPECT_GE(id.percent(), 99.0) << label << " " << f.name;
    if (id.identical != id.n_ref && tot.n_ref == id.n_ref)  // details for the first frame only
      std::printf("[ diagnose ] %s %s: %s\n", label, f.name.c_str(), gpu_test::diagnoseOrb(a, b).c_str());
  }
  std::printf("[ identity ] %-34s %4zu frames  %7d CPU kps  %7d GPU kps  %7d identical = %.3f %%\n", label,
              frames.size(), tot.n_ref, tot.n_test, tot.identical, tot.percent());
  return tot;
}

std::vector<Frame> proceduralFrames(int w, int h, int pairs, uint32_t seed0) {
  std::vector<Frame> out;
  for (int k = 0; k < pairs; ++k) {
    Frame l, r;
    gpu_test::renderStereoPair(w, h, seed0 + k, 48, 3, l, r);
    out.push_back(std::move(l));
    out.push_back(std::move(r));
  }
  return out;
}

TEST_F(OrbCudaIdentity, ProceduralDefaultParams) {
  const std::vector<Frame> frames = proceduralFrames(640, 480, 10, 100);
  const OrbIdentity t = runFrames(OrbParams(), frames, "640x480 default (N=200, 4 levels)");
  // Not vacuous: the quota is filled on these textured frames.
  EXPECT_GE(t.n_ref, static_cast<int>(frames.size()) * 190);
  EXPECT_EQ(t.identical, t.n_ref);
}

TEST_F(OrbCudaIdentity, ProceduralParameterSweep) {
  struct Case {
    int w, h, n, levels, thr;
    float scale;
    int edge;
  };
  const Case cases[] = {{640, 480, 1000, 8, 20, 1.2f, 19}, {752, 480, 500, 4, 10, 1.2f, 19},
                        {641, 479, 300, 5, 30, 1.3f, 25},  {320, 240, 200, 3, 7, 1.5f, 19},
                        {1280, 720, 2000, 8, 12, 1.2f, 19}, {640, 480, 200, 1, 20, 1.2f, 19}};
  int k = 0;
  for (const Case& c : cases) {
    OrbParams p;
    p.n_features = c.n;
    p.n_levels = c.levels;
    p.fast_threshold = c.thr;
    p.scale_factor = c.scale;
    p.edge = c.edge;
    char label[96];
    std::snprintf(label, sizeof(label), "%dx%d N=%d L=%d t=%d s=%.1f e=%d", c.w, c.h, c.n, c.levels, c.thr, c.scale, c.edge);
    const std::vector<Frame> frames = proceduralFrames(c.w, c.h, 3, 1000 + 10 * k++);
    const OrbIdentity t = runFrames(p, frames, label);
    EXPECT_GT(t.n_ref, 0) << label;
    EXPECT_EQ(t.identical, t.n_ref) << label;
  }
}

TEST_F(OrbCudaIdentity, StridedViewAndSizeChanges) {
  // A padded row stride and alternating sizes on one instance (re-allocation).
  OrbParams p;
  OrbCpuCore cpu(p);
  OrbCudaCore gpu(p);
  for (int k = 0; k < 4; ++k) {
    const int w = (k % 2) ? 512 : 640, h = (k % 2) ? 384 : 480, stride = w + 37;
    Frame l, r;
    gpu_test::renderStereoPair(w, h, 77 + k, 32, 2, l, r);
    std::vector<uint8_t> padded(static_cast<size_t>(stride) * h, 0xAB);
    for (int y = 0; y < h; ++y)
      std::copy(l.pixels.begin() + static_cast<size_t>(y) * w, l.pixels.begin() + static_cast<size_t>(y + 1) * w,
                padded.begin() + static_cast<size_t>(y) * stride);
    ImageView8 v{padded.data(), w, h, stride};
    const OrbIdentity id = compareOrb(cpu.extract(v), gpu.extract(v));
    EXPECT_GT(id.n_ref, 100);
    EXPECT_EQ(id.identical, id.n_ref);
    EXPECT_EQ(id.n_test, id.n_ref);
  }
}

TEST_F(OrbCudaIdentity, DegenerateInputs) {
  OrbParams p;
  OrbCudaCore gpu(p);
  OrbCpuCore cpu(p);
  // Smaller than the detection border on every level: nothing, like the CPU.
  std::vector<uint8_t> tiny(30 * 30, 128);
  ImageView8 v{tiny.data(), 30, 30, 30};
  EXPECT_TRUE(gpu.extract(v).keypoints.empty());
  EXPECT_TRUE(cpu.extract(v).keypoints.empty());
  // Flat image: no corners.
  std::vector<uint8_t> flat(640 * 480, 90);
  ImageView8 f{flat.data(), 640, 480, 640};
  EXPECT_TRUE(gpu.extract(f).keypoints.empty());
  // Null view.
  EXPECT_TRUE(gpu.extract(ImageView8()).keypoints.empty());
  // Zero features requested.
  OrbParams p0;
  p0.n_features = 0;
  OrbCudaCore gpu0(p0);
  Frame l, r;
  gpu_test::renderStereoPair(640, 480, 5, 32, 2, l, r);
  EXPECT_TRUE(gpu0.extract(view(l)).keypoints.empty());
  // Invalid parameters are rejected at construction.
  OrbParams bad;
  bad.scale_factor = 1.f;
  EXPECT_THROW(OrbCudaCore{bad}, std::invalid_argument);
}

// Frames carried to the GPU machine (e.g. rendered globe-bag images as PGM).
TEST_F(OrbCudaIdentity, FramesFromDirectory) {
  const char* dir = std::getenv("HAPI_TEST_FRAMES");
  if (!dir || !*dir) GTEST_SKIP() << "HAPI_TEST_FRAMES not set";
  const std::vector<std::string> paths = gpu_test::listPgm(dir);
  ASSERT_FALSE(paths.empty()) << "no .pgm files in " << dir;
  std::vector<Frame> frames;
  for (const std::string& path : paths) {
    Frame f;
    std::string err;
    ASSERT_TRUE(gpu_test::loadPgm(path, f, &err)) << err;
    frames.push_back(std::move(f));
  }
  const OrbIdentity t = runFrames(OrbParams(), frames, "HAPI_TEST_FRAMES default params");
  EXPECT_GT(t.n_ref, 0);
  EXPECT_GE(t.percent(), 99.0);
}

}  // namespace
}  // namespace hapi_frontend
