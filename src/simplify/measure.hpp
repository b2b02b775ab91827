// How far a point is from the TIN, and what a set of points holds: the error of a point is its
// vertical distance to the plane of the triangle holding it. Doubles are enough for an error
// value; which triangle a point is in is decided exactly elsewhere.
#pragma once

#include <cmath>
#include <cstdint>

#include "core/types.hpp"

namespace tincdt::simplify::detail {

// The gradient of the plane through three points, relative to the first, so that large
// coordinates (UTM) do not cancel: z = za + gx (x - a.x) + gy (y - a.y).
struct Gradient {
  double gx, gy;
  Gradient(Point2 a, double za, Point2 b, double zb, Point2 c, double zc) {
    const double bx = b.x - a.x, by = b.y - a.y, cx = c.x - a.x, cy = c.y - a.y;
    const double dzb = zb - za, dzc = zc - za;
    const double det = bx * cy - by * cx;
    gx = (dzb * cy - dzc * by) / det;
    gy = (dzc * bx - dzb * cx) / det;
  }
};

// The plane through a triangle, from its corner a.
struct Plane {
  Point2 a{};
  double za = 0, gx = 0, gy = 0;

  // The vertical distance from the plane to point (p, z).
  double error(Point2 p, double z) const {
    return std::fabs(z - (za + gx * (p.x - a.x) + gy * (p.y - a.y)));
  }
};

// Whether point p with error e is worse than the worst so far, w with error we (w = kNoId:
// none yet). Equal errors go by x, then y, so that input order never decides.
inline bool worse(double e, std::uint32_t p, double we, std::uint32_t w, const Point2* xy) {
  if (e != we) return e > we;
  return w == kNoId || xy_less(xy[p], xy[w]);
}

// What a set of points (a triangle's, or one thread's share of it) holds.
struct Tally {
  double worst_error = -1.0;
  double sum_sq = 0;  // of the errors
  std::uint32_t worst = kNoId;
  std::uint32_t count = 0;

  void add(double e, std::uint32_t p, const Point2* xy) {
    ++count;
    sum_sq += e * e;
    if (worse(e, p, worst_error, worst, xy)) {
      worst_error = e;
      worst = p;
    }
  }
};

}  // namespace tincdt::simplify::detail
