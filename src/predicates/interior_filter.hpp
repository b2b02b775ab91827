// A quick test that a point is strictly inside a triangle, for loops that locate many points
// which mostly lie in the triangle of the point before them: when it holds, orient2d() of the
// point and each edge is positive; when it does not, the caller decides by orient2d().
//
// Per edge a -> b it takes the sign of (b - a) x (q - a) in doubles, with b - a rounded once
// per triangle. With S = b - a and D = q - a exact, the computed value differs from
// S.x D.y - S.y D.x by at most (1 + u)^4 - 1 < 4.01u times |S.x D.y| + |S.y D.x| (u = 2^-53:
// two rounded differences, a product and the subtraction), which is at most
// (|S.x| + |S.y|) M for a point q in the triangle's box, M the largest |coordinate| of an edge
// (the box's longer side). The bound 2^-50 (|s.x| + |s.y|) M + 2^-1000, from the rounded edge
// s, covers that, its own rounding and underflow. Points outside the box fail the test, as do
// overflow and NaN (both comparisons fail).
#pragma once

#include <algorithm>
#include <cmath>

#include "core/types.hpp"

namespace tincdt::predicates {

class InteriorFilter {
 public:
  // The triangle a, b, c, counter-clockwise (for a clockwise one the test never holds).
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
    for (int i = 0; i < 3; ++i)
      bound_[i] = 0x1p-50 * (std::fabs(edge_[i].x) + std::fabs(edge_[i].y)) * reach + 0x1p-1000;
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
