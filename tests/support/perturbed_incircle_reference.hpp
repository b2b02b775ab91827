// An independent reference for predicates::incircle_perturbed, written from the definition alone:
// exact integer determinants, no floating point and no code from src/predicates. Points have
// integer coordinates in an IntegerFrame, which maps them exactly to the doubles the library sees
// (an origin plus a power-of-two step), so that the reference and the library decide the same
// geometry.
//
// The definition: lift each point p to x^2 + y^2 + eps_p, where eps_p > 0 is infinitesimal and
// larger for lexicographically (x, then y) larger points, each infinitely larger than the next.
// in_circle(a, b, c, d) is the sign of det[x y lift 1] over the rows a, b, c, d: a polynomial in
// the eps, whose sign is that of its constant term, or if that is 0 of the coefficient of the
// largest eps that has a nonzero one. The coefficient of eps_p is the determinant with the lift
// column replaced by the unit vector of p's row.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <tuple>

#include "core/types.hpp"

namespace tincdt::test {

__extension__ typedef __int128 Int128;

struct IntPoint {
  std::int64_t x;
  std::int64_t y;
  friend bool operator==(const IntPoint&, const IntPoint&) = default;
};

inline bool lex_less(IntPoint a, IntPoint b) {
  return std::tie(a.x, a.y) < std::tie(b.x, b.y);
}

// Integer coordinates <-> the library's doubles: x = x0 + ix * step, exact when step is a power
// of two and the values stay within the doubles' precision at x0.
struct IntegerFrame {
  double x0 = 0;
  double y0 = 0;
  double step = 1;

  Point2 to_double(IntPoint p) const {
    return {x0 + static_cast<double>(p.x) * step, y0 + static_cast<double>(p.y) * step};
  }
  IntPoint to_int(Point2 p) const {
    const IntPoint q{static_cast<std::int64_t>(std::llround((p.x - x0) / step)),
                     static_cast<std::int64_t>(std::llround((p.y - y0) / step))};
    EXPECT_EQ(to_double(q), p) << "the frame does not map this point exactly";
    return q;
  }
};

namespace detail {

inline int sign_of(Int128 v) {
  return (v > 0) - (v < 0);
}

inline Int128 det3(const std::array<std::array<Int128, 3>, 3>& m) {
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
         m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

// Laplace expansion along the first row.
inline Int128 det4(const std::array<std::array<Int128, 4>, 4>& m) {
  Int128 sum = 0;
  for (std::size_t col = 0; col < 4; ++col) {
    std::array<std::array<Int128, 3>, 3> minor{};
    for (std::size_t r = 1; r < 4; ++r)
      for (std::size_t c = 0, k = 0; c < 4; ++c)
        if (c != col) minor[r - 1][k++] = m[r][c];
    const Int128 term = m[0][col] * det3(minor);
    sum += col % 2 == 0 ? term : -term;
  }
  return sum;
}

}  // namespace detail

// The perturbed in-circle sign of d against a, b, c (positive: inside, for a, b, c counter-
// clockwise). Coordinates differences must stay below 2^20 or so (lifts below 2^41).
inline int perturbed_in_circle(IntPoint a, IntPoint b, IntPoint c, IntPoint d) {
  const std::array<IntPoint, 4> p{a, b, c, d};
  std::array<std::array<Int128, 4>, 4> m{};
  for (std::size_t i = 0; i < 4; ++i) {
    const Int128 x = p[i].x - a.x, y = p[i].y - a.y;  // a translation changes no sign
    m[i] = {x, y, x * x + y * y, 1};
  }
  if (const Int128 constant = detail::det4(m); constant != 0) return detail::sign_of(constant);
  std::array<std::size_t, 4> by_eps{0, 1, 2, 3};  // largest eps first
  std::sort(by_eps.begin(), by_eps.end(),
            [&](std::size_t i, std::size_t j) { return lex_less(p[j], p[i]); });
  for (const std::size_t row : by_eps) {
    auto unit = m;
    for (std::size_t i = 0; i < 4; ++i) unit[i][2] = i == row ? 1 : 0;
    if (const Int128 coefficient = detail::det4(unit); coefficient != 0)
      return detail::sign_of(coefficient);
  }
  return 0;
}

inline int orientation(IntPoint a, IntPoint b, IntPoint c) {
  return detail::sign_of(Int128{b.x - a.x} * (c.y - a.y) - Int128{b.y - a.y} * (c.x - a.x));
}

}  // namespace tincdt::test
