// main() of the cores' gtests (hapi_add_core_gtest, cmake/HapiCommon.cmake).
// gtest exits 0 when every test skipped (GTEST_SKIP: no CUDA device, a back
// end not built), which ctest would count as passed. This main prints
// kAllSkippedMarker then, and ctest's SKIP_REGULAR_EXPRESSION shows the entry
// as skipped; an entry with at least one test run and passed stays a pass.
#include "hapi_test/skip.hpp"

#include <gtest/gtest.h>

#include <iostream>

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  const int rc = RUN_ALL_TESTS();
  const testing::UnitTest& u = *testing::UnitTest::GetInstance();
  if (rc == 0 && u.test_to_run_count() > 0 && u.skipped_test_count() == u.test_to_run_count())
    std::cout << hapi_test::kAllSkippedMarker << " (" << u.skipped_test_count() << " tests)" << std::endl;
  return rc;
}
