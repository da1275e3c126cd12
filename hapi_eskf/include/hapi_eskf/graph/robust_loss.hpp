// The robust loss of Graph SLAM's residuals (docs/DESIGN.md "Graph SLAM"):
// its own header because the filter's settings table (settings.hpp) names it
// too (graph_robust_loss).
#pragma once

#include "hapi_eskf/field_table.hpp"

namespace hapi_eskf {
namespace graph {

enum class RobustLoss { kNone, kHuber, kCauchy };

}  // namespace graph

template <>
struct EnumNames<graph::RobustLoss> {
  static constexpr EnumName<graph::RobustLoss> kNames[] = {
      {graph::RobustLoss::kNone, "none"}, {graph::RobustLoss::kHuber, "huber"}, {graph::RobustLoss::kCauchy, "cauchy"}};
};

}  // namespace hapi_eskf
