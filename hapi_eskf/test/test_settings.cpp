// The settings table (settings.hpp, field_table.hpp): defaults valid,
// ranges enforced at their ends, every field settable from its text form,
// enum names round-trip. config/eskf.yaml against the table:
// test/ros/params_rostest.cpp.
#include "hapi_eskf/settings.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>
#include <string>

namespace hapi_eskf {
namespace {

TEST(SettingsTable, DefaultsAreValidAndNamesUnique) {
  const EskfSettings s;
  EXPECT_EQ(s.validate(), "");
  std::set<std::string> names;
  int n = 0;
  forEachField(s, [&](const FieldInfo& f, const auto& v) {
    ++n;
    EXPECT_TRUE(names.insert(f.name).second) << f.name;
    EXPECT_GT(std::string(f.doc).size(), 10u) << f.name;
    EXPECT_EQ(rangeError(f, v), "") << f.name;
  });
  EXPECT_EQ(n, static_cast<int>(names.size()));
  for (const char* name : {"max_landmarks", "backend", "cuda_stage_times", "ransac_iterations",
                           "initial_sigma_angular_velocity"})
    EXPECT_EQ(names.count(name), 1u) << name;
}

TEST(SettingsTable, EveryFieldRoundTripsThroughItsTextForm) {
  const EskfSettings defaults;
  forEachField(defaults, [&](const FieldInfo& f, const auto& def) {
    EskfSettings s;
    EXPECT_EQ(setFieldFromText(&s, f.name, valueText(def)), "") << f.name;
    bool same = false;
    forEachField(s, [&](const FieldInfo& g, const auto& v) {
      if (std::string(g.name) == f.name) same = valueText(v) == valueText(def);
    });
    EXPECT_TRUE(same) << f.name;
  });
  EskfSettings s;
  EXPECT_EQ(setFieldFromText(&s, "ransac_iterations", "0"), "");
  EXPECT_EQ(s.ransac_iterations, 0);
  EXPECT_EQ(setFieldFromText(&s, "relocalise_gap", "2.5"), "");
  EXPECT_EQ(s.relocalise_gap, 2.5);
  EXPECT_EQ(setFieldFromText(&s, "cuda_stage_times", "true"), "");
  EXPECT_TRUE(s.cuda_stage_times);
  EXPECT_EQ(setFieldFromText(&s, "cuda_rank_update", "gemm"), "");
  EXPECT_EQ(s.cuda_rank_update, CudaRankUpdate::kPanelGemm);
  // Refused: unknown names, partial numbers, unknown enum names (value unchanged).
  EXPECT_NE(setFieldFromText(&s, "max_landmark", "10").find("unknown setting 'max_landmark'"), std::string::npos);
  EXPECT_NE(setFieldFromText(&s, "max_landmarks", "12x").find("an integer"), std::string::npos);
  EXPECT_NE(setFieldFromText(&s, "gate_chi2", "").find("a number"), std::string::npos);
  EXPECT_EQ(setFieldFromText(&s, "cuda_solve", "fast"), "cuda_solve must be 'auto', 'trsm' or 'inverse', got 'fast'");
  EXPECT_EQ(s.cuda_solve, CudaSolve::kAuto);
  EXPECT_EQ(s.max_landmarks, EskfSettings().max_landmarks);
}

TEST(SettingsTable, RangesAreCheckedAtTheirEnds) {
  EskfSettings s;
  s.measurement_angular_sigma = 0.0;  // [0, 0.1) rad
  EXPECT_EQ(s.validate(), "");
  s.measurement_angular_sigma = 0.1;
  EXPECT_EQ(s.validate(), "measurement_angular_sigma must be in [0, 0.1) rad, got 0.1");
  s = EskfSettings();
  s.match_ratio = 1.0;  // (0, 1]
  EXPECT_EQ(s.validate(), "");
  s.match_ratio = 0.0;
  EXPECT_EQ(s.validate(), "match_ratio must be in (0, 1], got 0");
  s = EskfSettings();
  s.max_landmarks = 200000;  // [1, 200000]
  EXPECT_EQ(s.validate(), "");
  s.max_landmarks = 200001;
  EXPECT_EQ(s.validate(), "max_landmarks must be in [1, 200000], got 200001");
  s = EskfSettings();
  s.gate_chi2 = std::numeric_limits<double>::infinity();  // > 0 and finite
  EXPECT_NE(s.validate().find("gate_chi2 must be > 0"), std::string::npos);
  s = EskfSettings();
  s.relocalise_gap = std::nan("");
  EXPECT_NE(s.validate().find("relocalise_gap must be >= 0 s"), std::string::npos);
  s = EskfSettings();
  s.cuda_device = -1;
  EXPECT_NE(s.validate().find("cuda_device"), std::string::npos);
  // Between fields.
  s = EskfSettings();
  s.max_landmarks = 50;  // below the default bootstrap_landmarks
  EXPECT_EQ(s.validate(), "bootstrap_landmarks must be in [0, max_landmarks], got 100");
  s.bootstrap_landmarks = 50;
  EXPECT_EQ(s.validate(), "");
}

TEST(SettingsTable, EnumNamesAndDescriptions) {
  EXPECT_EQ(enumChoices<BackendKind>(), "'cpu' or 'cuda'");
  EXPECT_EQ(enumChoices<CudaRankUpdate>(), "'auto', 'syrk', 'gemm' or 'recursive'");
  CudaSolve v = CudaSolve::kAuto;
  EXPECT_TRUE(enumFromString("inverse", &v));
  EXPECT_EQ(v, CudaSolve::kInverse);
  EXPECT_STREQ(enumToString(v), "inverse");
  const EskfSettings s;
  std::string gap, backend;
  forEachField(s, [&](const FieldInfo& f, const auto& v) {
    if (std::string(f.name) == "relocalise_gap") gap = describeField(f, v);
    if (std::string(f.name) == "backend") backend = describeField(f, v);
  });
  EXPECT_EQ(gap.rfind("relocalise_gap (default 1, >= 0, s): ", 0), 0u) << gap;
  EXPECT_EQ(backend.rfind("backend (default cpu, 'cpu' or 'cuda'): ", 0), 0u) << backend;
}

}  // namespace
}  // namespace hapi_eskf
