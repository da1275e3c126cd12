// PipelineParams' declarations: one entry per field, unique names, ranges
// checked with messages that name the parameter and its range, relations.
#include "hapi_frontend/cpu_stereo_matcher.hpp"
#include "hapi_frontend/opencv_extractors.hpp"
#include "hapi_frontend/pipeline_params.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>

using namespace hapi_frontend;

namespace {

// Records each declaration's name and the field's address.
class Lister : public ParamVisitor {
 public:
  void visit(const ParamSpec& s, bool& v) override { add(s, &v); }
  void visit(const ParamSpec& s, int& v) override { add(s, &v); }
  void visit(const ParamSpec& s, double& v) override { add(s, &v); }
  void visit(const ParamSpec& s, std::string& v) override { add(s, &v); }
  std::vector<std::string> names, internal;
  std::set<const void*> fields;

 private:
  void add(const ParamSpec& s, const void* field) {
    (s.internal ? internal : names).push_back(s.name);
    fields.insert(field);
  }
};

bool has(const std::vector<std::string>& problems, const std::string& text) {
  for (const auto& p : problems)
    if (p == text) return true;
  return false;
}

}  // namespace

TEST(PipelineParams, EveryFieldIsDeclaredOnceUnderItsRosName) {
  PipelineParams p;
  Lister l;
  p.visit(l);
  EXPECT_EQ(l.names, (std::vector<std::string>{
                         "detector", "use_gpu", "landmarks_per_frame", "detector_features", "fast_threshold",
                         "pyramid_levels", "downscale", "rectified_input", "pixel_sigma", "min_depth", "max_depth",
                         "max_epipolar_px", "min_disparity", "max_disparity", "match_ratio", "match_max_hamming",
                         "match_cross_check", "refine_min_zncc"}));
  EXPECT_EQ(l.internal, (std::vector<std::string>{"refine_subpixel", "refine_half_patch", "refine_radius"}));
  EXPECT_EQ(l.fields.size(), l.names.size() + l.internal.size());  // no field declared twice
}

TEST(PipelineParams, DefaultsSatisfyTheirDeclarations) {
  EXPECT_TRUE(PipelineParams().problems().empty());
  EXPECT_EQ(PipelineParams().validate(), "");
}

TEST(PipelineParams, RangeMessagesNameParameterRangeAndUnit) {
  PipelineParams p;
  p.pyramid_levels = 12;
  EXPECT_TRUE(p.problems().empty());
  p.pyramid_levels = 13;
  EXPECT_TRUE(has(p.problems(), "pyramid_levels must be in [1, 12], got 13"));
  p = PipelineParams();
  p.pixel_sigma = 0;
  EXPECT_TRUE(has(p.problems(), "pixel_sigma must be > 0 px, got 0"));
  p = PipelineParams();
  p.match.ratio = 1.5;
  EXPECT_TRUE(has(p.problems(), "match_ratio must be in (0, 1], got 1.5"));
  p = PipelineParams();
  p.max_depth = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(has(p.problems(), "max_depth must be > 0 m, got inf"));
  p = PipelineParams();
  p.detector = "sift";
  EXPECT_TRUE(has(p.problems(), "detector must be one of orb, akaze, got 'sift'"));
  p = PipelineParams();
  p.refine_radius = 0;  // internal values are checked too
  EXPECT_TRUE(has(p.problems(), "refine_radius must be in [1, 30] px, got 0"));
}

TEST(PipelineParams, RelationsBetweenFields) {
  PipelineParams p;
  p.detector_features = 100;
  p.landmarks_per_frame = 200;
  EXPECT_TRUE(has(p.problems(), "detector_features must be >= landmarks_per_frame, got 100 and 200"));
  p = PipelineParams();
  p.match.min_disparity = 300;
  EXPECT_TRUE(has(p.problems(), "min_disparity must be < max_disparity, got 300 and 256"));
  p = PipelineParams();
  p.match.min_disparity = -1;
  EXPECT_TRUE(has(p.problems(), "min_disparity must be >= 0 px, got -1"));
  // All problems at once, joined by validate().
  p.pixel_sigma = -1;
  EXPECT_EQ(p.problems().size(), 2u);
  EXPECT_EQ(p.validate(), "pixel_sigma must be > 0 px, got -1; min_disparity must be >= 0 px, got -1");
}

// The pipeline asks its extractor and matcher whether they ran on the GPU;
// the CPU classes say no.
// The offline tools' name=value: by ROS name, typed, inside the declared
// range, the field unchanged on any error.
TEST(PipelineParams, SetFromTextTakesNamesTypesAndRanges) {
  PipelineParams p;
  EXPECT_EQ(setFromText(&p, "fast_threshold", "8"), "");
  EXPECT_EQ(p.fast_threshold, 8);
  EXPECT_EQ(setFromText(&p, "refine_min_zncc", "0.8"), "");
  EXPECT_DOUBLE_EQ(p.refine_min_zncc, 0.8);
  EXPECT_EQ(setFromText(&p, "use_gpu", "true"), "");
  EXPECT_TRUE(p.use_gpu);
  EXPECT_EQ(setFromText(&p, "detector", "akaze"), "");
  EXPECT_EQ(p.detector, "akaze");

  EXPECT_NE(setFromText(&p, "fast_threshold", "300").find("fast_threshold"), std::string::npos);
  EXPECT_NE(setFromText(&p, "fast_threshold", "8.5").find("whole number"), std::string::npos);
  EXPECT_NE(setFromText(&p, "refine_min_zncc", "high").find("a number"), std::string::npos);
  EXPECT_NE(setFromText(&p, "use_gpu", "yes").find("true or false"), std::string::npos);
  EXPECT_NE(setFromText(&p, "detector", "sift").find("one of"), std::string::npos);
  EXPECT_NE(setFromText(&p, "no_such_parameter", "1").find("unknown parameter"), std::string::npos);
  EXPECT_EQ(p.fast_threshold, 8);
  EXPECT_DOUBLE_EQ(p.refine_min_zncc, 0.8);
  EXPECT_TRUE(p.use_gpu);
  EXPECT_EQ(p.detector, "akaze");
}

TEST(GpuProperty, CpuImplementationsReportCpu) {
  EXPECT_FALSE(AkazeExtractor().usingGpu());
  EXPECT_FALSE(OpenCvOrbExtractor().usingGpu());
  EXPECT_FALSE(CpuStereoMatcher().usingGpu());
  EXPECT_FALSE(makeStereoMatcher(false)->usingGpu());
}
