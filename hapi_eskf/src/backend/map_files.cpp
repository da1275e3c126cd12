// The PLY and TUM writers and the map point's scalar sigma (map_files.hpp).
#include "hapi_eskf/backend/map_files.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>

namespace hapi_eskf {
namespace {

// Writes to "<path>.tmp" and renames, so a reader never sees a half file.
std::string commit(std::ofstream& f, const std::string& tmp, const std::string& path) {
  f.flush();
  if (!f) return "write to " + tmp + " failed";
  f.close();
  if (std::rename(tmp.c_str(), path.c_str()) != 0) return "rename to " + path + ": " + std::strerror(errno);
  return "";
}

}  // namespace

double landmarkSigma(const Mat3& covariance) {
  const Mat3 S = 0.5 * (covariance + covariance.transpose());
  if (!S.allFinite()) return std::numeric_limits<double>::quiet_NaN();
  const Eigen::SelfAdjointEigenSolver<Mat3> es(S, Eigen::EigenvaluesOnly);
  return std::sqrt(std::max(0.0, es.eigenvalues().maxCoeff()));
}

std::string writePly(const std::string& path, const std::vector<MapPoint>& points) {
  const std::string tmp = path + ".tmp";
  std::ofstream f(tmp);
  if (!f) return "cannot open " + tmp + ": " + std::strerror(errno);
  f << "ply\nformat ascii 1.0\ncomment hapi_eskf landmark map; sigma = sqrt(max eigenvalue of the 3x3 "
       "landmark covariance) [m]\n"
    << "element vertex " << points.size() << "\n"
    << "property float x\nproperty float y\nproperty float z\n"
    << "property uchar red\nproperty uchar green\nproperty uchar blue\n"
    << "property float sigma\nend_header\n";
  f << std::setprecision(9);
  for (const MapPoint& p : points) {
    f << p.position.x() << ' ' << p.position.y() << ' ' << p.position.z() << ' ' << int(p.rgb[0]) << ' '
      << int(p.rgb[1]) << ' ' << int(p.rgb[2]) << ' ' << p.sigma << '\n';
  }
  return commit(f, tmp, path);
}

std::string writeTum(const std::string& path, const std::vector<StampedPose>& poses) {
  const std::string tmp = path + ".tmp";
  std::ofstream f(tmp);
  if (!f) return "cannot open " + tmp + ": " + std::strerror(errno);
  f << "# timestamp tx ty tz qx qy qz qw\n" << std::fixed;
  for (const StampedPose& s : poses) {
    const Eigen::Quaterniond q = s.q.normalized();
    f << std::setprecision(9) << s.stamp << ' ' << s.p.x() << ' ' << s.p.y() << ' ' << s.p.z() << ' ' << q.x()
      << ' ' << q.y() << ' ' << q.z() << ' ' << q.w() << '\n';
  }
  return commit(f, tmp, path);
}

std::string timestampedPath(const std::string& dir, const std::string& prefix, const std::string& ext) {
  const auto now = std::chrono::system_clock::now();
  const std::time_t t = std::chrono::system_clock::to_time_t(now);
  const long ms = static_cast<long>(
      std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() % 1000);
  std::tm tm{};
  gmtime_r(&t, &tm);
  std::ostringstream s;
  s << dir << (dir.back() == '/' ? "" : "/") << prefix << '_' << std::put_time(&tm, "%Y%m%d_%H%M%S") << '_'
    << std::setw(3) << std::setfill('0') << ms << '.' << ext;
  return s.str();
}

}  // namespace hapi_eskf
