// surface_motion_replay: the surface-motion estimator (docs/DESIGN.md
// "Surface motion") offline, as SurfaceMotionNodelet runs it, for the
// evaluation of tools/eval/motion_study.py.
//
//   surface_motion_replay --odom PREFIX_imu_rate.txt --map PREFIX_map.txt --flow FLOW.txt
//       --intrinsics "fx fy cx cy width height rate" [--distortion "k1 k2 p1 p2 k3"]
//       [--extrinsic "x y z qx qy qz qw"] [--flow-latency S] --out OUT.txt [--smoothed SMOOTHED.txt]
//       [key=value ...]                         (--help: the settings key=value may set)
//
// Inputs: eskf_replay --out's PREFIX_imu_rate.txt (t, the odometry camera's
// pose in the world as TUM, its linear and angular velocity in its own
// frame) and PREFIX_map.txt (t N x1 y1 z1 ... per map snapshot, the same
// world), imaging_flow_replay's flow file (t_prev t u v a0..a5 C00..C55
// inliers tracked status), the imaging camera's intrinsics and its pose in
// the odometry camera's frame (default identity). A map snapshot is used from
// its stamp on; a flow is given to the estimator with the first odometry
// sample at or after its stamp plus --flow-latency (default 0).
// Output, one line per odometry sample (the causal output), and with
// --smoothed the same over the whole run from the fixed-interval smoother:
//   t status px py pz nx ny nz sx sy sz speed Css(9) vn var_vn iu iv Cii(4) flow_fused
// (m, mm/s, px/frame as hapi_msgs/SurfaceMotion; nan when status is not 0).
#include "hapi_eskf/settings_table.hpp"
#include "hapi_eskf/surface_motion/surface_motion_estimator.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

using namespace hapi_eskf;
using namespace hapi_eskf::surface_motion;

namespace {

// Whitespace-separated numbers per line, '#' lines and blank lines skipped.
bool readRows(const std::string& path, std::vector<std::vector<double>>* rows, std::string* err) {
  std::ifstream in(path);
  if (!in) {
    *err = "cannot read " + path;
    return false;
  }
  std::string line;
  while (std::getline(in, line)) {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream ss(line);
    std::vector<double> row;
    double x;
    while (ss >> x) row.push_back(x);
    if (!ss.eof()) {
      *err = path + ": not a number in '" + line + "'";
      return false;
    }
    if (!row.empty()) rows->push_back(std::move(row));
  }
  return true;
}

std::vector<double> numbers(const std::string& text) {
  std::istringstream ss(text);
  std::vector<double> v;
  double x;
  while (ss >> x) v.push_back(x);
  return v;
}

CameraOdometry odometryRow(const std::vector<double>& r) {
  CameraOdometry o;
  o.t = r[0];
  o.T_world_cam.translation() = Vec3(r[1], r[2], r[3]);
  o.T_world_cam.linear() = Eigen::Quaterniond(r[7], r[4], r[5], r[6]).normalized().toRotationMatrix();
  o.v = Vec3(r[8], r[9], r[10]);
  o.w = Vec3(r[11], r[12], r[13]);
  return o;
}

FlowMeasurement flowRow(const std::vector<double>& r) {
  FlowMeasurement f;
  f.t_prev = r[0];
  f.t = r[1];
  f.u = r[2];
  f.v = r[3];
  for (int i = 0; i < 6; ++i) f.affine[i] = r[4 + i];
  for (int i = 0; i < 36; ++i) f.covariance[i] = r[10 + i];
  f.inliers = static_cast<uint32_t>(r[46]);
  f.tracked = static_cast<uint32_t>(r[47]);
  f.status = static_cast<uint8_t>(r[48]);
  return f;
}

void writeOutput(std::FILE* f, const SurfaceMotionOutput& o) {
  const SurfaceVelocity& s = o.velocity;
  const bool ok = o.status == MotionStatus::kOk;
  auto num = [&](double x) { std::fprintf(f, " %.9g", ok ? x : std::nan("")); };
  std::fprintf(f, "%.9f %d", o.t, static_cast<int>(o.status));
  for (int i = 0; i < 3; ++i) num(s.point(i));
  for (int i = 0; i < 3; ++i) num(s.normal(i));
  for (int i = 0; i < 3; ++i) num(s.surface_velocity(i));
  num(s.speed());
  for (int i = 0; i < 9; ++i) num(s.surface_velocity_covariance(i / 3, i % 3));
  num(s.normal_velocity);
  num(s.normal_velocity_variance);
  for (int i = 0; i < 2; ++i) num(s.image_velocity(i));
  for (int i = 0; i < 4; ++i) num(s.image_velocity_covariance(i / 2, i % 2));
  std::fprintf(f, " %d\n", o.flow_fused ? 1 : 0);
}

const char* kUsage =
    "usage: surface_motion_replay --odom PREFIX_imu_rate.txt --map PREFIX_map.txt --flow FLOW.txt\n"
    "         --intrinsics \"fx fy cx cy width height rate\" [--distortion \"k1 k2 p1 p2 k3\"]\n"
    "         [--extrinsic \"x y z qx qy qz qw\"] [--flow-latency S] --out OUT.txt [--smoothed SMOOTHED.txt]\n"
    "         [key=value ...]\n"
    "       surface_motion_replay --help   (lists the settings key=value may set)\n";

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 2 && std::string(argv[1]) == "--help") {
    std::cout << kUsage << "settings (SurfaceMotionSettings, surface_motion_settings.def):\n";
    const SurfaceMotionSettings defaults;
    forEachField(defaults, [](const FieldInfo& f, const auto& v) { std::cout << "  " << describeField(f, v) << "\n"; });
    return 0;
  }
  SurfaceMotionSettings s;
  // Offline the smoother covers the whole run (a key=value may say otherwise).
  s.history_length = 3600;
  std::map<std::string, std::string> opt;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.rfind("--", 0) == 0 && i + 1 < argc) {
      opt[a] = argv[++i];
      continue;
    }
    const auto eq = a.find('=');
    const std::string err = eq == std::string::npos ? "unknown argument " + a
                                                    : setTableFieldFromText(&s, a.substr(0, eq), a.substr(eq + 1));
    if (!err.empty()) {
      std::cerr << err << "\n" << kUsage;
      return 1;
    }
  }
  for (const char* required : {"--odom", "--map", "--flow", "--intrinsics", "--out"})
    if (!opt.count(required)) {
      std::cerr << "missing " << required << "\n" << kUsage;
      return 1;
    }
  if (!s.validate().empty()) {
    std::cerr << s.validate() << "\n";
    return 1;
  }
  ImagingCamera cam;
  const std::vector<double> k = numbers(opt["--intrinsics"]);
  if (k.size() != 7) {
    std::cerr << "--intrinsics needs 7 numbers: fx fy cx cy width height rate\n";
    return 1;
  }
  cam.fx = k[0], cam.fy = k[1], cam.cx = k[2], cam.cy = k[3];
  cam.width = static_cast<int>(k[4]), cam.height = static_cast<int>(k[5]), cam.frame_rate = k[6];
  if (opt.count("--distortion")) {
    const std::vector<double> d = numbers(opt["--distortion"]);
    if (d.size() < 4 || d.size() > 5) {
      std::cerr << "--distortion needs 4 or 5 numbers (plumb_bob)\n";
      return 1;
    }
    for (std::size_t i = 0; i < d.size(); ++i) cam.distortion[i] = d[i];
  }
  Eigen::Isometry3d T_odom_imaging = Eigen::Isometry3d::Identity();
  if (opt.count("--extrinsic")) {
    const std::vector<double> e = numbers(opt["--extrinsic"]);
    if (e.size() != 7) {
      std::cerr << "--extrinsic needs 7 numbers: x y z qx qy qz qw\n";
      return 1;
    }
    T_odom_imaging.translation() = Vec3(e[0], e[1], e[2]);
    T_odom_imaging.linear() = Eigen::Quaterniond(e[6], e[3], e[4], e[5]).normalized().toRotationMatrix();
  }
  const double latency = opt.count("--flow-latency") ? std::stod(opt["--flow-latency"]) : 0.0;

  std::vector<std::vector<double>> odom, maps, flows;
  std::string err;
  if (!readRows(opt["--odom"], &odom, &err) || !readRows(opt["--map"], &maps, &err) ||
      !readRows(opt["--flow"], &flows, &err)) {
    std::cerr << err << "\n";
    return 1;
  }
  for (const auto& r : odom)
    if (r.size() != 14) return std::cerr << "--odom rows need 14 numbers\n", 1;
  for (const auto& r : maps)
    if (r.size() < 2 || r.size() != 2 + 3 * static_cast<std::size_t>(r[1])) return std::cerr << "bad --map row\n", 1;
  for (const auto& r : flows)
    if (r.size() != 49) return std::cerr << "--flow rows need 49 numbers\n", 1;

  SurfaceMotionEstimator est(s);
  err = est.setCamera(cam);
  if (!err.empty()) return std::cerr << err << "\n", 1;
  std::FILE* out = std::fopen(opt["--out"].c_str(), "w");
  if (out == nullptr) return std::cerr << "cannot write " << opt["--out"] << "\n", 1;
  std::fprintf(out, "# t status px py pz nx ny nz sx sy sz speed Css(9) vn var_vn iu iv Cii(4) flow_fused\n");
  std::size_t next_map = 0, next_flow = 0;
  std::map<FlowOutcome, int> outcomes;
  int outputs = 0, ok = 0;
  for (const auto& r : odom) {
    const CameraOdometry o = toRigidlyAttached(odometryRow(r), T_odom_imaging);
    for (; next_map < maps.size() && maps[next_map][0] <= o.t; ++next_map) {
      std::vector<Vec3> pts;
      for (std::size_t i = 2; i + 2 < maps[next_map].size(); i += 3)
        pts.emplace_back(maps[next_map][i], maps[next_map][i + 1], maps[next_map][i + 2]);
      est.setMap(std::move(pts));
    }
    for (; next_flow < flows.size() && flows[next_flow][1] + latency <= o.t; ++next_flow)
      ++outcomes[est.addFlow(flowRow(flows[next_flow]))];
    const auto res = est.addOdometry(o);
    for (FlowOutcome f : est.pendingOutcomes()) ++outcomes[f];
    if (!res) continue;
    writeOutput(out, *res);
    ++outputs;
    ok += res->status == MotionStatus::kOk;
  }
  std::fclose(out);
  if (opt.count("--smoothed") && !odom.empty()) {
    std::FILE* sm = std::fopen(opt["--smoothed"].c_str(), "w");
    if (sm == nullptr) return std::cerr << "cannot write " << opt["--smoothed"] << "\n", 1;
    std::fprintf(sm, "# smoothed: t status px py pz nx ny nz sx sy sz speed Css(9) vn var_vn iu iv Cii(4) flow_fused\n");
    for (const SurfaceMotionOutput& o : est.smoothed(odom.front()[0], odom.back()[0])) writeOutput(sm, o);
    std::fclose(sm);
  }
  std::fprintf(stderr, "%d outputs (%d ok), %zu flows:", outputs, ok, flows.size());
  for (const auto& kv : outcomes) std::fprintf(stderr, " %s %d", toString(kv.first), kv.second);
  std::fprintf(stderr, "\n");
  return 0;
}
