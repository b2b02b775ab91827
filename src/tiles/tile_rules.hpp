// The geometry of tiled jobs, shared by the plan, the tile job and its tests: the tile lattice,
// the rule that gives every triangle of the whole TIN to exactly one tile, and the tests that
// prove a triangle of a tile's TIN is a triangle of the whole TIN.
//
// Why a tile's triangle can be final: the tile reads every point inside its buffered box B and
// every line segment whose bounding box meets B, whole (never clipped), so its input is a subset
// of the whole input that holds everything inside B. A triangle of its constrained Delaunay
// triangulation whose closed circumdisk lies inside B sees, inside that disk, exactly the points
// and segments the whole run sees there; it is constrained Delaunay for the whole input too, and
// with ties broken by a rule of the points alone (symbolic perturbation) the whole CDT is unique
// and holds every such triangle. A disk may also reach outside B where no input has data (the
// plan knows every input's bounds).
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "core/types.hpp"

namespace tincdt::tiles {

// Tile (col, row) is the half-open box [col * S, (col + 1) * S) x [row * S, (row + 1) * S); the
// edges are the doubles col * S, computed the same way everywhere, so the boxes of neighbours
// share them exactly and every point of the plane is in exactly one tile.
struct TileGrid {
  double size = 0;

  double edge(std::int64_t i) const { return static_cast<double>(i) * size; }
  // The i with edge(i) <= v < edge(i + 1).
  std::int64_t cell_of(double v) const;
  // The tile's box, closed at its max sides (they belong to the next tile).
  BBox box(std::int64_t col, std::int64_t row) const {
    return {edge(col), edge(row), edge(col + 1), edge(row + 1)};
  }
  // The box grown by BUFFER on every side: what the tile reads.
  BBox buffered(std::int64_t col, std::int64_t row, double buffer) const {
    return {edge(col) - buffer, edge(row) - buffer, edge(col + 1) + buffer, edge(row + 1) + buffer};
  }
  bool holds(std::int64_t col, std::int64_t row, Point2 p) const {
    return edge(col) <= p.x && p.x < edge(col + 1) && edge(row) <= p.y && p.y < edge(row + 1);
  }
};

// The point whose tile owns a triangle: its centroid, from the corners sorted by (x, y) so that
// every job computes the same double whatever the corners' order in its TIN.
Point2 owner_point(Point2 a, Point2 b, Point2 c);

// A closed disk that contains the closed circumdisk of triangle a, b, c: the centre computed in
// doubles and the radius grown by a bound on the centre's rounding error. Radius infinity when
// the triangle is too flat for the bound to hold.
struct Disk {
  Point2 centre;
  double radius;
};
Disk circumdisk_bound(Point2 a, Point2 b, Point2 c);

inline bool intersects(const BBox& a, const BBox& b) {
  return a.min_x <= b.max_x && b.min_x <= a.max_x && a.min_y <= b.max_y && b.min_y <= a.max_y;
}
inline BBox grown(const BBox& b, double d) {
  return {b.min_x - d, b.min_y - d, b.max_x + d, b.max_y + d};
}
inline bool empty(const BBox& b) {
  return !(b.min_x <= b.max_x && b.min_y <= b.max_y);
}

// Whether disk D lies inside the open box B.
bool inside(const Disk& d, const BBox& b);
// Whether disk D has no point in common with the closed box R.
bool misses(const Disk& d, const BBox& r);
// How far disk D reaches beyond box Q on its farthest side (0 when inside).
double reach_beyond(const Disk& d, const BBox& q);

// Where points and lines may lie outside the buffered box B: every data box minus the interior of
// B, as closed boxes (up to four per data box, overlapping).
std::vector<BBox> data_outside(const std::vector<BBox>& data, const BBox& b);

// Whether some corner of the closed box R lies strictly left of the line u -> v (exact).
bool reaches_left_of(Point2 u, Point2 v, const BBox& r);

// ---- convex polygons, in doubles; every test errs on the side of "they meet" ------------------

using Polygon = std::vector<Point2>;  // convex, counter-clockwise; empty = nothing

Polygon box_polygon(const BBox& b);
// Whether the closed box R lies in the interior of convex polygon P (exact).
bool box_inside(const BBox& r, const Polygon& p);
// The part of P on the left of the line a -> b, the line moved right by GROW (so the result
// holds the true part despite rounding).
Polygon clip_left(const Polygon& p, Point2 a, Point2 b, double grow);
// Whether disk D and polygon P may meet (within MARGIN).
bool may_meet(const Disk& d, const Polygon& p, double margin);
// Whether triangle a, b, c (counter-clockwise) and polygon P may meet (within MARGIN).
bool may_meet(Point2 a, Point2 b, Point2 c, const Polygon& p, double margin);
// Whether the open half-plane left of u -> v and polygon P may meet (within MARGIN).
bool may_meet_left(Point2 u, Point2 v, const Polygon& p, double margin);

// ---- the rim: the points near the data's convex hull ------------------------------------------

// Near the hull, triangles of the whole TIN are long and thin along the hull's edges and depend
// on points far along them: no buffer settles them. The plan therefore finds the convex hull H
// of all the data and the points within `width` of its boundary (the rim), and every tile near
// the boundary reads the rim too. What a tile then does not hold lies in H shrunk by `width`.
struct Rim {
  std::vector<Point2> hull;  // counter-clockwise, no collinear points; empty = no rim
  double width = 0;
  // Whether P lies within `width` of the hull's boundary (by one fixed formula, in doubles).
  bool holds(Point2 p) const;
  // The hull shrunk by a bit less than `width`: it holds every point of H that holds() refuses.
  Polygon inner() const;
};

// The convex hull of POINTS, counter-clockwise, without collinear points (exact orientation).
std::vector<Point2> convex_hull(std::vector<Point2> points);
// Whether the interiors of box R and convex polygon HULL (counter-clockwise, 3 corners or more)
// meet: a tile that only touches the hull's boundary owns no triangle.
bool meets_convex(const BBox& r, const std::vector<Point2>& hull);

}  // namespace tincdt::tiles
