// Filters for loops that test many points against the same few edges: they answer only when
// the sign of orient2d() is sure, and leave the rest to orient2d().
#pragma once

#include <algorithm>
#include <cmath>

#include "core/types.hpp"
#include "predicates/predicates.hpp"

namespace tincdt::predicates {

// The bound for the sign of s.x d.y - s.y d.x computed in doubles, standing for orient2d(a, b, q)
// with s = b - a rounded once and d = q - a rounded, given |d.x|, |d.y| <= reach. With S and D
// exact, the computed value differs from S.x D.y - S.y D.x by at most (1 + u)^4 - 1 < 4.01u
// times |S.x D.y| + |S.y D.x| (u = 2^-53: two rounded differences, a product and the
// subtraction), which is at most (|S.x| + |S.y|) reach. 2^-50 (|s.x| + |s.y|) reach plus the
// underflow guard covers that, its own rounding and underflow. Infinite (never sure) when a
// product could overflow: one infinite product would pass any finite bound.
inline double cross_bound(Point2 s, double reach) {
  if (!(reach < 0x1p500)) return INFINITY;  // (also NaN)
  return 0x1p-50 * (std::fabs(s.x) + std::fabs(s.y)) * reach + detail::kUnderflowGuard;
}

// A quick test that a point is strictly inside a triangle, for loops that locate many points
// which mostly lie in the triangle of the point before them: when it holds, orient2d() of the
// point and each edge is positive. Per edge a -> b, the sign of (b - a) x (q - a) with
// cross_bound(), for points q in the triangle's box (the reach is its longer side); points
// outside the box fail the test.
class InteriorFilter {
 public:
  // The triangle a, b, c, counter-clockwise (for a clockwise or flat one it never holds).
  InteriorFilter(Point2 a, Point2 b, Point2 c) {
    const Point2 p[3] = {a, b, c};
    lo_ = {std::min({a.x, b.x, c.x}), std::min({a.y, b.y, c.y})};
    hi_ = {std::max({a.x, b.x, c.x}), std::max({a.y, b.y, c.y})};
    double reach = 0;
    for (int i = 0; i < 3; ++i) {
      from_[i] = p[i];
      edge_[i] = {p[(i + 1) % 3].x - p[i].x, p[(i + 1) % 3].y - p[i].y};
      reach = std::max({reach, std::fabs(edge_[i].x), std::fabs(edge_[i].y)});
    }
    for (int i = 0; i < 3; ++i) bound_[i] = cross_bound(edge_[i], reach);
  }

  // True only if q is strictly inside the triangle; false for most points that are not.
  bool surely_inside(Point2 q) const {
    bool inside = q.x >= lo_.x && q.x <= hi_.x && q.y >= lo_.y && q.y <= hi_.y;
    for (int i = 0; i < 3; ++i)  // (all three, without branches)
      inside &= edge_[i].x * (q.y - from_[i].y) - edge_[i].y * (q.x - from_[i].x) > bound_[i];
    return inside;
  }

 private:
  Point2 lo_, hi_;  // the box
  Point2 from_[3], edge_[3];
  double bound_[3];
};

}  // namespace tincdt::predicates
