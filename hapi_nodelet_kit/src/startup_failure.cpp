// StartupFailure (startup_failure.hpp): FATAL log lines and the repeated
// ERROR status of a nodelet that refuses to run.
#include "hapi_nodelet_kit/startup_failure.hpp"

#include <diagnostic_msgs/DiagnosticStatus.h>
#include <ros/console.h>

#include <algorithm>

namespace hapi_nodelet_kit {

StartupFailure::StartupFailure(std::string status_name, std::string hardware_id)
    : status_name_(std::move(status_name)), hardware_id_(std::move(hardware_id)) {}

StartupFailure::~StartupFailure() {
  // The timer callback uses updater_ and the fields: stop it first.
  timer_.stop();
}

void StartupFailure::refuse(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh,
                            const std::string& nodelet_name, const std::string& what,
                            const std::vector<std::string>& reasons) {
  std::string joined;
  for (const std::string& r : reasons) {
    // The same logger name as NODELET_FATAL uses (the nodelet's name).
    ROS_FATAL_NAMED(nodelet_name, "%s: %s", what.c_str(), r.c_str());
    joined += (joined.empty() ? "" : "; ") + r;
  }
  ROS_FATAL_NAMED(nodelet_name,
                  "%s does not run (%s): it stays loaded without subscribing and reports ERROR on /diagnostics; "
                  "fix the cause and load it again",
                  nodelet_name.c_str(), what.c_str());
  {
    std::lock_guard<std::mutex> lk(mu_);
    const std::string entry = joined.empty() ? what : what + ": " + joined;
    why_ += (why_.empty() ? "" : "; ") + entry;
    reasons_.insert(reasons_.end(), reasons.begin(), reasons.end());
  }
  if (updater_) return;  // already reporting
  updater_ = std::make_unique<diagnostic_updater::Updater>(nh, private_nh, nodelet_name);
  updater_->setHardwareID(hardware_id_);
  updater_->add(status_name_, this, &StartupFailure::produce);
  // Wall timer + force_update: the report continues while simulated time
  // pauses or jumps (a bag that is not playing).
  ros::NodeHandle timer_nh(nh);
  timer_ = timer_nh.createWallTimer(ros::WallDuration(std::max(0.1, updater_->getPeriod())),
                                    [this](const ros::WallTimerEvent&) { updater_->force_update(); });
  updater_->force_update();
}

bool StartupFailure::refused() const {
  std::lock_guard<std::mutex> lk(mu_);
  return !why_.empty();
}

std::string StartupFailure::why() const {
  std::lock_guard<std::mutex> lk(mu_);
  return why_;
}

void StartupFailure::produce(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  std::lock_guard<std::mutex> lk(mu_);
  stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR, "not running: " + why_);
  for (std::size_t i = 0; i < reasons_.size(); ++i) stat.add("reason " + std::to_string(i + 1), reasons_[i]);
}

}  // namespace hapi_nodelet_kit
