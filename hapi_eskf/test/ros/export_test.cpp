// PLY and TUM files written by ~save_map / ~save_trajectory parse back.
#include "hapi_eskf/ros/export.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <unistd.h>

using namespace hapi_eskf;
using namespace hapi_eskf::ros_glue;

TEST(Export, PlyRoundTrip) {
  std::vector<MapPoint> pts(3);
  for (int i = 0; i < 3; ++i) {
    pts[i].position = Vec3(i, -i, 0.5 * i);
    pts[i].rgb = {{uint8_t(10 * i), 20, 255}};
    pts[i].sigma = 0.01f * (i + 1);
  }
  const std::string path = "/tmp/hapi_export_test_" + std::to_string(getpid()) + ".ply";
  ASSERT_EQ(writePly(path, pts), "");
  std::ifstream f(path);
  std::string line, header;
  int vertices = -1;
  while (std::getline(f, line) && line != "end_header") {
    header += line + "\n";
    if (line.rfind("element vertex ", 0) == 0) vertices = std::stoi(line.substr(15));
  }
  EXPECT_EQ(header.rfind("ply\nformat ascii 1.0\n", 0), 0u);
  EXPECT_NE(header.find("property float sigma"), std::string::npos);
  ASSERT_EQ(vertices, 3);
  for (int i = 0; i < 3; ++i) {
    double x, y, z, s;
    int r, g, b;
    ASSERT_TRUE(f >> x >> y >> z >> r >> g >> b >> s);
    EXPECT_DOUBLE_EQ(x, i);
    EXPECT_DOUBLE_EQ(z, 0.5 * i);
    EXPECT_EQ(r, 10 * i);
    EXPECT_EQ(b, 255);
    EXPECT_NEAR(s, 0.01 * (i + 1), 1e-7);
  }
  double extra;
  EXPECT_FALSE(f >> extra);
  std::remove(path.c_str());
}

TEST(Export, TumRoundTrip) {
  std::vector<StampedPose> poses(2);
  poses[0].stamp = 1700000000.123456;
  poses[0].p = Vec3(1, 2, 3);
  poses[1].stamp = 1700000000.223456;
  poses[1].q = Eigen::Quaterniond(Eigen::AngleAxisd(0.5, Vec3::UnitZ()));
  const std::string path = "/tmp/hapi_export_test_" + std::to_string(getpid()) + ".tum";
  ASSERT_EQ(writeTum(path, poses), "");
  std::ifstream f(path);
  std::string line;
  int n = 0;
  while (std::getline(f, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    double v[8];
    for (double& x : v) ASSERT_TRUE(ss >> x) << line;
    EXPECT_NEAR(v[0], poses[n].stamp, 1e-6);
    EXPECT_NEAR(v[1], poses[n].p.x(), 1e-9);
    EXPECT_NEAR(v[4], poses[n].q.x(), 1e-9);
    EXPECT_NEAR(v[6], poses[n].q.z(), 1e-9);  // qx qy qz qw order
    EXPECT_NEAR(v[7], poses[n].q.w(), 1e-9);
    ++n;
  }
  EXPECT_EQ(n, 2);
  std::remove(path.c_str());
}

TEST(Export, UnwritableDirectoryIsAnError) {
  EXPECT_NE(writeTum("/nonexistent_dir_hapi/x.tum", {}), "");
  const std::string p = timestampedPath("/tmp", "hapi_map", "ply");
  EXPECT_EQ(p.rfind("/tmp/hapi_map_", 0), 0u);
  EXPECT_EQ(p.substr(p.size() - 4), ".ply");
}
