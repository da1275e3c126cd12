// RosParamSource: the parameter server below a private node handle.
#include "hapi_nodelet_kit/param_source.hpp"

#include <ros/param.h>

namespace hapi_nodelet_kit {

bool RosParamSource::get(const std::string& name, XmlRpc::XmlRpcValue* value) const {
  return nh_.hasParam(name) && nh_.getParam(name, *value);
}

std::vector<std::string> RosParamSource::names() const {
  std::vector<std::string> all, mine;
  if (!ros::param::getParamNames(all)) return mine;  // no master: nothing to compare against
  const std::string prefix = nh_.getNamespace() + "/";
  for (const std::string& full : all)
    if (full.size() > prefix.size() && full.compare(0, prefix.size(), prefix) == 0)
      mine.push_back(full.substr(prefix.size()));
  return mine;
}

}  // namespace hapi_nodelet_kit
