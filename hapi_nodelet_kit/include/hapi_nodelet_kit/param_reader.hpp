// ParamReader: reads a nodelet's private (~) parameters once at start-up, with
// the checks ros::NodeHandle::param() does not make.
//
// Why: NodeHandle::param() silently returns the default when the stored value
// has another type ("max_depth: '20'" or "landmarks_per_frame: 2e2"), and
// nothing notices a misspelled name. Both would make a robot run with a
// configuration nobody asked for. The reader therefore
//  * reads through XmlRpc types: a value of the wrong type is an ERROR (the
//    field keeps its default); an integer is accepted for a double ("20");
//  * records every name it was asked for, so the list of known names is the
//    code itself and cannot drift from it;
//  * collects all errors and warnings instead of stopping at the first, so one
//    start-up shows every mistake;
//  * lists the names set under ~ that nothing read (typos), ignoring
//    sub-namespaces (image_transport plugins' own parameters) and
//    diagnostic_updater's own ~diagnostic_period;
//  * keeps a renamed parameter's old name working (readRenamed): a warning
//    when only the old name is set, an error when both are set and differ.
// Range checks belong to the caller (they are part of each parameter's
// declaration); it reports violations with error().
//
// Typical use in onInit (the start-up failure policy: startup_failure.hpp):
//   hapi_nodelet_kit::ParamReader r(getPrivateNodeHandle());
//   r.read("queue_size", &p.queue_size);
//   if (p.queue_size < 1) r.error("~queue_size must be >= 1, got ...");
//   r.warnAboutUnknown("config/frontend.yaml");
//   for (auto& w : r.warnings()) NODELET_WARN("%s", w.c_str());
//   if (!r.ok()) return failure.refuse(..., "invalid parameters", r.errors());
//
// Supported types: bool, int, double, std::string. Not thread-safe (one
// reader per onInit).
#pragma once

#include "hapi_nodelet_kit/param_source.hpp"

#include <memory>
#include <set>
#include <string>
#include <vector>

namespace hapi_nodelet_kit {

class ParamReader {
 public:
  // Reads the parameter server below the namespace of `private_nh`.
  explicit ParamReader(const ros::NodeHandle& private_nh);
  // Reads any other source (tests).
  explicit ParamReader(std::unique_ptr<ParamSource> source);
  ~ParamReader();

  // Reads ~name into *value (bool, int, double, std::string, and
  // std::vector<double> from a list of numbers). Returns true when it is set
  // with a usable type
  // (*value updated); false when it is not set (*value keeps its default) or
  // has the wrong type (an error is recorded, *value keeps its default).
  template <typename T>
  bool read(const std::string& name, T* value);

  // A parameter renamed from `old_name` to `name`. Only ~name set: as read().
  // Only ~old_name set: its value is used and a deprecation warning recorded.
  // Both set: the same value gives the warning, different values an error
  // (which one was meant is unknown). Returns as read().
  template <typename T>
  bool readRenamed(const std::string& name, const std::string& old_name, T* value);

  // A name read by someone else (a library reading the same namespace), so
  // that warnAboutUnknown() does not report it.
  void markKnown(const std::string& name);

  // Records a problem found by the caller (a value out of its range); the
  // message should name the parameter with its ~ and the allowed range.
  void error(const std::string& message);
  void warn(const std::string& message);

  // Records one warning naming every parameter directly under ~ that no
  // read()/readRenamed()/markKnown() asked for: "unknown parameter(s)
  // ignored: ~a, ~b (misspelled? every parameter is listed in <listed_in>)".
  // Call after all reads. Returns those names (empty: nothing recorded).
  std::vector<std::string> warnAboutUnknown(const std::string& listed_in);

  bool ok() const { return errors_.empty(); }
  const std::vector<std::string>& errors() const { return errors_; }
  const std::vector<std::string>& warnings() const { return warnings_; }
  const std::set<std::string>& knownNames() const { return known_; }

 private:
  // The value of ~name when set; records the name as known.
  bool fetch(const std::string& name, XmlRpc::XmlRpcValue* value);
  template <typename T>
  bool convert(const std::string& name, XmlRpc::XmlRpcValue& x, T* value);

  std::unique_ptr<ParamSource> source_;
  std::set<std::string> known_;
  std::vector<std::string> errors_, warnings_;
};

}  // namespace hapi_nodelet_kit
