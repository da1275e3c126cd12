// ParamReader on an in-memory source: XmlRpc types, known names, renamed
// parameters, unknown names; readTimeJumpReset.
#include "hapi_nodelet_kit/param_reader.hpp"
#include "hapi_nodelet_kit/time_jump_reset_param.hpp"

#include <gtest/gtest.h>

#include <map>

using hapi_nodelet_kit::ParamReader;
using hapi_nodelet_kit::ParamSource;

namespace {

class MapSource : public ParamSource {
 public:
  explicit MapSource(std::map<std::string, XmlRpc::XmlRpcValue> values) : values_(std::move(values)) {}
  bool get(const std::string& name, XmlRpc::XmlRpcValue* value) const override {
    auto it = values_.find(name);
    if (it == values_.end()) return false;
    *value = it->second;
    return true;
  }
  std::vector<std::string> names() const override {
    std::vector<std::string> n;
    for (const auto& kv : values_) n.push_back(kv.first);
    return n;
  }
  std::string privateNamespace() const override { return "/test"; }

 private:
  std::map<std::string, XmlRpc::XmlRpcValue> values_;
};

ParamReader reader(std::map<std::string, XmlRpc::XmlRpcValue> values) {
  return ParamReader(std::make_unique<MapSource>(std::move(values)));
}

bool contains(const std::vector<std::string>& lines, const std::string& text) {
  for (const auto& l : lines)
    if (l.find(text) != std::string::npos) return true;
  return false;
}

}  // namespace

TEST(ParamReader, TypedReadsKeepTheDefaultWhenUnset) {
  auto r = reader({{"b", XmlRpc::XmlRpcValue(true)}, {"i", XmlRpc::XmlRpcValue(7)},
                   {"d", XmlRpc::XmlRpcValue(2.5)}, {"s", XmlRpc::XmlRpcValue("orb")}});
  bool b = false;
  int i = 0;
  double d = 0;
  std::string s;
  EXPECT_TRUE(r.read("b", &b));
  EXPECT_TRUE(r.read("i", &i));
  EXPECT_TRUE(r.read("d", &d));
  EXPECT_TRUE(r.read("s", &s));
  EXPECT_TRUE(b);
  EXPECT_EQ(i, 7);
  EXPECT_EQ(d, 2.5);
  EXPECT_EQ(s, "orb");
  int unset = 13;
  EXPECT_FALSE(r.read("unset", &unset));
  EXPECT_EQ(unset, 13);
  EXPECT_TRUE(r.ok());
  EXPECT_EQ(r.knownNames(), (std::set<std::string>{"b", "i", "d", "s", "unset"}));
}

TEST(ParamReader, IntegerIsANumberButNothingElseConverts) {
  auto r = reader({{"d", XmlRpc::XmlRpcValue(20)}, {"i_from_double", XmlRpc::XmlRpcValue(2e2)},
                   {"b_from_int", XmlRpc::XmlRpcValue(1)}, {"d_from_string", XmlRpc::XmlRpcValue("not a number")},
                   {"s_from_int", XmlRpc::XmlRpcValue(3)}});
  double d = 0;
  EXPECT_TRUE(r.read("d", &d));
  EXPECT_EQ(d, 20.0);
  int i = 5;
  bool b = false;
  double d2 = 0.24;
  std::string s = "raw";
  EXPECT_FALSE(r.read("i_from_double", &i));
  EXPECT_FALSE(r.read("b_from_int", &b));
  EXPECT_FALSE(r.read("d_from_string", &d2));
  EXPECT_FALSE(r.read("s_from_int", &s));
  EXPECT_EQ(i, 5);  // defaults kept
  EXPECT_FALSE(b);
  EXPECT_EQ(d2, 0.24);
  EXPECT_EQ(s, "raw");
  ASSERT_EQ(r.errors().size(), 4u);  // all collected, not just the first
  EXPECT_TRUE(contains(r.errors(),
                       "parameter ~i_from_double has the wrong type: expected an integer, got the double 200"));
  EXPECT_TRUE(contains(r.errors(), "parameter ~b_from_int has the wrong type: expected a boolean"));
  EXPECT_TRUE(contains(r.errors(), "parameter ~d_from_string has the wrong type: expected a number, "
                                   "got the string 'not a number'"));
  EXPECT_TRUE(contains(r.errors(), "parameter ~s_from_int has the wrong type: expected a string, got the integer 3"));
}

TEST(ParamReader, UnknownNamesIgnoreSubNamespacesAndDiagnosticPeriod) {
  auto r = reader({{"queue_size", XmlRpc::XmlRpcValue(5)}, {"queue_sise", XmlRpc::XmlRpcValue(5)},
                   {"max_landmark", XmlRpc::XmlRpcValue(100)}, {"compressed/format", XmlRpc::XmlRpcValue("png")},
                   {"diagnostic_period", XmlRpc::XmlRpcValue(0.5)}, {"library_param", XmlRpc::XmlRpcValue(1)}});
  int q = 0;
  r.read("queue_size", &q);
  r.markKnown("library_param");
  const auto unknown = r.warnAboutUnknown("config/x.yaml");
  EXPECT_EQ(unknown, (std::vector<std::string>{"max_landmark", "queue_sise"}));
  ASSERT_EQ(r.warnings().size(), 1u);
  EXPECT_EQ(r.warnings()[0], "unknown parameter(s) ignored: ~max_landmark, ~queue_sise "
                             "(misspelled? every parameter is listed in config/x.yaml)");
  EXPECT_TRUE(r.ok());  // a warning, not an error

  auto clean = reader({{"a", XmlRpc::XmlRpcValue(1)}});
  int a = 0;
  clean.read("a", &a);
  EXPECT_TRUE(clean.warnAboutUnknown("config/x.yaml").empty());
  EXPECT_TRUE(clean.warnings().empty());
}

TEST(ParamReader, RenamedParameter) {
  int v = 200;
  auto only_new = reader({{"landmarks_per_frame", XmlRpc::XmlRpcValue(150)}});
  EXPECT_TRUE(only_new.readRenamed("landmarks_per_frame", "max_landmarks", &v));
  EXPECT_EQ(v, 150);
  EXPECT_TRUE(only_new.warnings().empty());

  v = 200;
  auto only_old = reader({{"max_landmarks", XmlRpc::XmlRpcValue(120)}});
  EXPECT_TRUE(only_old.readRenamed("landmarks_per_frame", "max_landmarks", &v));
  EXPECT_EQ(v, 120);
  EXPECT_TRUE(only_old.ok());
  EXPECT_TRUE(contains(only_old.warnings(), "~max_landmarks is deprecated, it was renamed to ~landmarks_per_frame"));
  EXPECT_TRUE(only_old.warnAboutUnknown("y").empty());  // the old name is known

  v = 200;
  auto same = reader({{"max_landmarks", XmlRpc::XmlRpcValue(120)}, {"landmarks_per_frame", XmlRpc::XmlRpcValue(120)}});
  EXPECT_TRUE(same.readRenamed("landmarks_per_frame", "max_landmarks", &v));
  EXPECT_EQ(v, 120);
  EXPECT_TRUE(same.ok());
  EXPECT_EQ(same.warnings().size(), 1u);

  v = 200;
  auto conflict =
      reader({{"max_landmarks", XmlRpc::XmlRpcValue(-3)}, {"landmarks_per_frame", XmlRpc::XmlRpcValue(200)}});
  EXPECT_FALSE(conflict.readRenamed("landmarks_per_frame", "max_landmarks", &v));
  EXPECT_EQ(v, 200);
  ASSERT_EQ(conflict.errors().size(), 1u);
  EXPECT_EQ(conflict.errors()[0], "~max_landmarks = -3 and ~landmarks_per_frame = 200 are both set (~max_landmarks is "
                                  "deprecated, it was renamed to ~landmarks_per_frame): remove ~max_landmarks");

  auto bad_type = reader({{"max_landmarks", XmlRpc::XmlRpcValue("many")}});
  EXPECT_FALSE(bad_type.readRenamed("landmarks_per_frame", "max_landmarks", &v));
  EXPECT_TRUE(contains(bad_type.errors(), "parameter ~max_landmarks has the wrong type"));
}

TEST(ReadTimeJumpReset, DefaultRangeAndDeprecatedName) {
  auto unset = reader({});
  EXPECT_EQ(hapi_nodelet_kit::readTimeJumpReset(unset), 1.0);
  EXPECT_TRUE(unset.ok());
  EXPECT_EQ(unset.knownNames(), (std::set<std::string>{"time_jump_reset"}));

  auto set = reader({{"time_jump_reset", XmlRpc::XmlRpcValue(3)}});
  EXPECT_EQ(hapi_nodelet_kit::readTimeJumpReset(set), 3.0);

  auto negative = reader({{"time_jump_reset", XmlRpc::XmlRpcValue(-1.0)}});
  EXPECT_EQ(hapi_nodelet_kit::readTimeJumpReset(negative), 1.0);
  EXPECT_TRUE(contains(negative.errors(), "~time_jump_reset must be >= 0 s, got -1"));

  auto old_name = reader({{"max_backwards_jump", XmlRpc::XmlRpcValue(0.5)}});
  EXPECT_EQ(hapi_nodelet_kit::readTimeJumpReset(old_name, "max_backwards_jump"), 0.5);
  EXPECT_TRUE(old_name.ok());
  EXPECT_TRUE(contains(old_name.warnings(), "~max_backwards_jump is deprecated, it was renamed to ~time_jump_reset"));
}
