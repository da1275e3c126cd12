// BackendFaultPolicy: restarts for transient faults, then the CPU backend
// (allow_cpu_fallback) or a stop; a creation failure gives up at once; a good
// frame ends the run of faults; the CPU backend itself never "falls back".
#include "hapi_eskf/covariance/backend_fault_policy.hpp"

#include <gtest/gtest.h>

namespace hapi_eskf {
namespace {

TEST(BackendFaultPolicy, RestartsThenFallsBackToCpuWhenAllowed) {
  BackendFaultPolicy p(true, 2);
  EXPECT_EQ(p.onFault(BackendKind::kCuda), FaultAction::kRestart);
  EXPECT_EQ(p.onFault(BackendKind::kCuda), FaultAction::kRestart);
  EXPECT_EQ(p.onFault(BackendKind::kCuda), FaultAction::kFallBackToCpu);
  EXPECT_EQ(p.consecutiveFaults(), 3);
}

TEST(BackendFaultPolicy, RestartsThenStopsWithoutFallback) {
  BackendFaultPolicy p(false, 2);
  EXPECT_EQ(p.onFault(BackendKind::kCuda), FaultAction::kRestart);
  EXPECT_EQ(p.onFault(BackendKind::kCuda), FaultAction::kRestart);
  EXPECT_EQ(p.onFault(BackendKind::kCuda), FaultAction::kStop);
}

TEST(BackendFaultPolicy, AGoodFrameEndsTheRunOfFaults) {
  BackendFaultPolicy p(false, 1);
  EXPECT_EQ(p.onFault(BackendKind::kCuda), FaultAction::kRestart);
  p.onSuccess();
  EXPECT_EQ(p.consecutiveFaults(), 0);
  EXPECT_EQ(p.onFault(BackendKind::kCuda), FaultAction::kRestart);
  EXPECT_EQ(p.onFault(BackendKind::kCuda), FaultAction::kStop);
}

TEST(BackendFaultPolicy, CreationFailureGivesUpAtOnce) {
  EXPECT_EQ(BackendFaultPolicy(true).onCreateFailed(BackendKind::kCuda), FaultAction::kFallBackToCpu);
  EXPECT_EQ(BackendFaultPolicy(false).onCreateFailed(BackendKind::kCuda), FaultAction::kStop);
}

TEST(BackendFaultPolicy, TheCpuBackendStopsInsteadOfFallingBack) {
  BackendFaultPolicy p(true, 0);
  EXPECT_EQ(p.onFault(BackendKind::kCpu), FaultAction::kStop);
  EXPECT_EQ(p.onCreateFailed(BackendKind::kCpu), FaultAction::kStop);
}

}  // namespace
}  // namespace hapi_eskf
