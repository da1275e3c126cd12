// Settings of the Graph SLAM back end (docs/DESIGN.md "Graph SLAM"), declared
// once in graph_settings.def.
#pragma once

#include "hapi_eskf/field_table.hpp"

#include <string>
#include <type_traits>

namespace hapi_eskf {
namespace graph {

enum class RobustLoss { kNone, kHuber, kCauchy };

}  // namespace graph

template <>
struct EnumNames<graph::RobustLoss> {
  static constexpr EnumName<graph::RobustLoss> kNames[] = {
      {graph::RobustLoss::kNone, "none"}, {graph::RobustLoss::kHuber, "huber"}, {graph::RobustLoss::kCauchy, "cauchy"}};
};

namespace graph {

struct GraphSettings {
#define HAPI_FIELD(type, name, default_value, range, unit, doc) type name = default_value;
#include "hapi_eskf/graph/graph_settings.def"
#undef HAPI_FIELD

  std::string validate() const;  // empty when valid
};

template <typename Settings, typename Visitor,
          typename = std::enable_if_t<std::is_same<std::remove_const_t<Settings>, GraphSettings>::value>>
void forEachField(Settings& s, Visitor&& visit) {
#define HAPI_FIELD(type, name, default_value, range, unit, doc) visit(FieldInfo{#name, range, unit, doc}, s.name);
#include "hapi_eskf/graph/graph_settings.def"
#undef HAPI_FIELD
}

std::string setFieldFromText(GraphSettings* s, const std::string& name, const std::string& value);

}  // namespace graph
}  // namespace hapi_eskf
