// Where a ParamReader's values come from: the ROS parameter server under a
// nodelet's private namespace (RosParamSource), or an in-memory map in tests
// (the reader's rules are then checked without a ROS master).
#pragma once

#include <ros/node_handle.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include <string>
#include <vector>

namespace hapi_nodelet_kit {

class ParamSource {
 public:
  virtual ~ParamSource() = default;
  // The value of ~name (name relative to the private namespace); false when
  // it is not set.
  virtual bool get(const std::string& name, XmlRpc::XmlRpcValue* value) const = 0;
  // Every parameter set under ~, relative to it; parameters in
  // sub-namespaces keep their path ("compressed/format").
  virtual std::vector<std::string> names() const = 0;
  // The private namespace, for messages ("/stereo_frontend").
  virtual std::string privateNamespace() const = 0;
};

// The parameter server, below the namespace of `private_nh`.
class RosParamSource : public ParamSource {
 public:
  explicit RosParamSource(const ros::NodeHandle& private_nh) : nh_(private_nh) {}
  bool get(const std::string& name, XmlRpc::XmlRpcValue* value) const override;
  std::vector<std::string> names() const override;
  std::string privateNamespace() const override { return nh_.getNamespace(); }

 private:
  ros::NodeHandle nh_;
};

}  // namespace hapi_nodelet_kit
