// Reading one ASL/EuRoC mav0 folder (asl_recording.hpp).
#include "hapi_dataset/asl_recording.hpp"

#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <sys/stat.h>

#include "hapi_dataset/asl_csv.hpp"

namespace hapi_dataset {
namespace {

bool isDir(const std::string& p) {
  struct stat st {};
  return ::stat(p.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

bool isFile(const std::string& p) {
  struct stat st {};
  return ::stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

void requireIncreasing(int64_t previous, int64_t stamp, const std::string& path, int line) {
  if (stamp <= previous)
    throw std::runtime_error(path + ":" + std::to_string(line) + ": timestamp " + std::to_string(stamp) +
                             " does not increase");
}

// cam<i>/data.csv: timestamp [ns], file name under cam<i>/data/.
std::map<int64_t, std::string> readImageList(const std::string& cam_dir) {
  const std::string csv = cam_dir + "/data.csv";
  std::map<int64_t, std::string> out;
  int64_t prev = INT64_MIN;
  for (const CsvRow& row : readCsv(csv)) {
    const int64_t t = csvInt64(row, 0, csv);
    requireIncreasing(prev, t, csv, row.line);
    prev = t;
    if (row.fields.size() < 2 || row.fields[1].empty())
      throw std::runtime_error(csv + ":" + std::to_string(row.line) + ": no file name");
    out.emplace(t, cam_dir + "/data/" + row.fields[1]);
  }
  return out;
}

std::vector<ImuSample> readImu(const std::string& dir) {
  const std::string csv = dir + "/data.csv";
  std::vector<ImuSample> out;
  int64_t prev = INT64_MIN;
  for (const CsvRow& row : readCsv(csv)) {
    ImuSample s;
    s.stamp_ns = csvInt64(row, 0, csv);
    requireIncreasing(prev, s.stamp_ns, csv, row.line);
    prev = s.stamp_ns;
    for (int i = 0; i < 3; ++i) s.angular_velocity[i] = csvDouble(row, 1 + i, csv);
    for (int i = 0; i < 3; ++i) s.linear_acceleration[i] = csvDouble(row, 4 + i, csv);
    out.push_back(s);
  }
  return out;
}

// p_RS_R (x y z), q_RS (w x y z), v_RS_R (x y z), then biases (not used).
std::vector<BodyPose> readGroundTruth(const std::string& dir) {
  const std::string csv = dir + "/data.csv";
  std::vector<BodyPose> out;
  int64_t prev = INT64_MIN;
  for (const CsvRow& row : readCsv(csv)) {
    BodyPose b;
    b.stamp_ns = csvInt64(row, 0, csv);
    requireIncreasing(prev, b.stamp_ns, csv, row.line);
    prev = b.stamp_ns;
    const Eigen::Vector3d p(csvDouble(row, 1, csv), csvDouble(row, 2, csv), csvDouble(row, 3, csv));
    Eigen::Quaterniond q(csvDouble(row, 4, csv), csvDouble(row, 5, csv), csvDouble(row, 6, csv),
                         csvDouble(row, 7, csv));
    if (q.norm() < 0.5)
      throw std::runtime_error(csv + ":" + std::to_string(row.line) + ": quaternion far from unit norm");
    q.normalize();
    b.T_W_B = Eigen::Isometry3d::Identity();
    b.T_W_B.linear() = q.toRotationMatrix();
    b.T_W_B.translation() = p;
    if (row.fields.size() >= 11)
      b.v_W = Eigen::Vector3d(csvDouble(row, 8, csv), csvDouble(row, 9, csv), csvDouble(row, 10, csv));
    out.push_back(b);
  }
  return out;
}

}  // namespace

std::string findMav0(const std::string& folder) {
  if (isDir(folder + "/cam0")) return folder;
  if (isDir(folder + "/mav0/cam0")) return folder + "/mav0";
  return "";
}

AslRecording readAslRecording(const std::string& folder) {
  AslRecording rec;
  rec.mav0 = findMav0(folder);
  if (rec.mav0.empty()) throw std::runtime_error(folder + ": neither it nor its mav0/ holds cam0/");
  for (const char* d : {"cam0", "cam1", "imu0"})
    if (!isDir(rec.mav0 + "/" + d)) throw std::runtime_error(rec.mav0 + ": no " + d + "/");
  rec.cam0 = readCameraSensor(rec.mav0 + "/cam0/sensor.yaml");
  rec.cam1 = readCameraSensor(rec.mav0 + "/cam1/sensor.yaml");
  rec.imu0 = readImuSensor(rec.mav0 + "/imu0/sensor.yaml");

  // EuRoC triggers both cameras together: a stereo frame is a stamp that both
  // lists hold. Unpaired images (a dropped frame in one camera) are skipped.
  const auto left = readImageList(rec.mav0 + "/cam0");
  const auto right = readImageList(rec.mav0 + "/cam1");
  for (const auto& [t, png] : left) {
    const auto r = right.find(t);
    if (r != right.end()) rec.frames.push_back({t, png, r->second});
  }
  if (rec.frames.empty()) throw std::runtime_error(rec.mav0 + ": cam0 and cam1 share no timestamp");

  rec.imu = readImu(rec.mav0 + "/imu0");
  const std::string gt = rec.mav0 + "/state_groundtruth_estimate0";
  if (isFile(gt + "/data.csv")) rec.ground_truth = readGroundTruth(gt);

  const std::string scene = rec.mav0 + "/scene.yaml";
  if (isFile(scene)) {
    std::ifstream f(scene);
    std::ostringstream ss;
    ss << f.rdbuf();
    rec.scene_yaml = ss.str();
  }
  return rec;
}

}  // namespace hapi_dataset
