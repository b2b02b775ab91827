// The new triangles around an inserted vertex, and which of them holds a point: the hot loop of
// the greedy insertion classifies every point of the replaced triangles against the fan of
// spokes from the new vertex (the apex) to its ring.
#pragma once

#include <cassert>
#include <cstdint>

#include "core/error.hpp"
#include "core/types.hpp"
#include "predicates/predicates.hpp"
#include "simplify/measure.hpp"

namespace tincdt::simplify::detail {

// A new triangle (apex, ring[i], ring[i + 1]) around an inserted vertex.
struct Cone {
  TriangleId tri;
  Gradient plane;  // relative to the apex
};

// The new triangles around an inserted vertex, as plain arrays for the hot loop.
struct Fan {
  Point2 apex;
  double apex_z;
  const Point2* ring;   // m + 1 points; ring[m] == ring[0] when cyclic
  const Point2* spoke;  // ring[i] - apex, rounded
  const double* bound;  // spoke i's filter bound (below)
  const Cone* cones;    // m
  int m;
  bool cyclic;  // the apex is inside the hull (else the cones stop at the hull)

  // orient2d(apex, ring[i], q), given d = q - apex (rounded), by a filter with one bound per
  // spoke: predicates::cross_bound(spoke[i], M), M the largest |coordinate| of a spoke (every
  // point of the fan lies in the box of its corners). An uncertain sign (and NaN, which fails
  // both tests) goes to the exact predicate.
  int side(int i, Point2 d, Point2 q) const {
    const double det = spoke[i].x * d.y - spoke[i].y * d.x;
    if (det > bound[i]) return 1;
    if (det < -bound[i]) return -1;
    return predicates::orient2d(apex, ring[i], q);
  }

  // The cone holding q (known to lie in the fan), scanning from `hint`. A point on the spoke
  // between two cones goes to the one with the smaller slot, whatever the scan order.
  // Inlined: called, it took q and d through the stack as halves and read them back whole,
  // a failed store forwarding per point (14% of the stage on a 4096^2 grid).
  [[gnu::always_inline]] int classify(Point2 q, Point2 d, int hint) const {
    assert(0 <= hint && hint < m);
    int i = hint;
    int left = side(i, d, q);
    for (int step = 0; step < m; ++step) {
      const int right = side(i + 1, d, q);
      if (left >= 0 && right <= 0) {
        int j = -1;
        if (left == 0) j = i > 0 ? i - 1 : (cyclic ? m - 1 : -1);
        if (right == 0) j = i + 1 < m ? i + 1 : (cyclic ? 0 : -1);
        return j >= 0 && cones[j].tri < cones[i].tri ? j : i;
      }
      if (++i == m) {
        i = 0;
        left = cyclic ? right : side(0, d, q);
      } else {
        left = right;
      }
    }
    throw InternalError("simplify: a point of a replaced triangle is in none of the new");
  }
};

}  // namespace tincdt::simplify::detail
