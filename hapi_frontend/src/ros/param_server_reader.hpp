// Reads each declared ROS private parameter of a settings struct through a
// hapi_nodelet_kit::ParamReader (internal core values are skipped; a renamed
// parameter is also read under its old name, with a warning). Shared by the
// front end's nodelets.
#pragma once

#include "hapi_frontend/param_spec.hpp"

#include <hapi_nodelet_kit/param_reader.hpp>

#include <string>

namespace hapi_frontend {

class ParamServerReader : public ParamVisitor {
 public:
  explicit ParamServerReader(hapi_nodelet_kit::ParamReader& r) : r_(r) {}
  void visit(const ParamSpec& spec, bool& value) override { read(spec, &value); }
  void visit(const ParamSpec& spec, int& value) override { read(spec, &value); }
  void visit(const ParamSpec& spec, double& value) override { read(spec, &value); }
  void visit(const ParamSpec& spec, std::string& value) override { read(spec, &value); }

 private:
  template <typename T>
  void read(const ParamSpec& spec, T* value) {
    if (spec.internal) return;
    if (spec.deprecated_name)
      r_.readRenamed(spec.name, spec.deprecated_name, value);
    else
      r_.read(spec.name, value);
  }
  hapi_nodelet_kit::ParamReader& r_;
};

}  // namespace hapi_frontend
