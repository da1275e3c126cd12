// A camera moving through a cloud of points (the filter-level parity tests:
// CPU vs CUDA, partitioned vs dense); each frame sees the points in front of it
// within range, with 1 cm noise and a fixed descriptor per point.
#pragma once

#include "hapi_eskf/eskf/eskf.hpp"
#include "test_random.hpp"

#include <cmath>
#include <vector>

namespace hapi_eskf {
namespace testing_world {

using testing_random::Rng;

struct World {
  std::vector<Vec3> points;
  std::vector<std::vector<uint8_t>> desc;
  Rng r{7};
  explicit World(int n) {
    for (int i = 0; i < n; ++i) {
      points.emplace_back(r.n(3.0), r.n(2.0), 4.0 + 12.0 * std::abs(r.n(1.0)));
      desc.push_back(r.bytes(32));
    }
  }
  StereoFrame frame(const PoseState& truth, double stamp, int max_meas) {
    StereoFrame f;
    f.stamp = stamp;
    f.descriptor_length = 32;
    const Mat3 Rt = truth.q.toRotationMatrix().transpose();
    for (std::size_t i = 0; i < points.size() && static_cast<int>(f.measurements.size()) < max_meas; ++i) {
      const Vec3 z = Rt * (points[i] - truth.p);
      if (z.z() < 1.0 || z.z() > 15.0 || std::abs(z.x()) > z.z() || std::abs(z.y()) > z.z()) continue;
      StereoMeasurement m;
      m.z = z + r.v3(0.01);
      m.Cz = 1e-4 * Mat3::Identity();
      m.frontend_id = static_cast<uint32_t>(i);
      m.response = static_cast<float>((i * 37) % 101);
      f.measurements.push_back(m);
      f.descriptors.insert(f.descriptors.end(), desc[i].begin(), desc[i].end());
    }
    return f;
  }
};

}  // namespace testing_world
}  // namespace hapi_eskf
