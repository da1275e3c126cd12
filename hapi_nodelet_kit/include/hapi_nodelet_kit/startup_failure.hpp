// StartupFailure: the start-up failure policy of every HAPI nodelet, written
// once. Applied when a parameter is invalid or a required resource (an
// image_transport plugin, a CUDA device that may not be replaced by the CPU,
// ...) is missing. README.md "Parameters" states it for users.
//
// The policy: the nodelet STAYS LOADED BUT INERT.
//  1. Every reason is logged as FATAL, "<what>: <reason>", each naming the
//     parameter and its allowed range, then one FATAL line saying that the
//     nodelet does not run.
//  2. /diagnostics carries ERROR "not running: <what>: <reasons>" under the
//     nodelet's usual status name ("<node>: <status_name>"), repeated every
//     diagnostic period (wall clock) for as long as the nodelet is loaded, so
//     a monitor that starts late (rqt_robot_monitor, the aggregator, a test)
//     still sees why.
//  3. The caller returns from onInit right after refuse(): no processing
//     subscription, no publisher, no worker thread. `rostopic info` of its
//     input shows no subscriber from it.
//
// Why not throw from onInit: nodelet's Loader::load() (nodelet/src/loader.cpp)
// catches the exception, logs ROS_ERROR "Failed to initialize nodelet", and
// destroys the nodelet; `nodelet load` then exits with an error and roslaunch
// reports the process as died. The reason would then only be in the manager's
// log (on the robot, in a distributed launch), nothing could ever appear on
// /diagnostics because the nodelet and its updater are gone, a destructor has
// to cope with a half-initialised object, and respawn="true" turns it into a
// restart loop. The inert nodelet keeps the reason visible where operators
// look, in the log and on /diagnostics.
//
// Use (the nodelet must not create its own diagnostic_updater for the same
// status name before it knows that start-up succeeded):
//   class MyNodelet : public nodelet::Nodelet {
//     hapi_nodelet_kit::StartupFailure startup_{"filter", "hapi_eskf"};
//     void onInit() override {
//       ...
//       if (!reader.ok())
//         return startup_.refuse(getNodeHandle(), getPrivateNodeHandle(), getName(),
//                                "invalid parameters", reader.errors());
//       ...  // only now: own updater, publishers, worker, subscriptions
//     }
//   };
// Destroying the StartupFailure stops its reports (declare it so that it is
// destroyed with the nodelet).
#pragma once

#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/node_handle.h>
#include <ros/wall_timer.h>

#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace hapi_nodelet_kit {

class StartupFailure {
 public:
  // status_name: the nodelet's own diagnostic task name ("stereo front end",
  // "filter"), so the same /diagnostics entry turns ERROR; hardware_id: as
  // the nodelet sets it.
  StartupFailure(std::string status_name, std::string hardware_id);
  ~StartupFailure();
  StartupFailure(const StartupFailure&) = delete;
  StartupFailure& operator=(const StartupFailure&) = delete;

  // Applies the policy (see above). nh/private_nh/nodelet_name: the nodelet's
  // getNodeHandle(), getPrivateNodeHandle(), getName() (the status is
  // published on nh's /diagnostics, the period read from
  // ~diagnostic_period). what: the kind of failure ("invalid parameters");
  // reasons: one line each, non-empty. Calling it again adds the new reasons.
  void refuse(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh, const std::string& nodelet_name,
              const std::string& what, const std::vector<std::string>& reasons);

  bool refused() const;
  // "<what>: <reason>; <reason>..." of every refuse() call, "" when none.
  std::string why() const;

 private:
  void produce(diagnostic_updater::DiagnosticStatusWrapper& stat);

  const std::string status_name_, hardware_id_;
  mutable std::mutex mu_;  // why_, reasons_ (the timer thread reads them)
  std::string why_;
  std::vector<std::string> reasons_;
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  ros::WallTimer timer_;
};

}  // namespace hapi_nodelet_kit
