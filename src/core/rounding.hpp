// std::round without the call into the maths library that x86-64 code built for the baseline
// instruction set makes for every std::round (rounding instructions came with SSE4.1): for
// passes that round millions of coordinates onto a grid.
#pragma once

#include <cmath>
#include <cstdint>

namespace tincdt {

// std::round(x), bit for bit (halves away from zero, the sign of a zero kept, NaN and infinities
// returned as they are).
inline double round_half_away(double x) {
  if (!(std::fabs(x) < 0x1p52)) return x;  // an integer already, or NaN
  // Toward zero by conversion; the rest is exact, as x and its integer part share their sign and
  // |x - t| < 1 is a multiple of x's last place.
  const double t = static_cast<double>(static_cast<std::int64_t>(x));
  // Without a branch: whether a coordinate rounds up is a coin toss a branch predictor loses.
  const auto away = static_cast<double>(std::fabs(x - t) >= 0.5);
  return std::copysign(std::fabs(t) + away, x);
}

}  // namespace tincdt
