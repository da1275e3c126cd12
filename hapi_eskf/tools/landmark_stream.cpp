// Reader of the landmark stream (landmark_stream.hpp).
#include "landmark_stream.hpp"

#include <fstream>
#include <sstream>

namespace hapi_eskf {
namespace tools {
namespace {

std::vector<uint8_t> fromHex(const std::string& h) {
  std::vector<uint8_t> out(h.size() / 2);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = static_cast<uint8_t>(std::stoi(h.substr(2 * i, 2), nullptr, 16));
  return out;
}

}  // namespace

bool readLandmarkStream(const std::string& path, LandmarkStream* out, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = "cannot read " + path;
    return false;
  }
  LandmarkStream s;
  std::string line;
  int line_no = 0;
  auto bad = [&](const std::string& what) {
    *error = path + ":" + std::to_string(line_no) + ": " + what;
    return false;
  };
  while (std::getline(in, line)) {
    ++line_no;
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    if (tag == "globe") {
      ls >> s.globe_centre.x() >> s.globe_centre.y() >> s.globe_centre.z() >> s.globe_radius;
      s.has_globe = true;
    } else if (tag == "scene") {
      s.scene_json = line.substr(6);
    } else if (tag == "gt") {
      TruePose g;
      ls >> g.t >> g.p.x() >> g.p.y() >> g.p.z() >> g.q.x() >> g.q.y() >> g.q.z() >> g.q.w();
      s.truth.push_back(g);
    } else if (tag == "gtvel") {
      TrueTwist g;
      ls >> g.t >> g.v.x() >> g.v.y() >> g.v.z() >> g.w.x() >> g.w.y() >> g.w.z();
      s.true_twist.push_back(g);
    } else if (tag == "extrinsic") {
      CameraExtrinsic e;
      for (int k = 0; k < 9; ++k) ls >> e.R_imu_cam(k / 3, k % 3);
      ls >> e.p_imu_cam.x() >> e.p_imu_cam.y() >> e.p_imu_cam.z();
      s.extrinsic = e;
    } else if (tag == "imu") {
      ImuSample m;
      ls >> m.stamp >> m.gyro.x() >> m.gyro.y() >> m.gyro.z() >> m.accel.x() >> m.accel.y() >> m.accel.z();
      s.imu.push_back(m);
    } else if (tag == "frame") {
      StereoFrame f;
      int n = 0;
      ls >> f.stamp >> n >> f.descriptor_length;
      if (!ls || n < 0) return bad("malformed frame line");
      f.measurements.resize(n);
      for (int i = 0; i < n; ++i) {
        if (!std::getline(in, line)) return bad("frame ends early");
        ++line_no;
        std::istringstream ms(line);
        std::string m, hex;
        int r, g, b;
        StereoMeasurement& z = f.measurements[i];
        ms >> m >> z.frontend_id >> z.response >> r >> g >> b >> z.z.x() >> z.z.y() >> z.z.z();
        for (int k = 0; k < 9; ++k) ms >> z.Cz(k / 3, k % 3);
        ms >> hex;
        if (!ms || m != "m") return bad("malformed measurement line");
        z.rgb = {{static_cast<uint8_t>(r), static_cast<uint8_t>(g), static_cast<uint8_t>(b)}};
        const auto d = fromHex(hex);
        f.descriptors.insert(f.descriptors.end(), d.begin(), d.end());
      }
      s.frames.push_back(std::move(f));
    } else if (!tag.empty()) {
      return bad("unknown line '" + tag + "'");
    }
    if (!ls && tag != "frame" && tag != "scene") return bad("malformed '" + tag + "' line");
  }
  *out = std::move(s);
  return true;
}

}  // namespace tools
}  // namespace hapi_eskf
