// tile: in a tiled job (--plan), keeps the triangles the tile owns and proves that each of them,
// and every other triangle near the tile, is final: a triangle of the whole TIN (tile_rules.hpp).
// With --max-edge it then removes those the whole job trims (TileTrim), with --max-error it
// simplifies the tile (tile_simplify.hpp).
//
// A triangle is final when no point or line the tile lacks can change it: its circumdisk meets
// none of the regions where such data may lie (TileSetup::missing). Across a constrained edge
// nothing is visible: the part of the disk behind a constrained edge that holds the disk's whole
// chord on its line (the triangle's own constrained edges, and others near: wall_of())
// does not count, and of the rest only what lies beyond the triangle's unconstrained edges (and
// the triangle itself).
//
// Checked: every triangle that meets the tile's box (grown by a hair for the rounding of the
// owner point; the test errs on the side of meeting) and every hull edge whose outer side reaches
// it. So every triangle
// that holds a point of the tile is final, owned or not: the tile's DEM (TileJob, tile_job.hpp)
// fills the cells of its box from all of them. If they are all final, the triangles of the whole
// TIN owned by this tile are exactly the local ones it owns: the owner point of a whole-TIN
// triangle lies inside it, in the tile, so inside a checked local triangle, which is final and
// therefore that same triangle; a point of the tile outside the local hull is outside the whole
// hull too (its hull edge is final).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "pipeline/stage.hpp"
#include "predicates/predicates.hpp"
#include "terrain/trim.hpp"
#include "tiles/merge_outline.hpp"
#include "tiles/tile_job.hpp"
#include "tiles/tile_simplify.hpp"

namespace tincdt::tiles {
namespace {

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

// "(x, y)" for a message.
std::string place_text(Point2 p) {
  char text[80];
  std::snprintf(text, sizeof text, "(%.3f, %.3f)", p.x, p.y);
  return text;
}

// A buffer comfortably above NEEDED: rounded up to two significant digits, plus a tenth.
double suggested_buffer(double needed) {
  const double v = needed * 1.1;
  const double unit = std::pow(10.0, std::floor(std::log10(v)) - 1);
  return std::ceil(v / unit) * unit;
}

// The kept triangles' border: each edge whose other side is not kept, in the kept triangle's
// direction (its interior on the left).
std::vector<detail::Border> outline_of(const mesh::Triangulation& tin) {
  std::vector<detail::Border> border;
  const auto point = [&tin](VertexId v) {
    const Point2 p = tin.point(v);
    return Point3{p.x, p.y, tin.z(v)};
  };
  tin.for_each_triangle([&](TriangleId t, const std::array<VertexId, 3>& c) {
    for (std::uint32_t i = 0; i < 3; ++i) {
      if (tin.is_kept(mesh::triangle_of(tin.twin(3 * t + i)))) continue;
      border.push_back({point(c[i]), point(c[(i + 1) % 3]), point(c[(i + 2) % 3]),
                        tin.is_constrained(3 * t + i), 0});
    }
  });
  return border;
}

// In the stage list of a tile job only (tile_stages()); its outline is planned there too.
bool wanted(const pipeline::BuildOptions&) {
  return true;
}

// The triangles are checked in the tile's box grown by a bound on the rounding of owner points:
// a triangle's owner point is its centroid computed in doubles, within a few ulps of the true one.
BBox checked_region(const TileSetup& tile) {
  const double magnitude = std::max({std::fabs(tile.box.min_x), std::fabs(tile.box.max_x),
                                     std::fabs(tile.box.min_y), std::fabs(tile.box.max_y)});
  const double span = tile.buffered.max_x - tile.buffered.min_x;
  return tiles::grown(tile.box, 16 * 0x1p-52 * (magnitude + span));
}

// A line with the triangle on its left beyond which the triangle's circumdisk is hidden from it.
struct Wall {
  Point2 a, b;
};

// Constrained edge S0-S1 near triangle P (counter-clockwise) hides the part of the circumdisk
// beyond its line when the disk's chord on that line lies within the edge: a segment from the
// triangle to a point of the disk beyond the line stays in the disk, so it crosses the line
// there, on the edge. So when the triangle lies on one side of the line, neither end is inside
// the circle and the centre projects between the ends (kept clear of them by the bound on the
// computed centre's error). The triangle's own constrained edges always hold (their ends are on
// the circle).
std::optional<Wall> wall_of(const Point2 (&p)[3], Point2 s0, Point2 s1, const tiles::Disk& d,
                            double margin) {
  int side = 0;
  for (const Point2 q : p) {
    const int o = predicates::orient2d(s0, s1, q);
    if (o != 0 && side != 0 && o != side) return std::nullopt;
    if (o != 0) side = o;
  }
  if (side == 0 || predicates::incircle(p[0], p[1], p[2], s0) > 0 ||
      predicates::incircle(p[0], p[1], p[2], s1) > 0)
    return std::nullopt;
  const double lx = s1.x - s0.x, ly = s1.y - s0.y, length = std::hypot(lx, ly);
  const double along = ((d.centre.x - s0.x) * lx + (d.centre.y - s0.y) * ly) / length;
  const double slack = d.radius - std::hypot(d.centre.x - p[0].x, d.centre.y - p[0].y) + 4 * margin;
  if (!(along > slack && along < length - slack)) return std::nullopt;
  return side > 0 ? Wall{s0, s1} : Wall{s1, s0};
}

// The walls of triangle T (see wall_of()): its own constrained edges and the constrained edges
// of the triangles at its corners.
std::vector<Wall> walls_of(const mesh::Triangulation& tin, TriangleId t, const Point2 (&p)[3],
                           const tiles::Disk& d, double margin) {
  std::vector<Wall> walls;
  for (std::uint32_t i = 0; i < 3; ++i) {
    const auto own = static_cast<EdgeId>(3 * t + i);
    if (tin.is_constrained(own)) walls.push_back({p[i], p[(i + 1) % 3]});
    // Around corner i, through the ghosts too: every edge leaving it, and the far edge of each
    // triangle there.
    const auto consider = [&](EdgeId e) {
      const VertexId from = tin.origin(e), to = tin.dest(e);
      if (from == mesh::kInfinite || to == mesh::kInfinite || !tin.is_constrained(e)) return;
      if (const auto wall = wall_of(p, tin.point(from), tin.point(to), d, margin))
        walls.push_back(*wall);
    };
    EdgeId e = own;
    do {
      if (mesh::triangle_of(e) != t) {
        if (mesh::triangle_of(tin.twin(e)) != t) consider(e);
        consider(mesh::next_edge(e));
      }
      e = tin.twin(mesh::prev_edge(e));
    } while (e != own);
  }
  return walls;
}

// Whether the hull edge with the ghost (u, v, inf) is one of the whole TIN's: no data the tile
// lacks may lie on its outer side, the open half-plane left of U -> V.
bool is_final_hull_edge(const TileSetup& tile, Point2 u, Point2 v) {
  return std::none_of(tile.missing.begin(), tile.missing.end(), [&](const tiles::Polygon& piece) {
    return tiles::may_meet_left(u, v, piece, tile.margin);
  });
}

// A triangle A, B, X obtuse at X has its circumcentre beyond its edge A -> B, and of its
// circumdisk only the circular segment on chord AB lies on X's side, no higher than
// H = d L^2 / (4 s (L - s)) over it (X at height d, at s along AB of length L: the arc's height
// at s is at least d / H of its height at the middle, by the power of the foot of X). When AB
// is constrained, nothing beyond it is visible from the triangle (the disk's chord on its line
// is AB itself); when it is a final hull edge, there is no data beyond it. Either way a
// rectangle over AB of that height holds all of the disk that data could reach. This settles
// the slivers a ring makes with the points a hair off its line (centimetre coordinates have
// many) or with the hull where it crosses it, whose circumcentres lie too far off for
// circumdisk_bound() to be of use.
bool is_final_by_cap(const mesh::Triangulation& tin, const TileSetup& tile, TriangleId t) {
  for (std::uint32_t i = 0; i < 3; ++i) {
    const auto e = static_cast<EdgeId>(3 * t + i);
    const bool on_hull = tin.is_ghost(mesh::triangle_of(tin.twin(e)));
    if (!on_hull && !tin.is_constrained(e)) continue;
    const Point2 a = tin.point(tin.origin(e)), b = tin.point(tin.dest(e)),
                 x = tin.point(tin.apex(e));
    if ((a.x - x.x) * (b.x - x.x) + (a.y - x.y) * (b.y - x.y) >= 0) continue;  // not obtuse
    if (on_hull && !is_final_hull_edge(tile, b, a)) return false;
    const double ux = b.x - a.x, uy = b.y - a.y, length = std::hypot(ux, uy);
    const double s = ((x.x - a.x) * ux + (x.y - a.y) * uy) / length;
    const double d = (ux * (x.y - a.y) - uy * (x.x - a.x)) / length;
    if (!(s > 0 && s < length && d >= 0)) return false;
    const double h = 2 * d * length * length / (4 * s * (length - s)) + 4 * tile.margin;
    const Point2 lift{-uy / length * h, ux / length * h};  // towards X
    const Point2 b_up{b.x + lift.x, b.y + lift.y}, a_up{a.x + lift.x, a.y + lift.y};
    return std::none_of(tile.missing.begin(), tile.missing.end(), [&](const tiles::Polygon& p) {
      return tiles::may_meet(a, b, b_up, p, tile.margin) ||
             tiles::may_meet(a, b_up, a_up, p, tile.margin);
    });
  }
  return false;
}

// Whether no data the tile lacks may lie in circumdisk bound D of triangle T, or behind its walls.
bool disk_is_clear(const mesh::Triangulation& tin, const TileSetup& tile, TriangleId t,
                   const tiles::Disk& d) {
  if (tiles::inside(d, tile.buffered)) return true;
  const double margin = tile.margin;
  const auto c = tin.triangle(t);
  const Point2 p[3] = {tin.point(c[0]), tin.point(c[1]), tin.point(c[2])};
  bool constrained[3];
  for (int i = 0; i < 3; ++i) constrained[i] = tin.is_constrained(3 * t + i);
  std::vector<Wall> walls;
  bool walls_found = false;
  for (const tiles::Polygon& piece : tile.missing) {
    if (!tiles::may_meet(d, piece, margin)) continue;
    if (tiles::may_meet(p[0], p[1], p[2], piece, margin)) return false;
    if (!walls_found) {
      walls = walls_of(tin, t, p, d, margin);
      walls_found = true;
    }
    if (walls.empty()) return false;
    tiles::Polygon seen = piece;
    for (const Wall& w : walls) seen = tiles::clip_left(seen, w.a, w.b, margin);
    for (int i = 0; i < 3 && !seen.empty(); ++i) {
      if (constrained[i]) continue;
      // Beyond edge p[i] -> p[i + 1]: on its right, the left of p[i + 1] -> p[i].
      const tiles::Polygon beyond = tiles::clip_left(seen, p[(i + 1) % 3], p[i], margin);
      if (tiles::may_meet(d, beyond, margin)) return false;
    }
  }
  return true;
}

// Whether what T sees of its circumdisk (bound D) holds no data the tile lacks, followed through
// the TIN: a point of the disk that T sees is joined to T by a segment inside the disk that
// crosses no constrained edge, so it lies in a triangle reached from T across unconstrained
// edges, each meeting the disk. When every triangle so reached is clear of the missing regions
// (and every hull edge met is final), nothing unread is in sight. This settles the slivers whose
// disk is far larger than the pocket or channel of constrained edges around them (points a hair
// off a ring's line), which the walls of disk_is_clear() do not reach. At most kSightTriangles
// are followed. (A segment from T through a vertex V instead of an edge would make V, strictly
// inside the disk, visible from T: T would not be constrained Delaunay in the tile's TIN.)
bool is_final_by_sight(const mesh::Triangulation& tin, const TileSetup& tile, TriangleId t,
                       const tiles::Disk& d) {
  constexpr std::size_t kSightTriangles = 512;
  const auto corners = [&tin](TriangleId n) {
    const auto c = tin.triangle(n);
    return tiles::Polygon{tin.point(c[0]), tin.point(c[1]), tin.point(c[2])};
  };
  const auto clear = [&tile](const tiles::Polygon& p) {
    return std::none_of(tile.missing.begin(), tile.missing.end(), [&](const tiles::Polygon& m) {
      return tiles::may_meet(p[0], p[1], p[2], m, tile.margin);
    });
  };
  if (!clear(corners(t))) return false;
  std::vector<TriangleId> seen{t};
  for (std::size_t head = 0; head < seen.size(); ++head) {
    for (std::uint32_t i = 0; i < 3; ++i) {
      const auto e = static_cast<EdgeId>(3 * seen[head] + i);
      if (tin.is_constrained(e)) continue;
      const TriangleId n = mesh::triangle_of(tin.twin(e));
      if (std::find(seen.begin(), seen.end(), n) != seen.end()) continue;
      if (tin.is_ghost(n)) {
        if (!is_final_hull_edge(tile, tin.point(tin.dest(e)), tin.point(tin.origin(e))))
          return false;
        continue;
      }
      const tiles::Polygon p = corners(n);
      if (!tiles::may_meet(d, p, tile.margin)) continue;
      if (!clear(p) || seen.size() == kSightTriangles) return false;
      seen.push_back(n);
    }
  }
  return true;
}

// Whether triangle T, whose circumdisk lies within D, is final (see the top of the file).
bool is_final(const mesh::Triangulation& tin, const TileSetup& tile, TriangleId t,
              const tiles::Disk& d) {
  return disk_is_clear(tin, tile, t, d) || is_final_by_cap(tin, tile, t) ||
         is_final_by_sight(tin, tile, t, d);
}

// What the checks found, for the summary or for the error that names a large enough buffer.
struct FinalityTally {
  std::uint64_t owned = 0, checked = 0, failed = 0;
  std::uint64_t beyond = 0;   // final with a circumcircle beyond the buffered box
  std::uint64_t trimmed = 0;  // owned and removed by --max-edge
  double reach = 0;           // how far the other circumcircles reach beyond the tile
  double failed_reach = 0;    // how far those of the failures do
  bool unbounded = false;     // a failure no estimate covers (hull edge, flat triangle)
  Point2 at{0, 0};            // a failure, for the message
};

void add(FinalityTally& tally, const FinalityTally& more) {
  tally.failed += more.failed;
  tally.unbounded = tally.unbounded || more.unbounded;
  if (more.failed_reach >= tally.failed_reach && more.failed_reach > 0) {
    tally.failed_reach = more.failed_reach;
    tally.at = more.at;
  }
}

// A failure of the finality proof at real triangle T, whose circumdisk lies within D.
void count_failure(const mesh::Triangulation& tin, const TileSetup& tile, TriangleId t,
                   const tiles::Disk& d, FinalityTally& tally) {
  ++tally.failed;
  const double r = tiles::reach_beyond(d, tile.box);
  if (!std::isfinite(r)) {
    tally.unbounded = true;
  } else if (r >= tally.failed_reach) {
    const auto c = tin.triangle(t);
    const Point2 a = tin.point(c[0]), b = tin.point(c[1]), p = tin.point(c[2]);
    tally.failed_reach = r;
    tally.at = {(a.x + b.x + p.x) / 3, (a.y + b.y + p.y) / 3};
  }
}

// --max-edge in a tile. The whole job removes each component of long-edged triangles (joined
// across any edge) that touches the hull (terrain/trim.hpp). The tile follows a final
// triangle's component through its TIN: the component and its fate are the whole TIN's when
// every triangle of it is final, and so is every neighbour around it (a final triangle's edges
// are the whole TIN's, but the triangle across one is only when final too) and every hull edge
// it touches; otherwise the buffer is too small.
class TileTrim {
 public:
  TileTrim(const mesh::Triangulation& tin, const TileSetup& tile, double max_edge)
      : tin_(tin),
        tile_(tile),
        max_edge_(max_edge),
        component_(tin.triangle_slots(), kNone),
        trimmed_(tin.triangle_slots(), 0) {}

  // Whether the whole job trims final real triangle T; false, with the failure counted in
  // TALLY, when the tile cannot tell.
  bool trimmed(TriangleId t, FinalityTally& tally) {
    if (!terrain::has_long_edge(tin_, t, max_edge_)) return false;
    if (component_[t] == kNone) follow(t, tally);
    trimmed_[t] = fate_[component_[t]] == Fate::trimmed;
    return trimmed_[t];
  }

  // The final triangles trimmed() found trimmed, 1 per slot.
  const std::vector<std::uint8_t>& found_trimmed() const { return trimmed_; }

 private:
  enum class Fate : std::uint8_t { kept, trimmed, unknown };
  static constexpr std::uint32_t kNone = kNoId;

  bool is_final_triangle(TriangleId t, FinalityTally& tally) const {
    const auto c = tin_.triangle(t);
    const tiles::Disk d =
        tiles::circumdisk_bound(tin_.point(c[0]), tin_.point(c[1]), tin_.point(c[2]));
    if (is_final(tin_, tile_, t, d)) return true;
    count_failure(tin_, tile_, t, d, tally);
    return false;
  }

  // The component of SEED, breadth first from it. One final hull edge reached through final
  // triangles proves it trimmed; kept needs the whole component and its surroundings final. The
  // failures of the proof count only when neither holds (the job then reads more).
  void follow(TriangleId seed, FinalityTally& tally) {
    const auto id = static_cast<std::uint32_t>(fate_.size());
    FinalityTally doubts;
    const auto fate = [&] {
      std::vector<TriangleId> queue{seed};
      component_[seed] = id;
      for (std::size_t head = 0; head < queue.size(); ++head) {
        const TriangleId t = queue[head];
        if (t != seed && !is_final_triangle(t, doubts)) continue;
        for (std::uint32_t i = 0; i < 3; ++i) {
          const EdgeId e = 3 * t + i;
          const TriangleId n = mesh::triangle_of(tin_.twin(e));
          if (tin_.is_ghost(n)) {
            // The ghost runs the other way: dest -> origin.
            if (is_final_hull_edge(tile_, tin_.point(tin_.dest(e)), tin_.point(tin_.origin(e))))
              return Fate::trimmed;
            ++doubts.failed;
            doubts.unbounded = true;
          } else if (terrain::has_long_edge(tin_, n, max_edge_)) {
            // An earlier walk reached N from a final triangle of its own and stopped (trimmed)
            // or failed: when N is final too, this is the same component of the whole TIN.
            if (component_[n] != kNone && component_[n] != id) {
              if (is_final_triangle(n, doubts)) return fate_[component_[n]];
            } else if (component_[n] == kNone) {
              component_[n] = id;
              queue.push_back(n);
            }
          } else {
            is_final_triangle(n, doubts);
          }
        }
      }
      return doubts.failed > 0 ? Fate::unknown : Fate::kept;
    }();
    if (fate == Fate::unknown) add(tally, doubts);
    fate_.push_back(fate);
  }

  const mesh::Triangulation& tin_;
  const TileSetup& tile_;
  double max_edge_;
  std::vector<std::uint32_t> component_;  // per triangle slot
  std::vector<Fate> fate_;                // per component
  std::vector<std::uint8_t> trimmed_;     // per triangle slot
};

// Ghost (u, v, inf): the outer side of hull edge v -> u is the open half-plane left of u -> v.
// Where it reaches the tile, no data may lie in it outside the buffered box.
void check_hull_edge(const mesh::Triangulation& tin, const TileSetup& tile, const BBox& near,
                     const std::array<VertexId, 3>& c, FinalityTally& tally) {
  const int i = c[0] == mesh::kInfinite ? 1 : (c[1] == mesh::kInfinite ? 2 : 0);
  const Point2 u = tin.point(c[i]), v = tin.point(c[(i + 1) % 3]);
  if (!tiles::reaches_left_of(u, v, near)) return;
  ++tally.checked;
  const bool final = is_final_hull_edge(tile, u, v);
  ++tally.beyond;
  if (!final) {
    ++tally.failed;
    tally.unbounded = true;
    tally.at = {(u.x + v.x) / 2, (u.y + v.y) / 2};
  }
}

// A real triangle: removed when it does not meet NEAR; else checked final, and kept when the
// tile owns it (the others go to job.dem_extra_triangles, for the DEM). The final ones are
// marked in job.proven_triangles.
void check_triangle(TileJob& job, const BBox& near, const tiles::Polygon& near_polygon,
                    TileTrim* trim, TriangleId t, FinalityTally& tally) {
  const TileSetup& tile = job.tile;
  mesh::Triangulation& tin = job.tin();
  const auto c = tin.triangle(t);
  const Point2 a = tin.point(c[0]), b = tin.point(c[1]), p = tin.point(c[2]);
  BBox box;
  box.add(a.x, a.y);
  box.add(b.x, b.y);
  box.add(p.x, p.y);
  // The triangle itself, not only its bounding box: where the tile reads the rim, the gap
  // between the buffered box and the rim is spanned by large triangles that cannot be final,
  // and their boxes may reach the tile although they do not (a lattice's rim column on the
  // tile's edge did).
  if (!tiles::intersects(box, near) || !tiles::may_meet(a, b, p, near_polygon, tile.margin)) {
    tin.set_removed(t, true);
    return;
  }
  ++tally.checked;
  const tiles::Disk d = tiles::circumdisk_bound(a, b, p);
  const double r = tiles::reach_beyond(d, tile.box);
  if (r <= tile.buffer)
    tally.reach = std::max(tally.reach, r);
  else
    ++tally.beyond;
  const bool owned = tile.grid.holds(tile.col, tile.row, tiles::owner_point(a, b, p));
  if (!is_final(tin, tile, t, d)) {
    count_failure(tin, tile, t, d, tally);
  } else {
    job.proven_triangles[t] = 1;
    if (trim && trim->trimmed(t, tally)) {
      tally.trimmed += owned;
      tin.set_removed(t, true);  // neither the tile's nor its DEM's
      return;
    }
  }
  if (owned) {
    ++tally.owned;
  } else {
    tin.set_removed(t, true);
    job.dem_extra_triangles.push_back(t);
  }
}

// The longest segment of the soft lines and polygon rings (0 without any).
double longest_feature_segment(const TileJob& job) {
  double longest = 0;
  for (const pipeline::detail::SurfaceInput* input :
       {&job.soft, &job.clip, &job.erase, &job.replace})
    for (const io::ShapeFeature& f : input->data.features)
      for (const io::ShapePart& part : f.parts)
        for (std::size_t i = 0; i < part.points.size(); ++i) {
          const Point3& a = part.points[i];
          const Point3& b = part.points[(i + 1) % part.points.size()];
          if (i + 1 < part.points.size() || part.closed)
            longest = std::max(longest, std::hypot(b.x - a.x, b.y - a.y));
        }
  return longest;
}

[[noreturn]] void throw_buffer_too_small(const TileJob& job, const std::string& name,
                                         const FinalityTally& tally) {
  const TileSetup& tile = job.tile;
  std::string detail = "buffer " + number(tile.buffer) +
                       " is too small: " + count_text(tally.failed, "triangle") +
                       " near the tile could still change (one near " + place_text(tally.at) + ")";
  // Past a hull edge of the points read, a larger buffer usually finds more points; the
  // estimate from the circles is then a lower bound.
  if (tally.failed_reach > 0) {
    detail += "; a buffer of " + number(suggested_buffer(tally.failed_reach)) +
              (tally.unbounded ? " or more" : "") + " is needed";
  } else {
    detail +=
        "; the data's outline near the tile is not settled within the buffer: try a "
        "buffer of a tile size or more";
  }
  // A long segment through dense points has thin triangles along it whose circles reach far
  // along it: no buffer shorter than the segment settles them. Split, the pieces settle, unless
  // they lie on one straight line and points lie a hair off it all along (docs/tiling.md).
  if (const double longest = longest_feature_segment(job); longest > tile.grid.size)
    detail += "; the soft lines and polygon rings have segments up to " + number(longest) +
              " long, and the thin triangles along one settle only when the tile reads along "
              "all of it: split them (e.g. ogr2ogr -segmentize " +
              number(tile.grid.size / 20) + ")";
  else if (tally.failed_reach > 1e6 * tile.grid.size)
    detail +=
        "; a sliver of points a hair off a straight line or ring sees along it as far "
        "as it runs straight: build this area without --plan";
  throw BufferTooSmall(tile.plan_path, name, detail,
                       {.used = tile.buffer,
                        .needed = tally.failed_reach > 0 ? suggested_buffer(tally.failed_reach) : 0,
                        .tile_size = tile.grid.size,
                        .largest = tile.largest_buffer});
}

// --replace: a vertex takes a polygon's height when any triangle around it lies inside, so
// every triangle around a corner of a triangle the tile writes or rasterizes must be final too.
void prove_corner_fans(TileJob& job, FinalityTally& tally) {
  const mesh::Triangulation& tin = job.mesh.tin;
  std::vector<std::uint8_t>& proven = job.proven_triangles;
  const auto prove_fans_of = [&](TriangleId t) {
    for (std::uint32_t i = 0; i < 3; ++i) {
      const auto start = static_cast<EdgeId>(3 * t + i);
      EdgeId e = start;
      do {
        const TriangleId n = mesh::triangle_of(e);
        if (!tin.is_ghost(n) && !proven[n]) {
          const auto c = tin.triangle(n);
          const tiles::Disk d =
              tiles::circumdisk_bound(tin.point(c[0]), tin.point(c[1]), tin.point(c[2]));
          if (is_final(tin, job.tile, n, d))
            proven[n] = 1;
          else
            count_failure(tin, job.tile, n, d, tally);
        }
        e = tin.twin(mesh::prev_edge(e));
      } while (e != start);
    }
  };
  const auto slots = static_cast<TriangleId>(tin.triangle_slots());
  for (TriangleId t = 0; t < slots; ++t)
    if (!tin.is_ghost(t) && tin.is_kept(t)) prove_fans_of(t);
  for (const TriangleId t : job.dem_extra_triangles) prove_fans_of(t);
}

// Every corner of a triangle the tile writes or rasterizes (or, with ALSO, 1 per slot, measures
// in its simplification) has a height: a draped vertex whose triangle the tile could not prove
// final has none (SurfaceScope::settled), and the tile then reads more.
void check_heights_settled(TileJob& job, const std::vector<std::uint8_t>* also = nullptr) {
  const mesh::Triangulation& tin = job.mesh.tin;
  const auto unsettled = [&tin](TriangleId t) {
    const auto c = tin.triangle(t);
    return std::isnan(tin.z(c[0])) || std::isnan(tin.z(c[1])) || std::isnan(tin.z(c[2]));
  };
  std::uint64_t count = 0;
  Point2 at{0, 0};
  const auto look = [&](TriangleId t) {
    if (!unsettled(t)) return;
    const auto c = tin.triangle(t);
    if (count++ == 0) at = tiles::owner_point(tin.point(c[0]), tin.point(c[1]), tin.point(c[2]));
  };
  tin.for_each_triangle([&](TriangleId t, const std::array<VertexId, 3>&) { look(t); });
  for (const TriangleId t : job.dem_extra_triangles) look(t);
  if (also)
    for (std::size_t t = 0; t < also->size(); ++t)
      if ((*also)[t]) look(static_cast<TriangleId>(t));
  if (count == 0) return;
  const TileSetup& tile = job.tile;
  throw BufferTooSmall(tile.plan_path, "tile " + std::to_string(tile.index),
                       "buffer " + number(tile.buffer) +
                           " is too small: " + count_text(count, "triangle") +
                           " near the tile have a corner draped from a triangle that could "
                           "still change (one near " +
                           place_text(at) + ")",
                       {.used = tile.buffer,
                        .needed = 0,
                        .tile_size = tile.grid.size,
                        .largest = tile.largest_buffer});
}

void run(TileJob& job) {
  const TileSetup& tile = job.tile;
  mesh::Triangulation& tin = job.tin();
  const BBox near = checked_region(tile);
  const tiles::Polygon near_polygon = tiles::box_polygon(near);
  FinalityTally tally;
  std::optional<TileTrim> trim;
  if (job.options.max_edge > 0) trim.emplace(tin, tile, job.options.max_edge);
  const std::size_t slots = tin.triangle_slots();
  job.proven_triangles.assign(slots, 0);
  for (std::size_t s = 0; s < slots; ++s) {
    const auto t = static_cast<TriangleId>(s);
    if (tin.is_ghost(t))
      check_hull_edge(tin, tile, near, tin.triangle(t), tally);
    else
      check_triangle(job, near, near_polygon, trim ? &*trim : nullptr, t, tally);
  }
  if (!job.options.replace.empty()) prove_corner_fans(job, tally);

  const std::string name = "tile " + std::to_string(tile.index);
  if (tally.failed > 0) throw_buffer_too_small(job, name, tally);
  job.report.trimmed_triangles = tally.trimmed;
  // Its border may then be the edge of a trimmed, clipped or erased area, which tincdt merge
  // must not take for a crack (even when this tile removed nothing, its neighbour may have).
  const pipeline::BuildOptions& o = job.options;
  if (o.max_edge > 0 || !o.clip.empty() || !o.erase.empty())
    job.write.ply_trimmed = detail::mark_text({tile.tile_count, {tile.index}});
  if (o.max_error) {
    check_heights_settled(job, trim ? &trim->found_trimmed() : nullptr);  // to be measured
    // As in the whole job, the trimmed outline is kept through the simplification and what lies
    // beyond it removed after (stage_simplify.cpp): the fence's edges in the tile are between
    // final triangles, so both tiles of a border fence it alike.
    if (trim) terrain::fence_trimmed(tin, trim->found_trimmed());
    const std::optional<mesh::Triangulation> full = detail::simplify_tile(job);
    // The simplified TIN's triangles beyond the tile's border may straddle rings it did not
    // read: the polygon stages classify the tile's own.
    if (full) {
      const mesh::Triangulation& simplified = job.tin();
      job.proven_triangles.assign(simplified.triangle_slots(), 0);
      simplified.for_each_triangle([&](TriangleId t, const auto&) { job.proven_triangles[t] = 1; });
    }
    if (trim && full)
      job.report.trimmed_triangles = terrain::remove_marked_regions(
          job.tin(), terrain::mark_trimmed_areas(*full, trim->found_trimmed(), job.tin()));
  }
  job.info(name + ": " + count_text(tally.owned, "triangle") + " owned, " +
           count_text(tally.checked) +
           " checked final: " + count_text(tally.checked - tally.beyond) +
           " with a circumcircle inside the buffered box (reaching " + number(tally.reach) +
           " beyond the tile; buffer " + number(tile.buffer) + "), " + count_text(tally.beyond) +
           " by the rim, their constrained edges or areas without data");
}

// Only a TileJob runs the stages (tile_stages()).
void run_tile(pipeline::Job& job) {
  run(static_cast<TileJob&>(job));
}

// After the polygon stages, which may remove more of the tile's triangles and give heights to
// the vertices of replace polygons.
void write_tile_outline(pipeline::Job& pipeline_job) {
  TileJob& job = static_cast<TileJob&>(pipeline_job);
  check_heights_settled(job);
  if (job.outline.empty()) return;
  io::OutputFile& out = pipeline_job.add_output(job.outline, "outline");
  detail::write_outline(out, outline_of(job.mesh.tin), "", job.write.ply_trimmed);
  pipeline_job.finish_output(out);
}

}  // namespace

bool proven_final(const mesh::Triangulation& tin, const TileSetup& tile, TriangleId t) {
  const auto c = tin.triangle(t);
  return is_final(tin, tile, t,
                  tiles::circumdisk_bound(tin.point(c[0]), tin.point(c[1]), tin.point(c[2])));
}

constexpr pipeline::StageProgress kTileProgress{"cutting the tile", "triangles",
                                                pipeline::stage_items::triangles};
extern const pipeline::Stage tile_stage{"tile",  "tile", wanted, run_tile,
                                        nullptr, "",     {},     kTileProgress};
constexpr pipeline::StageProgress kOutlineProgress{"writing the tile's outline"};
extern const pipeline::Stage tile_outline_stage{"tile_outline", "tile", wanted, write_tile_outline,
                                                nullptr,        "",     {},     kOutlineProgress};

}  // namespace tincdt::tiles
