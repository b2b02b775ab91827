// The plan's JSON reader and number writer (pipeline/plan_json.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "tiles/plan_json.hpp"

namespace {

using tincdt::tiles::detail::json_number;
using tincdt::tiles::detail::json_string;
using tincdt::tiles::detail::JsonError;
using tincdt::tiles::detail::JsonValue;
using Kind = JsonValue::Kind;

TEST(PlanJson, ReadsEveryKind) {
  const JsonValue v = JsonValue::parse(
      R"( {"a": [1, -2.5e3, true, false, null], "b": {"c": "x\"y\u00e9\n"}, "d": []} )");
  ASSERT_TRUE(v.is(Kind::object));
  const JsonValue* a = v.find("a");
  ASSERT_TRUE(a && a->is(Kind::array));
  ASSERT_EQ(a->items().size(), 5u);
  EXPECT_EQ(a->items()[1].number(), -2500);
  EXPECT_TRUE(a->items()[2].boolean());
  EXPECT_TRUE(a->items()[4].is(Kind::null));
  EXPECT_EQ(v.find("b")->find("c")->string(), "x\"y\xc3\xa9\n");
  EXPECT_TRUE(v.find("d")->items().empty());
  EXPECT_EQ(v.find("e"), nullptr);
}

TEST(PlanJson, RefusesWhatIsNotJson) {
  for (const char* bad : {"", "{", "[1,]", "{\"a\" 1}", "01", "1.", "tru", "\"a", "[1] x",
                          "{\"a\": 1, \"a\": 2}", "\"\\q\"", "1e999", "\"\\ud800\""}) {
    EXPECT_THROW(JsonValue::parse(bad), JsonError) << bad;
  }
}

TEST(PlanJson, NumbersSurviveTheRoundTrip) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> at(-1e7, 1e7);
  for (int k = 0; k < 10000; ++k) {
    const double v = k % 3 ? at(rng) : std::ldexp(at(rng), -60);
    EXPECT_EQ(JsonValue::parse(json_number(v)).number(), v) << json_number(v);
  }
  EXPECT_EQ(json_number(273400), "273400");
  EXPECT_EQ(JsonValue::parse(json_string("a\"b\\c\td")).string(), "a\"b\\c\td");
}

}  // namespace
