// Numbers in messages, one way: counts thousands separated, other values to six significant
// digits with the integer part grouped, an exponent only beyond what a person reads at a glance.
#include "core/number_text.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>

namespace tincdt {
namespace {

TEST(NumberText, CountsAreThousandsSeparated) {
  EXPECT_EQ(count_text(0), "0");
  EXPECT_EQ(count_text(999), "999");
  EXPECT_EQ(count_text(1000), "1,000");
  EXPECT_EQ(count_text(17349), "17,349");
  EXPECT_EQ(count_text(3999996), "3,999,996");
  EXPECT_EQ(count_text(UINT64_MAX), "18,446,744,073,709,551,615");
}

TEST(NumberText, ACountTakesTheSingularForOne) {
  EXPECT_EQ(count_text(0, "segment"), "0 segments");
  EXPECT_EQ(count_text(1, "segment"), "1 segment");
  EXPECT_EQ(count_text(1200, "segment"), "1,200 segments");
  EXPECT_EQ(count_text(1, "vertex", "vertices"), "1 vertex");
  EXPECT_EQ(count_text(2, "vertex", "vertices"), "2 vertices");
}

TEST(NumberText, ValuesAreShortAndGrouped) {
  EXPECT_EQ(number_text(0), "0");
  EXPECT_EQ(number_text(2), "2");
  EXPECT_EQ(number_text(-25), "-25");
  EXPECT_EQ(number_text(0.25), "0.25");
  EXPECT_EQ(number_text(0.0001), "0.0001");
  EXPECT_EQ(number_text(12345.678), "12,345.7");
  EXPECT_EQ(number_text(10.545473047620463), "10.5455");
  EXPECT_EQ(number_text(1600000), "1,600,000");
  // Six digits that round up to a seventh keep the plain form.
  EXPECT_EQ(number_text(999999.7), "1,000,000");
  EXPECT_EQ(number_text(-999999.5), "-1,000,000");
  EXPECT_EQ(number_text(999999.4), "999,999");
  EXPECT_EQ(number_text(19876543.0), "19,876,500");
  EXPECT_EQ(number_text(-4000000.5), "-4,000,000");
  EXPECT_EQ(number_text(1e-7), "1e-07");
  EXPECT_EQ(number_text(1e308), "1e+308");
  EXPECT_EQ(number_text(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(number_text(std::nan("")), "nan");
}

}  // namespace
}  // namespace tincdt
