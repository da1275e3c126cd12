// rostest (eskf_nodelet_startup.test): parameters are validated at start-up;
// an invalid one is a start-up failure (hapi_nodelet_kit/startup_failure.hpp):
// a clear FATAL message, the nodelet stays loaded but inert (ERROR "not
// running" on /diagnostics, no subscription). ~backend=cuda without a usable
// GPU is the same start-up failure with ~allow_cpu_fallback:=false and a
// loudly logged fallback to the CPU backend (reported in /diagnostics)
// otherwise.
#include "hapi_eskf/covariance/covariance_backend.hpp"
#include "hapi_eskf/eskf/storage_factory.hpp"
#include "nodelet_observer.hpp"
#include "synthetic_frames.hpp"

#include <diagnostic_msgs/DiagnosticArray.h>
#include <nav_msgs/Odometry.h>
#include <nodelet/NodeletList.h>
#include <nodelet/NodeletLoad.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <mutex>

namespace {

std::mutex mu;
std::vector<rosgraph_msgs::Log> logs;
std::map<std::string, std::map<std::string, std::string>> diag;  // status name -> values
std::vector<diagnostic_msgs::DiagnosticStatus> statuses;         // every status received

void onLog(const rosgraph_msgs::Log::ConstPtr& m) {
  std::lock_guard<std::mutex> lk(mu);
  logs.push_back(*m);
}
void onDiag(const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
  std::lock_guard<std::mutex> lk(mu);
  for (const auto& s : m->status)
    for (const auto& kv : s.values) diag[s.name][kv.key] = kv.value;
  statuses.insert(statuses.end(), m->status.begin(), m->status.end());
}
using hapi_eskf_test::waitFor;
// A /rosout message of at least `level` containing `text`.
bool logged(std::uint8_t level, const std::string& text, double timeout = 5.0) {
  return waitFor([&] {
    std::lock_guard<std::mutex> lk(mu);
    return std::any_of(logs.begin(), logs.end(), [&](const rosgraph_msgs::Log& l) {
      return l.level >= level && l.msg.find(text) != std::string::npos;
    });
  }, timeout);
}
std::string diagValue(const std::string& nodelet, const std::string& key) {
  std::lock_guard<std::mutex> lk(mu);
  for (const auto& s : diag)
    if (s.first.find(nodelet) != std::string::npos && s.second.count(key)) return s.second.at(key);
  return "";
}

// The nodelet's "filter" status was ERROR with a message starting "not running".
bool reportsNotRunning(const std::string& nodelet, double timeout = 5.0) {
  const std::string name = nodelet.substr(1) + ": filter";  // diagnostic_updater drops the leading '/'
  return waitFor([&] {
    std::lock_guard<std::mutex> lk(mu);
    return std::any_of(statuses.begin(), statuses.end(), [&](const diagnostic_msgs::DiagnosticStatus& st) {
      return st.name == name && st.level == diagnostic_msgs::DiagnosticStatus::ERROR &&
             st.message.rfind("not running", 0) == 0;
    });
  }, timeout);
}

// Subscribers on the nodelet's `landmarks` input that a publisher sees after a
// wait long enough for a running nodelet to connect.
std::uint32_t landmarksSubscribers(const std::string& nodelet) {
  ros::NodeHandle nh;
  ros::Publisher pub = nh.advertise<hapi_msgs::StereoLandmarks>(nodelet + "/landmarks", 1);
  waitFor([&] { return pub.getNumSubscribers() > 0; }, 3.0);
  return pub.getNumSubscribers();
}

bool load(const std::string& name) {
  nodelet::NodeletLoad srv;
  srv.request.name = name;
  srv.request.type = "hapi_eskf/EskfNodelet";
  const bool called = ros::service::call("/manager/load_nodelet", srv);
  return called && srv.response.success;
}
std::vector<std::string> loaded() {
  nodelet::NodeletList srv;
  if (!ros::service::call("/manager/list", srv)) return {"<manager not answering>"};
  return srv.response.nodelets;
}
bool isLoaded(const std::string& name) {
  const auto l = loaded();
  return std::find(l.begin(), l.end(), name) != l.end();
}

}  // namespace

TEST(EskfNodeletStartup, InvalidParametersLeaveTheNodeletInertWithAClearError) {
  struct Case {
    std::string name, expected;
  };
  ros::param::set("/bad_rate/map_publish_rate", 0.0);
  ros::param::set("/bad_type/max_landmarks", std::string("many"));
  ros::param::set("/bad_backend/backend", std::string("gpu"));
  ros::param::set("/bad_frames/camera_frame", std::string("map"));  // = world_frame
  ros::param::set("/bad_filter/gate_chi2", -1.0);
  const std::vector<Case> cases = {
      {"/bad_rate", "~map_publish_rate must be in (0, 100] Hz"},
      {"/bad_type", "parameter ~max_landmarks has the wrong type"},
      {"/bad_backend", "~backend must be 'cpu' or 'cuda', got 'gpu'"},
      {"/bad_frames", "~camera_frame must differ from ~world_frame"},
      {"/bad_filter", "gate_chi2"},
  };
  for (const Case& c : cases) {
    EXPECT_TRUE(load(c.name)) << c.name << ": an invalid parameter must leave the nodelet loaded (inert)";
    EXPECT_TRUE(logged(rosgraph_msgs::Log::FATAL, "invalid parameters: " + c.expected)) << c.name;
    EXPECT_TRUE(isLoaded(c.name)) << c.name;
    EXPECT_TRUE(reportsNotRunning(c.name)) << c.name << ": no ERROR \"not running\" on /diagnostics";
    EXPECT_EQ(landmarksSubscribers(c.name), 0u) << c.name << " subscribed to its input despite an invalid parameter";
  }
  // The manager survived every refusal and still loads a valid nodelet; a
  // misspelled name does not stop it but is named in a warning.
  ros::param::set("/good/max_landmark", 100);
  ros::param::set("/good/output_dir", std::string("/tmp"));
  EXPECT_TRUE(load("/good"));
  EXPECT_TRUE(isLoaded("/good"));
  EXPECT_TRUE(logged(rosgraph_msgs::Log::WARN, "unknown parameter(s) ignored: ~max_landmark ("));
  // The check above can see a subscriber: the valid nodelet has one.
  EXPECT_EQ(landmarksSubscribers("/good"), 1u);
}

// A pool the device cannot hold (C alone for 200000 landmarks: 2.9 TB) is a
// start-up failure with the memory needed and available, not a crash at the
// first frame or a half-started node (without a GPU: the same failure,
// saying why CUDA is unusable).
TEST(EskfNodeletStartup, CudaPoolThatDoesNotFitIsFatalWithTheMemoryFigures) {
  std::string why;
  const bool cuda = hapi_eskf::cudaBackendAvailable(hapi_eskf::EskfSettings().cuda_device, &why);
  ros::param::set("/cuda_too_big/backend", std::string("cuda"));
  ros::param::set("/cuda_too_big/max_landmarks", 200000);
  ros::param::set("/cuda_too_big/allow_cpu_fallback", false);
  EXPECT_TRUE(load("/cuda_too_big"));
  EXPECT_TRUE(isLoaded("/cuda_too_big"));
  EXPECT_TRUE(logged(rosgraph_msgs::Log::FATAL, "~backend=cuda cannot run"));
  if (cuda) EXPECT_TRUE(logged(rosgraph_msgs::Log::FATAL, "free of"));
  EXPECT_TRUE(reportsNotRunning("/cuda_too_big"));
  EXPECT_EQ(landmarksSubscribers("/cuda_too_big"), 0u) << "/cuda_too_big subscribed with a pool the GPU cannot hold";
}

TEST(EskfNodeletStartup, CudaWithoutDeviceIsFatalOrAnAnnouncedCpuFallback) {
  std::string why;
  const bool cuda = hapi_eskf::cudaBackendAvailable(hapi_eskf::EskfSettings().cuda_device, &why);
  std::printf("[startup rostest] CUDA backend available: %s (%s)\n", cuda ? "yes" : "no", why.c_str());

  ros::param::set("/cuda_strict/backend", std::string("cuda"));
  ros::param::set("/cuda_strict/allow_cpu_fallback", false);
  EXPECT_TRUE(load("/cuda_strict"));
  EXPECT_TRUE(isLoaded("/cuda_strict"));
  if (!cuda) {
    EXPECT_TRUE(logged(rosgraph_msgs::Log::FATAL, "~allow_cpu_fallback is false"));
    EXPECT_TRUE(reportsNotRunning("/cuda_strict"));
    EXPECT_EQ(landmarksSubscribers("/cuda_strict"), 0u) << "/cuda_strict subscribed without a usable GPU";
  } else {
    EXPECT_EQ(landmarksSubscribers("/cuda_strict"), 1u) << "/cuda_strict does not run despite a usable GPU";
  }

  ros::param::set("/cuda_fallback/backend", std::string("cuda"));
  ros::param::set("/cuda_fallback/allow_cpu_fallback", true);
  ros::param::set("/cuda_fallback/diagnostics_period", 0.2);
  ASSERT_TRUE(load("/cuda_fallback"));
  if (!cuda) EXPECT_TRUE(logged(rosgraph_msgs::Log::WARN, "FALLING BACK TO THE CPU BACKEND"));

  // It runs: frames in, odometry out, and /diagnostics names the backend used.
  ros::NodeHandle nh;
  std::size_t n_odom = 0;
  ros::Subscriber s = nh.subscribe<nav_msgs::Odometry>("/cuda_fallback/odom", 10, [&](const nav_msgs::Odometry::ConstPtr&) {
    std::lock_guard<std::mutex> lk(mu);
    ++n_odom;
  });
  ros::Publisher pub = nh.advertise<hapi_msgs::StereoLandmarks>("/cuda_fallback/landmarks", 10);
  ASSERT_TRUE(waitFor([&] { return pub.getNumSubscribers() > 0 && s.getNumPublishers() > 0; }, 20.0));
  hapi_eskf_test::SyntheticScene scene;
  const ros::Time t0 = ros::Time::now();
  for (int i = 1; i <= 5; ++i) {
    pub.publish(scene.frame(0.05 * i, t0 + ros::Duration(0.05 * i), "stereo_left_optical_frame"));
    ros::WallDuration(0.1).sleep();
  }
  EXPECT_TRUE(waitFor([&] {
    std::lock_guard<std::mutex> lk(mu);
    return n_odom > 0;
  }, 20.0));
  ASSERT_TRUE(waitFor([] { return diagValue("cuda_fallback", "backend").rfind("none", 0) != 0 &&
                                  !diagValue("cuda_fallback", "backend").empty(); }, 10.0));
  const std::string backend = diagValue("cuda_fallback", "backend");
  std::printf("[startup rostest] /cuda_fallback runs on backend '%s'\n", backend.c_str());
  if (cuda)
    EXPECT_NE(backend.find("cuda"), std::string::npos) << backend;
  else
    EXPECT_NE(backend.find("cpu"), std::string::npos) << backend;
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_eskf_nodelet_startup");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(2);
  spinner.start();
  ros::Subscriber s1 = nh.subscribe("/rosout", 1000, onLog);  // rostest runs no rosout node: listen to the nodes directly
  ros::Subscriber s2 = nh.subscribe("/diagnostics", 100, onDiag);
  // Connected to the manager's /rosout (our own node is the other publisher).
  waitFor([&] { return s1.getNumPublishers() >= 2; }, 20.0);
  ros::WallDuration(0.5).sleep();
  ros::service::waitForService("/manager/load_nodelet", 20000);
  const int rc = RUN_ALL_TESTS();
  spinner.stop();
  return rc;
}
