// --max-error in a tile job: the tile's part of the simplified TIN, with the same vertices on its
// borders as its neighbours'.
//
// Once the tile stage has proven every triangle that meets the tile final, the TIN's section
// along each side of the tile is the whole TIN's, the same in the two tiles of the side: the
// places where its edges cross the side (computed from their ends in (x, y) order, so the same
// doubles in every tile) and its vertices on it, the side's ends where the TIN covers them. Each
// side's profile is simplified by Douglas–Peucker (vertical, at --max-error, the crossings of
// constrained edges forced), so both tiles of a side keep the same border vertices. The greedy
// insertion then runs on the tile alone: the border vertices chained by constrained edges, the
// TIN's vertices strictly inside the tile as candidates, and its constrained edges cut at the
// border, kept. Every vertex of the TIN lies within the tolerance: inside a tile by the greedy
// insertion, on a border line by the profile (the merged TIN along a border is its polyline).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "core/types.hpp"
#include "mesh/triangulation.hpp"

namespace tincdt::tiles {

struct TileJob;

namespace detail {

// An axis-parallel side: the line x = at (vertical) or y = at, from lo to hi along it; the two
// tiles of the side reach `depth` across it.
struct Side {
  bool vertical = false;
  double at = 0, lo = 0, hi = 0, depth = 0;
};

// A point of a side's section: its place along the side, its height, whether it must stay (a
// vertex of a constrained edge, or where one crosses), and what it lies on in the TIN: a vertex,
// or an edge it crosses (neither: a side's end).
struct SectionPoint {
  double along = 0;
  double z = 0;
  bool forced = false;
  VertexId vertex = kNoId;
  EdgeId edge = kNoId;
};

// Where a side leaves the TIN through a hull edge, the border does not end at the crossing (a
// point computed in doubles, a hair off the hull, which would leave the merged outline not
// quite convex): it turns from the point before, along the TIN's edge there, to the hull edge's
// end that edge shares. The tile on the other side then takes the sliver of the triangle beyond
// the line, and the hull edge whole. (Only where that end lies in the two tiles of the side: a
// border along an edge into a third tile would cross that tile's border.)
struct TurnedEnd {
  Point3 vertex;          // the hull edge's end the border turns to
  VertexId id = kNoId;    // that vertex in the TIN
  Point2 hull_a, hull_b;  // the hull edge
};

// The TIN's section along a side: its points on the line, by increasing place, one point a place,
// and at either end, where the line leaves the hull, the end the border turns to instead.
struct Section {
  std::vector<SectionPoint> points;
  std::optional<TurnedEnd> first, last;
  // Where the line leaves the hull at an end that cannot turn (the triangle there reaches a third
  // tile, or a corner of the tile lies in it): the border ends at the crossing, and the merged
  // outline may not be exactly convex there.
  std::optional<Point2> stuck;
};

// The section of TIN along SIDE. ON_CONSTRAINT: per vertex, 1 when it ends a constrained edge.
// Every triangle of TIN that meets the side must be final: the result is then the same in every
// tile that holds the side.
Section tin_section(const mesh::Triangulation& tin, const Side& side,
                    std::span<const std::uint8_t> on_constraint);

// Replaces the job's TIN by the tile's simplified triangles (see the top of the file), the
// pieces, crossings and duplicates renumbered, the report's simplification filled in, and
// returns the TIN it replaced (nothing when the tile has no area to simplify, and its TIN stays).
// Runs in the tile stage, after every triangle that meets the tile is proven final.
std::optional<mesh::Triangulation> simplify_tile(TileJob& job);

}  // namespace detail
}  // namespace tincdt::tiles
