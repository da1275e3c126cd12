// rostest (params.test): config/eskf.yaml and the settings tables agree, and
// loadParams keeps its read rules. The yaml is checked as the nodelet sees it:
// loaded by rosparam, read by loadParams through the tables.
#include "hapi_eskf/ros/params.hpp"

#include <ros/ros.h>

#include <gtest/gtest.h>

#include <cstdio>
#include <set>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

using hapi_eskf::FieldInfo;
using hapi_eskf::ros_glue::loadParams;
using hapi_eskf::ros_glue::NodeletParams;

namespace {

// Every parameter of `p` by name, as exact typed values (doubles compared
// bit for bit through their 17-digit text, enums through their names).
std::vector<std::pair<std::string, std::string>> values(const NodeletParams& p) {
  std::vector<std::pair<std::string, std::string>> out;
  hapi_eskf::ros_glue::forEachParameter(p, [&](const FieldInfo& f, const auto& v) {
    using T = std::decay_t<decltype(v)>;
    std::string text;
    if constexpr (std::is_same<T, double>::value) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.17g", v);
      text = buf;
    } else {
      text = hapi_eskf::valueText(v);
    }
    out.emplace_back(f.name, text);
  });
  return out;
}

}  // namespace

TEST(EskfParams, ConfigYamlListsEveryTableFieldWithItsDefault) {
  ros::NodeHandle yaml("/eskf_yaml");
  const NodeletParams defaults;
  std::set<std::string> names;
  hapi_eskf::ros_glue::forEachParameter(defaults, [&](const FieldInfo& f, const auto&) {
    names.insert(f.name);
    EXPECT_TRUE(yaml.hasParam(f.name)) << "config/eskf.yaml lacks ~" << f.name;
  });
  NodeletParams loaded;
  ASSERT_EQ(loadParams(yaml, &loaded), "");
  std::string extra;
  for (const std::string& n : loaded.unknown) extra += " ~" + n;
  EXPECT_EQ(extra, "") << "config/eskf.yaml has keys that no table names";
  const auto want = values(defaults), got = values(loaded);
  ASSERT_EQ(want.size(), got.size());
  ASSERT_EQ(want.size(), names.size());
  for (std::size_t i = 0; i < want.size(); ++i)
    EXPECT_EQ(got[i].second, want[i].second) << "~" << want[i].first << ": config/eskf.yaml vs the table's default";
  // ~time_jump_reset is hapi_nodelet_kit's parameter, with the kit's default.
  EXPECT_TRUE(yaml.hasParam(hapi_nodelet_kit::TimeJumpResetParam::kName)) << "config/eskf.yaml lacks ~time_jump_reset";
  EXPECT_EQ(loaded.time_jump_reset, hapi_nodelet_kit::TimeJumpResetParam::kDefault);
}

TEST(EskfParams, ReadRules) {
  NodeletParams p;
  // Absent: the defaults.
  ros::NodeHandle empty("/nothing_set");
  ASSERT_EQ(loadParams(empty, &p), "");
  EXPECT_EQ(p.filter.ransac_iterations, NodeletParams().filter.ransac_iterations);
  EXPECT_TRUE(p.unknown.empty());
  // Ints are accepted for doubles; enums by name; unknown names are listed
  // (not a sub-namespace: another component's parameters, hapi_nodelet_kit's
  // ParamReader rule for every nodelet).
  ros::param::set("/ok/map_publish_rate", 2);
  ros::param::set("/ok/relocalise_gap", 3);
  ros::param::set("/ok/cuda_solve", std::string("inverse"));
  ros::param::set("/ok/use_imu", true);
  ros::param::set("/ok/max_landmark", 10);
  // Kalibr's T_cam_imu: the camera in the IMU frame is its inverse.
  ros::param::set("/ok/T_cam_imu", std::vector<double>{0, -1, 0, 0.01, 0, 0, -1, 0.02, 1, 0, 0, 0.03, 0, 0, 0, 1});
  ros::param::set("/ok/nested/key", 1);
  ASSERT_EQ(loadParams(ros::NodeHandle("/ok"), &p), "");
  EXPECT_EQ(p.map_publish_rate, 2.0);
  EXPECT_EQ(p.filter.relocalise_gap, 3.0);
  EXPECT_EQ(p.filter.cuda_solve, hapi_eskf::CudaSolve::kInverse);
  // The deprecated ~use_imu: true selects the gyro model (and is not unknown).
  EXPECT_EQ(p.filter.motion_model, hapi_eskf::MotionModelKind::kGyro);
  EXPECT_TRUE(p.usesImu());
  hapi_eskf::CameraExtrinsic e;
  std::string why;
  ASSERT_TRUE(hapi_eskf::ros_glue::cameraInImuFromKalibr(p.T_cam_imu, &e, &why)) << why;
  EXPECT_LT((e.R_imu_cam * Eigen::Vector3d(0.01, 0.02, 0.03) + e.p_imu_cam).norm(), 1e-12);  // camera origin side
  EXPECT_LT((e.R_imu_cam * Eigen::Vector3d::UnitZ() - Eigen::Vector3d::UnitX()).norm(), 1e-12);
  EXPECT_EQ(p.unknown, (std::vector<std::string>{"max_landmark"}));
  // A present parameter of the wrong type, an unknown enum name, a value out
  // of its range, a broken rule between parameters: refused, *out untouched.
  const NodeletParams before = p;
  ros::param::set("/type/max_landmarks", std::string("many"));
  EXPECT_EQ(loadParams(ros::NodeHandle("/type"), &p),
            "parameter ~max_landmarks has the wrong type: expected an integer, got the string 'many'");
  ros::param::set("/number/gate_chi2", std::string("big"));
  EXPECT_EQ(loadParams(ros::NodeHandle("/number"), &p),
            "parameter ~gate_chi2 has the wrong type: expected a number, got the string 'big'");
  ros::param::set("/flag/publish_tf", 1);
  EXPECT_EQ(loadParams(ros::NodeHandle("/flag"), &p),
            "parameter ~publish_tf has the wrong type: expected a boolean (true/false), got the integer 1");
  ros::param::set("/enum/backend", std::string("gpu"));
  EXPECT_EQ(loadParams(ros::NodeHandle("/enum"), &p), "~backend must be 'cpu' or 'cuda', got 'gpu'");
  ros::param::set("/range/time_jump_reset", -1.0);
  EXPECT_EQ(loadParams(ros::NodeHandle("/range"), &p), "~time_jump_reset must be >= 0 s, got -1");
  ros::param::set("/filter_range/ransac_iterations", -5);
  EXPECT_EQ(loadParams(ros::NodeHandle("/filter_range"), &p), "ransac_iterations must be in [0, 100000], got -5");
  ros::param::set("/rule/motion_model", std::string("inertial"));
  ros::param::set("/rule/imu_topic", std::string(""));
  EXPECT_EQ(loadParams(ros::NodeHandle("/rule"), &p),
            "~imu_topic must not be empty with ~motion_model gyro or inertial");
  ros::param::set("/extrinsic/T_cam_imu", std::vector<double>{1, 0, 0});
  EXPECT_EQ(loadParams(ros::NodeHandle("/extrinsic"), &p), "~T_cam_imu must hold 16 numbers (a row-major 4x4), got 3");
  ros::param::set("/extrinsic2/T_cam_imu", std::vector<double>{2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1});
  EXPECT_EQ(loadParams(ros::NodeHandle("/extrinsic2"), &p),
            "~T_cam_imu must be a rigid transform (rotation, translation, last row 0 0 0 1)");
  ros::param::set("/model/motion_model", std::string("imu"));
  EXPECT_EQ(loadParams(ros::NodeHandle("/model"), &p),
            "~motion_model must be 'constant_velocity', 'gyro' or 'inertial', got 'imu'");
  EXPECT_EQ(values(p), values(before));
  EXPECT_EQ(p.time_jump_reset, before.time_jump_reset);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_eskf_params");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
