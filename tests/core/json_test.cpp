// The JSON writer and reader (core/json.hpp): layouts, number forms, and what the reader refuses,
// with where.
#include "core/json.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace tincdt::json {
namespace {

using Kind = Value::Kind;

TEST(JsonWriter, LinesLayoutIndentsTwoSpacesALevel) {
  Writer j;
  j.begin_object().field("a", std::uint64_t{1}).key("b").begin_array();
  j.value(0.25).begin_object().end_object().begin_array().end_array().end_array();
  j.key("c").begin_object().field("d", true).key("e").null().end_object().end_object();
  EXPECT_EQ(j.str(),
            "{\n  \"a\": 1,\n  \"b\": [\n    0.25,\n    {},\n    []\n  ],\n"
            "  \"c\": {\n    \"d\": true,\n    \"e\": null\n  }\n}");
}

TEST(JsonWriter, OneLineLayoutsHoldTheirChildren) {
  Writer j;
  j.begin_object().key("box").array(std::vector<int>{-1, 2}, Layout::spaced);
  j.key("s").begin_object(Layout::spaced).field("x", "y").key("l").begin_array();
  j.value(1).value(2).end_array().end_object();
  j.key("c").begin_object(Layout::compact).field("k", 3).key("v").array(std::vector<int>{4, 5});
  j.end_object().end_object();
  EXPECT_EQ(j.str(),
            "{\n  \"box\": [-1, 2],\n  \"s\": {\"x\": \"y\", \"l\": [1, 2]},\n"
            "  \"c\": {\"k\":3,\"v\":[4,5]}\n}");
}

TEST(JsonWriter, WritesIntegersWhole) {
  Writer j;
  j.begin_array(Layout::compact).value(std::numeric_limits<std::uint64_t>::max());
  j.value(std::numeric_limits<std::int64_t>::min()).value(std::uint8_t{255}).value(-3);
  j.raw("{\"r\":1}").end_array();
  EXPECT_EQ(j.str(), "[18446744073709551615,-9223372036854775808,255,-3,{\"r\":1}]");
}

TEST(JsonWriter, StringsKeepOrReplaceNonUtf8) {
  const std::string bad = "a\"\xff";
  Writer replaced;
  replaced.value(bad);
  EXPECT_EQ(replaced.str(), R"("a\"\ufffd")");
  Writer kept(Numbers::plain, NonUtf8::keep);
  kept.value(bad);
  EXPECT_EQ(kept.str(), "\"a\\\"\xff\"");
  EXPECT_EQ(parse(kept.str()).string(), bad);
}

TEST(JsonNumbers, EachFormAsItsDocumentsHaveIt) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const Numbers style : {Numbers::plain, Numbers::shortest, Numbers::digits17}) {
    EXPECT_EQ(number(nan, style), "null");
    EXPECT_EQ(number(-HUGE_VAL, style), "null");
  }
  EXPECT_EQ(number(500000, Numbers::plain), "500000");
  EXPECT_EQ(number(500000, Numbers::shortest), "5e+05");
  EXPECT_EQ(number(500000, Numbers::digits17), "500000");
  EXPECT_EQ(number(0.1, Numbers::plain), "0.1");
  EXPECT_EQ(number(0.1, Numbers::shortest), "0.1");
  EXPECT_EQ(number(0.1, Numbers::digits17), "0.10000000000000001");
  EXPECT_EQ(number(1e20, Numbers::plain), "1e+20");
  EXPECT_EQ(number(1e-5, Numbers::plain), "1e-05");
  EXPECT_EQ(number(0x1p53, Numbers::digits17), "9007199254740992");
}

TEST(JsonNumbers, EveryFormSurvivesTheRoundTrip) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> at(-1e7, 1e7);
  for (int k = 0; k < 10000; ++k) {
    const double v = k % 3 ? at(rng) : std::ldexp(at(rng), (k % 7) * 40 - 120);
    for (const Numbers style : {Numbers::plain, Numbers::shortest, Numbers::digits17})
      EXPECT_EQ(parse(number(v, style)).number(), v) << number(v, style);
  }
}

TEST(JsonReader, ReadsEveryKind) {
  const Value v =
      parse(R"( {"a": [1, -2.5e3, true, false, null], "b": {"c": "x\"y\u00e9\ud83d\ude00\/\n"},
                 "d": []} )");
  ASSERT_TRUE(v.is(Kind::object));
  EXPECT_EQ(v.keys(), (std::vector<std::string>{"a", "b", "d"}));
  const Value* a = v.find("a");
  ASSERT_TRUE(a && a->is(Kind::array));
  ASSERT_EQ(a->items().size(), 5u);
  EXPECT_EQ(a->items()[1].number(), -2500);
  EXPECT_TRUE(a->items()[2].boolean());
  EXPECT_FALSE(a->items()[3].boolean());
  EXPECT_TRUE(a->items()[4].is(Kind::null));
  EXPECT_EQ(v.find("b")->find("c")->string(), "x\"y\xc3\xa9\xf0\x9f\x98\x80/\n");
  EXPECT_TRUE(v.find("d")->items().empty());
  EXPECT_EQ(v.find("e"), nullptr);
  EXPECT_EQ(a->find("x"), nullptr);
}

TEST(JsonReader, RefusesWhatIsNotJson) {
  for (const char* bad : {"",
                          " ",
                          "{",
                          "[1,]",
                          "{\"a\" 1}",
                          "{\"a\":1,}",
                          "{1:2}",
                          "01",
                          "-",
                          "1.",
                          "1e",
                          ".5",
                          "+1",
                          "tru",
                          "nul",
                          "\"a",
                          "[1] x",
                          "[1 2]",
                          "{\"a\": 1, \"a\": 2}",
                          "\"\\q\"",
                          "\"\\u12\"",
                          "\"\\ud800\"",
                          "\"\\udc00\"",
                          "\"\\ud800\\u0041\"",
                          "\"a\tb\"",
                          "NaN",
                          "Infinity"}) {
    EXPECT_THROW(parse(bad), ParseError) << bad;
  }
}

TEST(JsonReader, ErrorsSayWhere) {
  try {
    parse("{\n  \"a\": 1,\n  \"b\" 2\n}", "plan.json");
    FAIL() << "no error";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), 3u);
    EXPECT_EQ(e.column(), 7u);
    EXPECT_EQ(e.offset(), 18u);
    EXPECT_EQ(e.file(), "plan.json");
    EXPECT_EQ(std::string(e.what()), "plan.json: line 3, column 7: not JSON: expected ':'");
  }
  // A repeated name is pointed at where it repeats; the error is an InputError.
  try {
    parse("{\"k\": 1, \"k\": 2}");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), "line 1, column 10");
  }
}

TEST(JsonReader, DeepNestingIsRefusedNotOverflowed) {
  const auto nested = [](int depth) {
    return std::string(static_cast<std::size_t>(depth), '[') +
           std::string(static_cast<std::size_t>(depth), ']');
  };
  EXPECT_TRUE(parse(nested(kMaxDepth + 1)).is(Kind::array));
  EXPECT_THROW(parse(nested(kMaxDepth + 2)), ParseError);
  EXPECT_THROW(parse(nested(1'000'000)), ParseError);
  std::string objects;
  for (int i = 0; i < 100'000; ++i) objects += "{\"a\":";
  EXPECT_THROW(parse(objects), ParseError);
}

TEST(JsonReader, HugeNumbers) {
  // Past the doubles' range is an error; many digits within it are the nearest double.
  EXPECT_THROW(parse("1e309"), ParseError);
  EXPECT_THROW(parse("-1e999"), ParseError);
  EXPECT_EQ(parse("1.7976931348623157e308").number(), std::numeric_limits<double>::max());
  EXPECT_EQ(parse("123456789012345678901234567890").number(), 1.2345678901234568e29);
  EXPECT_EQ(parse("18446744073709551615").number(), 0x1p64);
  EXPECT_EQ(parse(std::string(400, '9') + "e-390").number(), 1e10);
  EXPECT_EQ(parse("-0").number(), 0.0);
  EXPECT_TRUE(std::signbit(parse("-0").number()));
}

TEST(JsonReader, NonUtf8BytesAreKeptInStringsAndRefusedOutside) {
  const std::string bytes = "\xff\xfe\xc3\x28\xed\xa0\x80";
  EXPECT_EQ(parse("\"" + bytes + "\"").string(), bytes);
  EXPECT_EQ(parse("{\"" + bytes + "\": 1}").keys().front(), bytes);
  try {
    parse("[1, \xff]");
    FAIL() << "no error";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.column(), 5u);
  }
}

TEST(JsonReader, LargeDocuments) {
  // Wide objects (names checked for repeats without a quadratic scan) and long arrays.
  Writer j;
  j.begin_object(Layout::compact);
  std::string name = "k";
  for (int i = 0; i < 50'000; ++i)
    j.field(name.replace(1, std::string::npos, std::to_string(i)), i);
  j.end_object();
  const Value v = parse(j.str());
  ASSERT_EQ(v.items().size(), 50'000u);
  EXPECT_EQ(v.find("k49999")->number(), 49999);
  const std::string repeated = j.str().substr(0, j.str().size() - 1) + ",\"k7\":0}";
  EXPECT_THROW(parse(repeated), ParseError);
  std::string zeros = "[0";
  for (int i = 1; i < 100'000; ++i) zeros += ",0";
  EXPECT_EQ(parse(zeros + "]").items().size(), 100'000u);
}

}  // namespace
}  // namespace tincdt::json
