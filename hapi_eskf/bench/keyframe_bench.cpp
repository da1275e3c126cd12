// Relocalisation in a large keyframe map (docs/DESIGN.md "Keyframes"):
// 10^4 landmarks with random 32-byte descriptors on a 1.45 m square
// surface, 10^3 keyframes 25 cm above it on a 32 x 32 grid (about 300 points
// each, 16 descriptor bits flipped per view), then queries with no pose hint:
// cameras near a random keyframe (up to 1.5 cm and 0.2 rad off, other noise
// and bits) and cameras over a surface never mapped (other descriptors).
// Prints the time of KeyframeRelocaliser::place per query (p50 / p99 /
// max), how many were placed and their pose errors. Asserts nothing.
//   hapi_eskf_keyframe_bench [queries=100] [landmarks=10000] [grid=32]
#include "hapi_eskf/keyframes/keyframe_relocaliser.hpp"

#include "keyframe_scene.hpp"

#include <hapi_nodelet_kit/sample_quantiles.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

}  // namespace

int main(int argc, char** argv) {
  using namespace hapi_eskf;
  const int queries = argc > 1 ? std::atoi(argv[1]) : 100;
  const int n_landmarks = argc > 2 ? std::atoi(argv[2]) : 10000;
  const int grid = argc > 3 ? std::atoi(argv[3]) : 32;
  const double side = 1.45 * std::sqrt(n_landmarks / 1e4);
  const test::KeyframeScene scene = test::makeKeyframeScene(n_landmarks, side, 7);
  std::mt19937 g(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  KeyframeRelocaliser reloc;
  std::size_t points = 0;
  auto t0 = Clock::now();
  const double span = side - 0.3;  // keep each view over the surface
  for (int i = 0; i < grid; ++i)
    for (int j = 0; j < grid; ++j) {
      const Eigen::Isometry3d T = test::cameraAbove(-0.5 * span + span * i / (grid - 1),
                                                    -0.5 * span + span * j / (grid - 1), 0.25, M_PI * u(g));
      const StereoFrame f = test::viewOf(scene, T, g, 16);
      points += f.measurements.size();
      reloc.add(keyframeOf(reloc.keyframes().size() + 1, f, T, Mat6::Identity() * 1e-6));
    }
  const double t_build = msSince(t0);
  std::printf("map: %d landmarks over %.2f m x %.2f m, %zu keyframes (%.0f points each on average), built in %.0f ms\n",
              n_landmarks, side, side, reloc.keyframes().size(), double(points) / reloc.keyframes().size(), t_build);

  const test::KeyframeScene other = test::makeKeyframeScene(n_landmarks, side, 99);
  for (int unmapped = 0; unmapped < 2; ++unmapped) {
    std::vector<double> ms;
    std::vector<double> err_mm, err_deg;
    int placed = 0;
    for (int q = 0; q < queries; ++q) {
      const Keyframe& near = reloc.keyframes()[static_cast<std::size_t>(g() % reloc.keyframes().size())];
      Eigen::Isometry3d T = near.T_map_cam;
      T.translation() += Vec3(0.015 * u(g), 0.015 * u(g), 0.01 * u(g));
      T.linear() = T.linear() * Eigen::AngleAxisd(0.2 * u(g), Vec3::UnitZ()).toRotationMatrix();
      const StereoFrame f = test::viewOf(unmapped ? other : scene, T, g, 16);
      t0 = Clock::now();
      const std::optional<KeyframeFit> fit = reloc.place(f);
      ms.push_back(msSince(t0));
      if (!fit) continue;
      ++placed;
      const Eigen::Isometry3d E = T.inverse() * fit->T_map_cam;
      err_mm.push_back(1e3 * E.translation().norm());
      err_deg.push_back(Eigen::AngleAxisd(E.linear()).angle() * 180.0 / M_PI);
    }
    std::printf("%s: %d queries, placed %d; place() [ms] p50 / p99 / max %s", unmapped ? "unmapped surface" : "mapped",
                queries, placed, hapi_nodelet_kit::formatP50P99Max(ms, 2).c_str());
    if (!err_mm.empty())
      std::printf("; pose error [mm] %s, [deg] %s", hapi_nodelet_kit::formatP50P99Max(err_mm, 2).c_str(),
                  hapi_nodelet_kit::formatP50P99Max(err_deg, 3).c_str());
    std::printf("\n");
  }
  return 0;
}
