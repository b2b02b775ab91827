// round_half_away against std::round, bit for bit: halves and their neighbours, both signs, every
// exponent up to where every double is an integer and beyond, zeros, subnormals, infinities, NaN.
#include "core/rounding.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

namespace tincdt {
namespace {

void expect_same_as_std(double x) {
  const double ours = round_half_away(x), theirs = std::round(x);
  if (std::isnan(theirs)) {
    EXPECT_TRUE(std::isnan(ours)) << x;
    return;
  }
  EXPECT_EQ(std::bit_cast<std::uint64_t>(ours), std::bit_cast<std::uint64_t>(theirs))
      << std::hexfloat << x << " gave " << ours << ", std::round " << theirs;
}

TEST(RoundHalfAway, HalvesAndTheirNeighbours) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  for (double k = 0; k < 70000; k += k < 100 ? 1 : 37) {
    for (const double sign : {1.0, -1.0}) {
      const double half = sign * (k + 0.5);
      expect_same_as_std(half);
      expect_same_as_std(std::nextafter(half, kInf));
      expect_same_as_std(std::nextafter(half, -kInf));
      expect_same_as_std(sign * k);
    }
  }
  expect_same_as_std(0.49999999999999994);  // floor(x + 0.5) would give 1
  expect_same_as_std(-0.49999999999999994);
}

TEST(RoundHalfAway, SpecialValuesAndEveryExponent) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  for (const double x :
       {0.0, -0.0, 0.3, -0.3, std::numeric_limits<double>::denorm_min(),
        -std::numeric_limits<double>::denorm_min(), 0x1p52, -0x1p52, std::nextafter(0x1p52, 0.0),
        -std::nextafter(0x1p52, 0.0), 0x1p52 + 1, 0x1p53 + 2, 0x1p63, -0x1p63, 0x1p64,
        std::numeric_limits<double>::max(), kInf, -kInf, std::numeric_limits<double>::quiet_NaN()})
    expect_same_as_std(x);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> mantissa(1, 2);
  for (int e = -60; e <= 70; ++e)
    for (int i = 0; i < 2000; ++i) {
      const double x = std::ldexp(mantissa(rng), e);
      expect_same_as_std(x);
      expect_same_as_std(-x);
    }
}

}  // namespace
}  // namespace tincdt
