// dense_depth_link: what DenseDepthNodelet would send over the link on a
// recording (docs/DESIGN.md "Dense depth", link): the same keyframe gate and
// processing, the serialized size of ~depth, ~confidence and ~camera_info,
// and the valid fraction and time per keyframe (time on this machine).
//
//   dense_depth_link BAG [--prefix /stereo] [name=value ...]
//
// name=value: any ~ parameter of DenseDepthNodelet (dense_depth_settings.def,
// dense_depth_nodelet_params.def). Pairs: <prefix>/{left,right}/image_raw and
// camera_info with equal stamps.
#include "../ros/dense_depth_nodelet_processor.hpp"
#include "hapi_surface/dense_depth_keyframe_gate.hpp"

#include <ros/serialization.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <map>
#include <string>
#include <vector>

namespace {

using namespace hapi_surface;

struct PairSlot {
  sensor_msgs::ImageConstPtr left, right;
  sensor_msgs::CameraInfoConstPtr left_info, right_info;
  bool complete() const { return left && right && left_info && right_info; }
};

template <typename M>
std::size_t bytes(const M& m) {
  return ros::serialization::serializationLength(m);
}

int usage() {
  std::cerr << "usage: dense_depth_link BAG [--prefix /stereo] [name=value ...]\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage();
  const std::string bag_path = argv[1];
  std::string prefix = "/stereo";
  DenseDepthNodeletParams params;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--prefix" && i + 1 < argc) {
      prefix = argv[++i];
      continue;
    }
    const std::size_t eq = a.find('=');
    if (eq == std::string::npos) return usage();
    const std::string e = setDenseDepthParam(&params, a.substr(0, eq), a.substr(eq + 1));
    if (!e.empty()) {
      std::cerr << e << "\n";
      return 2;
    }
  }
  const std::string invalid = params.depth.validate();
  if (!invalid.empty()) {
    std::cerr << invalid << "\n";
    return 2;
  }
  rosbag::Bag bag(bag_path, rosbag::bagmode::Read);
  const std::string tl = prefix + "/left/image_raw", tr = prefix + "/right/image_raw";
  const std::string il = prefix + "/left/camera_info", ir = prefix + "/right/camera_info";
  rosbag::View view(bag, rosbag::TopicQuery(std::vector<std::string>{tl, tr, il, ir}));
  DenseDepthProcessor processor(params);
  DenseDepthKeyframeGate gate(params.rate);
  std::map<std::uint64_t, PairSlot> pending;
  std::size_t n_pairs = 0, n_key = 0, depth_bytes = 0, conf_bytes = 0, info_bytes = 0, stereo_bytes = 0;
  double valid = 0, ms = 0;
  ros::Time first, last;
  for (const rosbag::MessageInstance& m : view) {
    std::uint64_t stamp = 0;
    if (auto img = m.instantiate<sensor_msgs::Image>()) {
      stamp = img->header.stamp.toNSec();
      (m.getTopic() == tl ? pending[stamp].left : pending[stamp].right) = img;
      stereo_bytes += bytes(*img);
    } else if (auto info = m.instantiate<sensor_msgs::CameraInfo>()) {
      stamp = info->header.stamp.toNSec();
      (m.getTopic() == il ? pending[stamp].left_info : pending[stamp].right_info) = info;
    } else {
      continue;
    }
    const PairSlot& p = pending[stamp];
    if (!p.complete()) continue;
    ++n_pairs;
    if (first.isZero()) first = p.left->header.stamp;
    last = p.left->header.stamp;
    if (gate.take(static_cast<std::int64_t>(stamp))) {
      DepthMessages out;
      const auto t0 = std::chrono::steady_clock::now();
      const InputError e = processor.process(p.left, p.left_info, p.right, p.right_info, &out);
      ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      if (e) {
        std::cerr << "rejected [" << e.reason << "]: " << e.detail << "\n";
      } else {
        ++n_key;
        depth_bytes += bytes(*out.depth);
        conf_bytes += bytes(*out.confidence);
        info_bytes += bytes(*out.camera_info);
        valid += out.valid_fraction;
      }
    }
    pending.erase(pending.begin(), pending.upper_bound(stamp));
  }
  // Pairs are 1/rate apart: the recording's span plus one frame period.
  const double span = n_pairs > 1 ? (last - first).toSec() * n_pairs / (n_pairs - 1.0) : 0.0;
  if (n_key == 0 || span <= 0) {
    std::cerr << "no keyframe computed (" << n_pairs << " pairs on " << prefix << ")\n";
    return 1;
  }
  const double total = static_cast<double>(depth_bytes + conf_bytes + info_bytes);
  std::printf("pairs %zu over %.2f s, keyframes %zu (%.2f Hz)\n", n_pairs, span, n_key, n_key / span);
  std::printf("per keyframe: depth %zu B, confidence %zu B, camera_info %zu B; valid %.1f %%; %.0f ms on this machine\n",
              depth_bytes / n_key, conf_bytes / n_key, info_bytes / n_key, 100.0 * valid / n_key, ms / n_key);
  std::printf("link: %.0f B/s = %.3f MB/s (the raw stereo pair: %.3f MB/s)\n", total / span, total / span / 1e6,
              stereo_bytes / span / 1e6);
  return 0;
}
