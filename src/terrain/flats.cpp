#include "terrain/flats.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <queue>
#include <utility>

#include "core/error.hpp"
#include "mesh/geometry.hpp"
#include "mesh/point_insertion.hpp"
#include "predicates/predicates.hpp"
#include "terrain/quality.hpp"

namespace tincdt::terrain {

using mesh::kInfinite;
using mesh::Location;
using mesh::Triangulation;
using predicates::orient2d;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double distance(Point2 p, Point2 q) {
  return std::hypot(p.x - q.x, p.y - q.y);
}

double segment_distance(Point2 p, Point2 a, Point2 b) {
  const double abx = b.x - a.x, aby = b.y - a.y, apx = p.x - a.x, apy = p.y - a.y;
  const double len2 = abx * abx + aby * aby;
  const double t = len2 > 0 ? std::clamp((apx * abx + apy * aby) / len2, 0.0, 1.0) : 0.0;
  return std::hypot(apx - t * abx, apy - t * aby);
}

double min_angle(Point2 a, Point2 b, Point2 c) {
  const Point2 p[3] = {a, b, c};
  double smallest = std::numbers::pi;
  for (int i = 0; i < 3; ++i) {
    const Point2 o = p[i], u = p[(i + 1) % 3], v = p[(i + 2) % 3];
    const double ux = u.x - o.x, uy = u.y - o.y, vx = v.x - o.x, vy = v.y - o.y;
    smallest = std::min(smallest, std::atan2(std::fabs(ux * vy - uy * vx), ux * vx + uy * vy));
  }
  return smallest;
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// The nearest features around a point, within its region (see FlatFixer::search).
struct Nearest {
  double d_same = kInf;   // to the region's own level (its contour)
  double d_other = kInf;  // to another level
  double z_other = kNaN;  // that level
};

// How a region that holds no other level gets its heights: the slope and direction found just
// across its contour.
struct Outside {
  bool known = false;
  double sign = 0;      // +1: the ground rises from the contour into the region, -1: it falls
  double slope = 0;     // level difference per unit of horizontal distance
  double interval = 0;  // the level difference to the next contour outside
};

class FlatFixer {
 public:
  FlatFixer(Triangulation& tin, const std::vector<std::uint8_t>& on_contour,
            const FlatFixOptions& options, FlatFixReport& report)
      : tin_(tin),
        on_contour_(on_contour),
        options_(options),
        report_(report),
        original_vertices_(static_cast<VertexId>(tin.vertex_count())) {}

  bool flat(TriangleId t) const {
    return !tin_.is_ghost(t) && is_flat(tin_, tin_.triangle(t), &on_contour_);
  }

  // Phase 1. A flip of edge a -> b of flat (a, b, c) with neighbour (b, a, d) gives (d, c, a) and
  // (c, d, b); with z(a) = z(b) = z(c) both are non-flat unless d is a contour vertex at that
  // level too, and then the neighbour was flat before. So each flip removes exactly one flat and
  // makes none: the loop ends after at most as many flips as there were flats. Of the possible
  // flips of a triangle the one with the largest smallest angle wins (no needless slivers).
  void swap_phase() {
    std::vector<TriangleId> work;
    const auto slots = static_cast<TriangleId>(tin_.triangle_slots());
    for (TriangleId t = 0; t < slots; ++t)
      if (flat(t)) work.push_back(t);
    while (!work.empty()) {
      const TriangleId t = work.back();
      work.pop_back();
      if (!flat(t)) continue;
      EdgeId best = kNoId;
      double best_angle = -1;
      for (EdgeId e = 3 * t; e < 3 * t + 3; ++e) {
        if (tin_.is_constrained(e)) continue;
        const EdgeId f = tin_.twin(e);
        if (tin_.is_ghost(mesh::triangle_of(f))) continue;
        const VertexId a = tin_.origin(e), b = tin_.dest(e), c = tin_.apex(e), d = tin_.apex(f);
        const Point2 pa = tin_.point(a), pb = tin_.point(b), pc = tin_.point(c), pd = tin_.point(d);
        // Strictly convex quadrilateral: a and b strictly on opposite sides of c-d.
        if (orient2d(pc, pd, pa) * orient2d(pc, pd, pb) >= 0) continue;
        if (is_flat(tin_, {d, c, a}, &on_contour_) || is_flat(tin_, {c, d, b}, &on_contour_))
          continue;
        const double angle = std::min(min_angle(pd, pc, pa), min_angle(pc, pd, pb));
        if (angle > best_angle) {
          best_angle = angle;
          best = e;
        }
      }
      if (best == kNoId) continue;
      const TriangleId other = mesh::triangle_of(tin_.twin(best));
      tin_.flip(best);
      ++report_.swaps;
      // The flat neighbours of the new pair face a new apex across their shared edge: retry them.
      for (TriangleId s : {t, other})
        for (EdgeId e = 3 * s; e < 3 * s + 3; ++e) {
          const TriangleId n = mesh::triangle_of(tin_.twin(e));
          if (flat(n)) work.push_back(n);
        }
    }
  }

  // Phase 2: one Steiner vertex per flat triangle that is left, largest first, until none is.
  // A new vertex is on no contour, so every triangle made around it is non-flat, and each
  // insertion destroys at least the triangle it lands in: the loop is bounded by the flats.
  void insert_phase() {
    label_regions();
    measure_outsides();
    mesh::PointInserter inserter(tin_);
    std::priority_queue<std::pair<double, TriangleId>> work;  // longest free edge first
    const auto slots = static_cast<TriangleId>(tin_.triangle_slots());
    for (TriangleId t = 0; t < slots; ++t)
      if (flat(t)) work.push({longest_free_edge(t), t});
    while (!work.empty()) {
      const TriangleId t = work.top().second;
      work.pop();
      // A slot that was rewritten holds a triangle with a new vertex: not flat any more.
      if (!flat(t)) continue;
      const std::uint32_t r = region_[t];
      const double level = tin_.z(tin_.origin(3 * t));
      const bool closed = closed_region(r, level);
      if (closed && !outside_[r].known) continue;  // counted as "no level" at the end
      Point2 s;
      Location at{};
      if (!place(t, inserter, s, at)) continue;  // counted as "unplaced" at the end
      const Nearest near = search(s, t, level, true, !closed);
      double z;
      if (closed) {
        const Outside& o = outside_[r];
        z = level +
            o.sign * std::min(o.slope * near.d_same, options_.extrapolation_cap * o.interval);
        ++report_.vertices_extrapolated;
      } else if (std::isfinite(near.d_other) && std::isfinite(near.d_same)) {
        // Linear in the distances to the two contours: the point's share of the way across.
        z = level + (near.z_other - level) * near.d_same / (near.d_same + near.d_other);
        ++report_.vertices_interpolated;
      } else {
        continue;
      }
      const VertexId v = tin_.add_vertex(s, z);
      inserter.insert(v, at);
      ++report_.vertices_added;
      region_.resize(tin_.triangle_slots(), r);  // new slots lie in the same region
      stamp_.resize(tin_.triangle_slots(), 0);
    }
  }

  // Counts the flats left and sorts them by reason.
  void explain_left() {
    const auto slots = static_cast<TriangleId>(tin_.triangle_slots());
    for (TriangleId t = 0; t < slots; ++t) {
      if (!flat(t)) continue;
      ++report_.flats_after;
      if (!options_.insert) {
        ++report_.flats_left_not_tried;
      } else {
        const std::uint32_t r = region_[t];
        if (closed_region(r, tin_.z(tin_.origin(3 * t))) && !outside_[r].known)
          ++report_.flats_left_no_level;
        else
          ++report_.flats_left_unplaced;
      }
    }
  }

 private:
  bool closed_region(std::uint32_t r, double level) const {
    return region_min_[r] == level && region_max_[r] == level;
  }

  double longest_free_edge(TriangleId t) const {
    double longest = 0;
    bool free_found = false;
    for (EdgeId e = 3 * t; e < 3 * t + 3; ++e) {
      const bool free = !tin_.is_constrained(e);
      const double len = distance(tin_.point(tin_.origin(e)), tin_.point(tin_.dest(e)));
      if (free && (!free_found || len > longest)) {
        longest = len;
        free_found = true;
      } else if (!free_found) {
        longest = std::max(longest, len);
      }
    }
    return longest;
  }

  // Regions: triangles connected across unconstrained edges, i.e. the pieces of the TIN between
  // contours (and other constraints). A Steiner vertex's height comes from its own region only:
  // looking across a contour would mix up the two sides of a ridge or a valley.
  void label_regions() {
    const auto slots = static_cast<TriangleId>(tin_.triangle_slots());
    region_.assign(slots, kNoId);
    stamp_.assign(slots, 0);
    std::vector<TriangleId> stack;
    for (TriangleId seed = 0; seed < slots; ++seed) {
      if (tin_.is_ghost(seed) || region_[seed] != kNoId) continue;
      const auto r = static_cast<std::uint32_t>(region_min_.size());
      double lo = kInf, hi = -kInf;
      region_[seed] = r;
      stack.assign(1, seed);
      while (!stack.empty()) {
        const TriangleId t = stack.back();
        stack.pop_back();
        for (EdgeId e = 3 * t; e < 3 * t + 3; ++e) {
          const VertexId v = tin_.origin(e);
          lo = std::min(lo, tin_.z(v));
          hi = std::max(hi, tin_.z(v));
          if (tin_.is_constrained(e)) continue;
          const TriangleId n = mesh::triangle_of(tin_.twin(e));
          if (tin_.is_ghost(n) || region_[n] != kNoId) continue;
          region_[n] = r;
          stack.push_back(n);
        }
      }
      region_min_.push_back(lo);
      region_max_.push_back(hi);
    }
    outside_.assign(region_min_.size(), Outside{});
  }

  // For every region that holds no other level: from up to 16 of its contour edges, spread
  // along its outline, the distance across to the next level on the other side gives a slope
  // sample. The majority direction wins; slope and interval are its medians (robust to a sample
  // that looked along a contour instead of across it). A region whose neighbours across its
  // contour hold no other level either (a small ring inside a band that is itself closed, like a
  // pit in a plateau) takes the slope of such a neighbour once that is known, in the opposite
  // direction: crossing the same level twice turns back.
  void measure_outsides() {
    const auto slots = static_cast<TriangleId>(tin_.triangle_slots());
    const std::size_t regions = region_min_.size();
    std::vector<std::vector<EdgeId>> outline(regions);
    for (TriangleId t = 0; t < slots; ++t) {
      if (tin_.is_ghost(t)) continue;
      const std::uint32_t r = region_[t];
      if (region_min_[r] != region_max_[r]) continue;
      for (EdgeId e = 3 * t; e < 3 * t + 3; ++e) {
        if (!tin_.is_constrained(e)) continue;
        const TriangleId n = mesh::triangle_of(tin_.twin(e));
        if (!tin_.is_ghost(n) && region_[n] != r) outline[r].push_back(e);
      }
    }
    constexpr std::size_t kSamples = 16;
    for (std::size_t r = 0; r < regions; ++r) {
      const auto& edges = outline[r];
      if (edges.empty()) continue;
      const double level = region_min_[r];
      std::vector<double> up_slopes, down_slopes, up_steps, down_steps;
      const std::size_t n = std::min(kSamples, edges.size());
      for (std::size_t i = 0; i < n; ++i) {
        const EdgeId e = edges[i * edges.size() / n];
        const TriangleId across = mesh::triangle_of(tin_.twin(e));
        if (closed_region(region_[across], level)) continue;  // nothing to find there
        const Point2 a = tin_.point(tin_.origin(e)), b = tin_.point(tin_.dest(e));
        const Point2 m{a.x + (b.x - a.x) / 2, a.y + (b.y - a.y) / 2};
        const Nearest near = search(m, across, level, false, true);
        if (!(near.d_other > 0) || !std::isfinite(near.d_other)) continue;
        const double step = std::fabs(near.z_other - level);
        // Lower outside: the region rises from its contour (a hilltop, a ridge end).
        (near.z_other < level ? up_slopes : down_slopes).push_back(step / near.d_other);
        (near.z_other < level ? up_steps : down_steps).push_back(step);
      }
      if (up_slopes.empty() && down_slopes.empty()) continue;
      const bool up = up_slopes.size() >= down_slopes.size();
      Outside& o = outside_[r];
      o.known = true;
      o.sign = up ? 1 : -1;
      o.slope = median(up ? up_slopes : down_slopes);
      o.interval = median(up ? up_steps : down_steps);
    }
    for (bool changed = true; changed;) {
      changed = false;
      for (std::size_t r = 0; r < regions; ++r) {
        if (outside_[r].known) continue;
        for (EdgeId e : outline[r]) {
          const Outside& o = outside_[region_[mesh::triangle_of(tin_.twin(e))]];
          if (!o.known) continue;
          outside_[r] = {true, -o.sign, o.slope, o.interval};
          changed = true;
          break;
        }
      }
    }
  }

  // A point for the Steiner vertex of flat triangle t, on (an approximation of) the medial axis
  // of the region between the contour arms t joins. The unconstrained edges of a flat triangle
  // are chords across that region from one stretch of contour to another, and the midpoints of
  // such chords form the chordal axis, a medial-axis approximation from a constrained
  // triangulation of the outline (exact for parallel arms, and it never leaves the region).
  // Where three chords meet (a branch of the skeleton) the circumcentre is the Voronoi vertex of
  // the three contour vertices, exactly equidistant from them: used when it lies strictly inside
  // t (else it could be across a contour). Otherwise the midpoint of the longest chord (the
  // widest section), and as a last resort the centroid. A candidate is used only if it lands
  // strictly inside t or on / just across one of its chords, never on a constraint or a vertex.
  bool place(TriangleId t, mesh::PointInserter& inserter, Point2& s, Location& at) {
    const auto c = tin_.triangle(t);
    const Point2 p0 = tin_.point(c[0]), p1 = tin_.point(c[1]), p2 = tin_.point(c[2]);
    Point2 candidates[3];
    int count = 0;
    int chords = 0;
    EdgeId longest = kNoId;
    double longest_len = -1;
    for (EdgeId e = 3 * t; e < 3 * t + 3; ++e) {
      if (tin_.is_constrained(e)) continue;
      ++chords;
      const double len = distance(tin_.point(tin_.origin(e)), tin_.point(tin_.dest(e)));
      if (len > longest_len) {
        longest_len = len;
        longest = e;
      }
    }
    if (chords == 3) {
      const double bx = p1.x - p0.x, by = p1.y - p0.y, cx = p2.x - p0.x, cy = p2.y - p0.y;
      const double d = 2 * (bx * cy - by * cx);
      const double b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
      const Point2 cc{p0.x + (cy * b2 - by * c2) / d, p0.y + (bx * c2 - cx * b2) / d};
      if (orient2d(p0, p1, cc) > 0 && orient2d(p1, p2, cc) > 0 && orient2d(p2, p0, cc) > 0)
        candidates[count++] = cc;
    }
    if (longest != kNoId) {
      const Point2 a = tin_.point(tin_.origin(longest)), b = tin_.point(tin_.dest(longest));
      candidates[count++] = {a.x + (b.x - a.x) / 2, a.y + (b.y - a.y) / 2};
    }
    candidates[count++] = {p0.x + ((p1.x - p0.x) + (p2.x - p0.x)) / 3,
                           p0.y + ((p1.y - p0.y) + (p2.y - p0.y)) / 3};
    for (int i = 0; i < count; ++i) {
      const Location loc = inserter.locate(candidates[i], t);
      if (loc.kind == Location::on_vertex) continue;
      if (loc.kind == Location::on_edge && tin_.is_constrained(loc.edge)) continue;
      const TriangleId where = mesh::triangle_of(loc.edge);
      if (tin_.is_ghost(where) && loc.kind == Location::in_triangle) continue;  // off the hull
      bool near_t = where == t || mesh::triangle_of(tin_.twin(loc.edge)) == t;
      for (EdgeId e = 3 * t; e < 3 * t + 3 && !near_t; ++e)
        near_t = !tin_.is_constrained(e) && mesh::triangle_of(tin_.twin(e)) == where;
      if (!near_t) continue;
      s = candidates[i];
      at = loc;
      return true;
    }
    return false;
  }

  // Best-first search over the triangles of s's region from `start`, never across a constraint,
  // for the nearest feature at `level` (a vertex, or a constrained edge with both ends there) and
  // the nearest at another z (a vertex, or a constrained edge at one other z). Triangles are
  // taken in order of the distance from s to the edge they were entered by (never less than that
  // of their parent), and the search stops once that exceeds the distances wanted. Only input
  // vertices count: Steiner vertices made here carry derived heights.
  Nearest search(Point2 s, TriangleId start, double level, bool want_same, bool want_other) {
    Nearest r;
    if (++generation_ == 0) {  // wrapped: clear the stamps
      std::fill(stamp_.begin(), stamp_.end(), 0);
      generation_ = 1;
    }
    using Entry = std::pair<double, TriangleId>;
    heap_.clear();
    heap_.push_back({0.0, start});
    stamp_[start] = generation_;
    const auto later = [](const Entry& x, const Entry& y) { return x.first > y.first; };
    while (!heap_.empty()) {
      std::pop_heap(heap_.begin(), heap_.end(), later);
      const auto [key, t] = heap_.back();
      heap_.pop_back();
      const double bound = std::max(want_same ? r.d_same : 0.0, want_other ? r.d_other : 0.0);
      if (key >= bound) break;
      for (EdgeId e = 3 * t; e < 3 * t + 3; ++e) {
        const VertexId a = tin_.origin(e), b = tin_.dest(e);
        if (a < original_vertices_) {
          const double d = distance(s, tin_.point(a));
          if (tin_.z(a) == level) {
            r.d_same = std::min(r.d_same, d);
          } else if (d < r.d_other) {
            r.d_other = d;
            r.z_other = tin_.z(a);
          }
        }
        if (tin_.is_constrained(e)) {
          if (a < original_vertices_ && b < original_vertices_ && tin_.z(a) == tin_.z(b)) {
            const double d = segment_distance(s, tin_.point(a), tin_.point(b));
            if (tin_.z(a) == level) {
              r.d_same = std::min(r.d_same, d);
            } else if (d < r.d_other) {
              r.d_other = d;
              r.z_other = tin_.z(a);
            }
          }
          continue;  // the search stays on this side of every constraint
        }
        const TriangleId n = mesh::triangle_of(tin_.twin(e));
        if (tin_.is_ghost(n) || stamp_[n] == generation_) continue;
        stamp_[n] = generation_;
        const double k = std::max(key, segment_distance(s, tin_.point(a), tin_.point(b)));
        heap_.push_back({k, n});
        std::push_heap(heap_.begin(), heap_.end(), later);
      }
    }
    return r;
  }

  Triangulation& tin_;
  const std::vector<std::uint8_t>& on_contour_;
  const FlatFixOptions& options_;
  FlatFixReport& report_;
  const VertexId original_vertices_;
  std::vector<std::uint32_t> region_;  // per triangle slot
  std::vector<double> region_min_, region_max_;
  std::vector<Outside> outside_;
  std::vector<std::uint32_t> stamp_;  // search visits, per triangle slot
  std::uint32_t generation_ = 0;
  std::vector<std::pair<double, TriangleId>> heap_;
};

}  // namespace

std::uint64_t count_flat_triangles(const Triangulation& tin,
                                   const std::vector<std::uint8_t>& on_contour) {
  std::uint64_t n = 0;
  tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& c) {
    if (is_flat(tin, c, &on_contour)) ++n;
  });
  return n;
}

// The order: swaps first, Steiner vertices second. The swaps are cheap and add nothing, but are
// not Delaunay; Steiner insertion keeps the Delaunay property around each new vertex (its Lawson
// flips only make triangles with the new vertex in them, so they never re-create a flat, and may
// flip a swapped edge away). The reverse order would leave nothing to swap. A final Lawson pass
// over the whole TIN is not made: it would flip the swapped edges back into flats.
FlatFixReport fix_flat_triangles(Triangulation& tin, const std::vector<std::uint8_t>& on_contour,
                                 const FlatFixOptions& options) {
  const auto slots = static_cast<TriangleId>(tin.triangle_slots());
  for (TriangleId t = 0; t < slots; ++t)
    if (!tin.is_ghost(t) && tin.is_removed(t))
      throw Error("fix_flat_triangles runs before clipping, erasing or trimming the TIN");
  if (!(options.extrapolation_cap >= 0) || !std::isfinite(options.extrapolation_cap))
    throw Error("the flat-fix extrapolation cap must be a finite fraction >= 0");
  FlatFixReport report;
  report.first_new_vertex = static_cast<VertexId>(tin.vertex_count());
  FlatFixer fixer(tin, on_contour, options, report);
  report.flats_before = count_flat_triangles(tin, on_contour);
  if (options.swap) fixer.swap_phase();
  report.flats_after_swaps = count_flat_triangles(tin, on_contour);
  if (options.insert) fixer.insert_phase();
  tin.recount();
  fixer.explain_left();

  const std::size_t half_edges = 3 * tin.triangle_slots();
  for (std::size_t i = 0; i < half_edges; ++i) {
    const auto e = static_cast<EdgeId>(i);
    const VertexId a = tin.origin(e), b = tin.dest(e);
    if (a >= b || b == kInfinite || tin.is_constrained(e)) continue;
    if (!mesh::is_locally_delaunay(tin, e)) ++report.non_delaunay_edges;
  }
  return report;
}

}  // namespace tincdt::terrain
