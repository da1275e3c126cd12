// rostest (kit_ros.test): the parameter reader on the parameter server, and
// StartupFailure's FATAL lines and ERROR status repeated on /diagnostics.
#include "hapi_nodelet_kit/param_reader.hpp"
#include "hapi_nodelet_kit/startup_failure.hpp"

#include <diagnostic_msgs/DiagnosticArray.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>

#include <gtest/gtest.h>

#include <mutex>

namespace {

std::mutex mu;
std::vector<diagnostic_msgs::DiagnosticStatus> statuses;
std::vector<rosgraph_msgs::Log> logs;

template <typename P>
bool waitFor(P p, double s) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(s);
  while (ros::ok() && ros::WallTime::now() < end && !p()) ros::WallDuration(0.01).sleep();
  return p();
}

// diagnostic_updater's constructor announces itself once, before any task.
bool isStartupAnnouncement(const diagnostic_msgs::DiagnosticStatus& s) { return s.message == "Node starting up"; }

std::size_t count(const std::string& name) {
  std::lock_guard<std::mutex> lk(mu);
  std::size_t n = 0;
  for (const auto& s : statuses) n += s.name == name && !isStartupAnnouncement(s);
  return n;
}

void onDiagnostics(const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
  std::lock_guard<std::mutex> lk(mu);
  statuses.insert(statuses.end(), m->status.begin(), m->status.end());
}

void onLog(const rosgraph_msgs::Log::ConstPtr& m) {
  std::lock_guard<std::mutex> lk(mu);
  logs.push_back(*m);
}

}  // namespace

TEST(KitRos, ReaderSeesTheParameterServerBelowItsNamespaceOnly) {
  ros::param::set("/kit_test/queue_size", 5);
  ros::param::set("/kit_test/queue_sise", 5);
  ros::param::set("/kit_test/compressed/format", std::string("png"));  // a plugin's own
  ros::param::set("/kit_test/diagnostic_period", 0.5);
  ros::param::set("/kit_test_other/stray", 1);  // same prefix, another node
  hapi_nodelet_kit::ParamReader r{ros::NodeHandle("/kit_test")};
  int q = 0;
  double wrong = 0;
  EXPECT_TRUE(r.read("queue_size", &q));
  EXPECT_EQ(q, 5);
  ros::param::set("/kit_test/name_as_number", std::string("3.5"));
  EXPECT_FALSE(r.read("name_as_number", &wrong));
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.warnAboutUnknown("config/test.yaml"), std::vector<std::string>{"queue_sise"});
}

TEST(KitRos, StartupFailureLogsFatalAndRepeatsAnErrorStatus) {
  ros::NodeHandle nh;
  ros::NodeHandle pnh("/kit_refused");
  pnh.setParam("diagnostic_period", 0.2);
  const std::string name = "kit_refused: thing";
  {
    hapi_nodelet_kit::StartupFailure failure("thing", "kit_test");
    EXPECT_FALSE(failure.refused());
    failure.refuse(nh, pnh, "/kit_refused", "invalid parameters",
                   {"~x must be in [1, 12], got 20", "~y must be a string"});
    EXPECT_TRUE(failure.refused());
    EXPECT_EQ(failure.why(), "invalid parameters: ~x must be in [1, 12], got 20; ~y must be a string");
    // Repeated: a monitor that starts late still sees it.
    ASSERT_TRUE(waitFor([&] { return count(name) >= 3; }, 10.0)) << count(name) << " statuses";
    std::lock_guard<std::mutex> lk(mu);
    for (const auto& s : statuses) {
      if (s.name != name || isStartupAnnouncement(s)) continue;
      EXPECT_EQ(s.level, diagnostic_msgs::DiagnosticStatus::ERROR);
      EXPECT_EQ(s.message, "not running: " + failure.why());
      EXPECT_EQ(s.hardware_id, "kit_test");
    }
    bool fatal_x = false, fatal_summary = false;
    for (const auto& l : logs) {
      if (l.level != rosgraph_msgs::Log::FATAL) continue;
      fatal_x |= l.msg == "invalid parameters: ~x must be in [1, 12], got 20";
      fatal_summary |= l.msg.find("/kit_refused does not run (invalid parameters)") != std::string::npos;
    }
    EXPECT_TRUE(fatal_x);
    EXPECT_TRUE(fatal_summary);
  }
  // Destroyed with its nodelet: the reports stop.
  ros::WallDuration(0.5).sleep();
  const std::size_t after = count(name);
  ros::WallDuration(1.0).sleep();
  EXPECT_EQ(count(name), after);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_kit_ros");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(2);
  spinner.start();
  ros::Subscriber d = nh.subscribe("/diagnostics", 100, onDiagnostics);
  // rostest runs no rosout node: listen to our own /rosout directly.
  ros::Subscriber l = nh.subscribe("/rosout", 100, onLog);
  waitFor([&] { return l.getNumPublishers() >= 1; }, 10.0);
  const int rc = RUN_ALL_TESTS();
  spinner.stop();
  return rc;
}
