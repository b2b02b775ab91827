// Clip and erase rings cut to a TIN's convex hull, before they are draped and inserted.
//
// Users draw boundaries a little larger than their data. A ring vertex outside the hull would
// grow the TIN (a 3D ring) or have no z to drape (a 2D one), so the rings are cut to the hull
// first: Sutherland-Hodgman against each hull edge's half-plane, which for a convex clip region
// keeps the even-odd inside of any ring, bow-ties and overlaps included. Where a ring leaves and
// re-enters, the cut runs along the hull; the classification of triangles by the original rings
// (terrain::remove_outside / remove_inside) is the same inside the hull, so only the inserted
// constraints change. A crossing point, rounded to doubles, may land an ulp outside the hull: it
// is then moved towards the hull's inside by the smallest power-of-two fraction that puts it
// inside or on the hull, checked with orient2d.
#pragma once

#include <vector>

#include "core/types.hpp"
#include "mesh/triangulation.hpp"

namespace tincdt::terrain {

// The TIN's convex hull, counter-clockwise, without collinear vertices (the fewest half-planes),
// from its least point by (x, y): the same list as tiles::convex_hull() of the TIN's vertices.
std::vector<Point2> strict_hull(const mesh::Triangulation& tin);

// Whether p lies inside or on HULL (convex, counter-clockwise).
bool inside_or_on(const std::vector<Point2>& hull, Point2 p);

// A point strictly inside the hull (a hull vertex if the hull is too thin to find one).
Point2 interior_point(const std::vector<Point2>& hull);

// Whether RING (3 points or more) encloses no area: every vertex on the line through the first
// two (which differ: the reader collapsed repeats).
bool zero_area(const std::vector<Point3>& ring);

// The part of RING inside HULL (strict_hull()), INSIDE a point strictly inside it
// (interior_point()): empty when that encloses no area (the ring lies outside, or only touches
// the hull). Where the cut ring follows the hull, its corners are the hull's own vertices (so the
// TIN's vertices there are reused, with their z); where the ring crosses the hull, the crossing's
// z is interpolated along the ring.
std::vector<Point3> cut_to_hull(const std::vector<Point3>& ring, const std::vector<Point2>& hull,
                                Point2 inside);

}  // namespace tincdt::terrain
