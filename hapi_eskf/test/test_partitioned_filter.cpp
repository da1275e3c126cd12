// The partitioned CPU filter against the dense one (partitioned_filter_run.hpp).
#include "basic_settings.hpp"
#include "partitioned_filter_run.hpp"

#include <gtest/gtest.h>

namespace hapi_eskf {
namespace {

using testing_partitioned::runFilters;

TEST(PartitionedFilter, BasicIterationMatchesDenseFilter) { runFilters(testing_settings::basicFilter(), 150, 30); }

TEST(PartitionedFilter, TunedSettingsMatchDenseFilter) {
  EskfSettings s;  // RANSAC, bootstrap batch, re-detection noise as shipped
  runFilters(s, 150, 50);
}

// The staged flush (docs/DESIGN.md "Staged flush"): each flush's passive part
// over the next 3 updates, in the whole filter.
TEST(PartitionedFilter, StagedFlushMatchesDenseFilter) {
  EskfSettings s = testing_settings::basicFilter();
  s.partition_flush_shares = 3;
  runFilters(s, 150, 30);
}

// Background shares (docs/DESIGN.md "Background shares"): the shares run on
// the worker thread between processFrame calls.
TEST(PartitionedFilter, BackgroundSharesMatchDenseFilter) {
  EskfSettings s = testing_settings::basicFilter();
  s.partition_flush_shares = 2;
  s.partition_flush_background = true;
  runFilters(s, 150, 30);
}

}  // namespace
}  // namespace hapi_eskf
