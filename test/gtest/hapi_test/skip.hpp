// Skips of the cores' gtests.
//
// HAPI_SKIP_WITHOUT_GPU(why): a test that needs a CUDA device skips without
// one, except where HAPI_REQUIRE_GPU=1 is set (the GPU machine:
// tools/device/*.sh): there the missing device is a failure, so a broken
// driver or an unseen card cannot pass as "0 tests run".
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>

namespace hapi_test {

// Printed by hapi_gtest_main.cpp when every test of the binary skipped;
// cmake/HapiCommon.cmake matches it (SKIP_REGULAR_EXPRESSION).
constexpr const char* kAllSkippedMarker = "[ HAPI ALL SKIPPED ]";

inline bool gpuRequired() {
  const char* v = std::getenv("HAPI_REQUIRE_GPU");
  return v != nullptr && std::strcmp(v, "1") == 0;
}

}  // namespace hapi_test

#define HAPI_SKIP_WITHOUT_GPU(why)                                              \
  do {                                                                          \
    if (::hapi_test::gpuRequired()) FAIL() << "HAPI_REQUIRE_GPU=1: " << (why);  \
    GTEST_SKIP() << (why);                                                      \
  } while (0)
