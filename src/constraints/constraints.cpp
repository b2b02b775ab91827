#include "constraints/constraints.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <tuple>

#include "core/id_map.hpp"
#include "core/number_text.hpp"
#include "mesh/geometry.hpp"
#include "mesh/point_insertion.hpp"
#include "predicates/predicates.hpp"

namespace tincdt::constraints {

CrossingError::CrossingError(std::uint32_t a, std::uint32_t b, Point2 p)
    : GeometryError("constraints from features " + count_text(a) + " and " + count_text(b) +
                    " cross, and crossings are refused"),
      source_a(a),
      source_b(b),
      at(p) {}

namespace {

using namespace mesh;  // the half-edge vocabulary: next_edge, triangle_of, kInfinite, ...
using predicates::orient2d;

struct VertexPair {
  VertexId u;
  VertexId v;
};

// Part a -> b of the input segment WHOLE (its two end vertices). Crossings are computed from the
// whole segments, never from the parts left by earlier crossings, so that the vertex made where
// two segments cross does not depend on the order of insertion nor on the other segments a job
// holds: every job (every tile) that holds both segments makes the same vertex.
struct Work {
  VertexId a;
  VertexId b;
  std::uint32_t source;
  VertexPair whole;
};

VertexPair whole_of(const Piece& p) {
  return {p.whole_a, p.whole_b};
}

std::uint64_t edge_key(VertexId u, VertexId v) {
  return u < v ? (std::uint64_t{u} << 32 | v) : (std::uint64_t{v} << 32 | u);
}

// Circumradius over inradius, the paper's triangle quality R(T): abc * s / (4 A^2).
double aspect_ratio(Point2 p, Point2 q, Point2 r) {
  const double a = std::hypot(q.x - r.x, q.y - r.y);
  const double b = std::hypot(p.x - r.x, p.y - r.y);
  const double c = std::hypot(p.x - q.x, p.y - q.y);
  const double area2 = std::fabs((q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x));
  if (area2 == 0) return HUGE_VAL;
  return a * b * c * (a + b + c) / (2 * area2 * area2);
}

class ConstraintInserter {
 public:
  ConstraintInserter(Triangulation& tin, const ConstraintOptions& options, std::uint64_t segments,
                     std::uint64_t old_constraints)
      : tin_(tin),
        options_(options),
        points_(tin),
        crossing_bound_(segments * (segments + 2 * old_constraints)) {
    if (!tin_.has_vertex_index()) tin_.build_vertex_index();
  }

  // REPORT hears of each piece: crossings can make one segment a long piece of work.
  void insert(const Segment& segment, Progress& report) {
    const VertexPair whole = segment.whole_a == kNoId
                                 ? VertexPair{segment.a, segment.b}
                                 : VertexPair{segment.whole_a, segment.whole_b};
    work_.push_back({segment.a, segment.b, segment.source, whole});
    while (!work_.empty()) {
      const Work s = work_.back();
      work_.pop_back();
      if (s.a != s.b) insert_piece(s);
      report.heartbeat();
    }
  }

  ConstraintResult take_result() {
    result_.flips_restoration += points_.flips();
    return std::move(result_);
  }
  ConstraintResult& result() { return result_; }

 private:
  Point2 pt(VertexId v) const { return tin_.point(v); }

  void mark(EdgeId e, VertexId a, VertexId b, const Work& s) {
    tin_.set_constrained(e, true);
    result_.pieces.push_back({a, b, s.source, s.whole.u, s.whole.v});
    if (indexed_) index_piece(static_cast<std::uint32_t>(result_.pieces.size() - 1));
  }

  // Only a crossing needs to find the pieces on an edge, so the index is built at the first one.
  void index_piece(std::uint32_t piece) {
    const Piece& p = result_.pieces[piece];
    next_piece_.push_back(index_.find(edge_key(p.a, p.b)));  // chain the sources of one edge
    index_.insert(edge_key(p.a, p.b), piece);
  }

  // Makes segment a -> b (or its first part, up to a vertex on it) an edge; queues the rest.
  void insert_piece(const Work& s) {
    const VertexId a = s.a, b = s.b;
    const Point2 pa = pt(a), pb = pt(b);

    // The triangle at a that the segment leaves through: (a, r, l) with r right of a -> b and
    // l left of it, or an edge a -> u along the segment.
    // Most segments are edges already (the Delaunay stage saw their vertices): look first, with
    // no orientation test.
    if (const EdgeId ab = tin_.find_edge(a, b); ab != kNoId) {
      mark(ab, a, b, s);
      return;
    }
    EdgeId cur = kNoId;
    VertexId r = kNoId, l = kNoId;
    const EdgeId first = tin_.edge_from(a);
    EdgeId e = first;
    do {
      const VertexId u = tin_.dest(e), w = tin_.apex(e);
      if (u != kInfinite) {
        const int side_u = orient2d(pa, pb, pt(u));
        if (side_u == 0 &&
            (pt(u).x - pa.x) * (pb.x - pa.x) + (pt(u).y - pa.y) * (pb.y - pa.y) > 0) {
          ++result_.split_at_vertices;  // the segment runs through u: a -> u now, u -> b later
          mark(e, a, u, s);
          work_.push_back({u, b, s.source, s.whole});
          return;
        }
        if (side_u < 0 && w != kInfinite && orient2d(pa, pb, pt(w)) > 0) {
          cur = next_edge(e);  // u -> w
          r = u;
          l = w;
          break;
        }
      }
      e = tin_.twin(prev_edge(e));
    } while (e != first);
    if (cur == kNoId)
      throw GeometryError("internal: segment " + count_text(a) + "-" + count_text(b) +
                          " leaves its first vertex through no triangle");

    // Walk along the segment collecting the crossed edges (paper step C.1).
    crossed_.clear();
    VertexId end = b;
    for (;;) {
      if (tin_.is_constrained(cur)) {
        split_crossing(s, r, l);
        return;
      }
      crossed_.push_back({r, l});
      const EdgeId t = tin_.twin(cur);  // l -> r in triangle (l, r, x)
      const VertexId x = tin_.apex(t);
      if (x == b) break;
      const int side = orient2d(pa, pb, pt(x));
      if (side == 0) {  // x lies on the segment: insert a -> x now, x -> b later
        ++result_.split_at_vertices;
        end = x;
        work_.push_back({x, b, s.source, s.whole});
        break;
      }
      if (side > 0) {
        cur = next_edge(t);  // r -> x
        l = x;
      } else {
        cur = prev_edge(t);  // x -> l
        r = x;
      }
    }
    swap_in(pa, pt(end));
    const EdgeId ab = tin_.find_edge(a, end);
    mark(ab, a, end, s);
    restore();
  }

  // Paper step C.2 in Sloan's order: swap each crossed edge whose quadrilateral is strictly
  // convex; one that still crosses goes back in the queue, as does one that is not convex yet.
  void swap_in(Point2 pa, Point2 pb) {
    created_.clear();
    // In rounds: every edge still crossing goes to the next round, in order, so the whole is
    // one FIFO queue without a consumed prefix to keep.
    while (!crossed_.empty()) {
      waiting_.clear();
      const std::uint64_t flips_before = result_.flips_insertion;
      for (const VertexPair q : crossed_) {
        const EdgeId e = tin_.find_edge(q.u, q.v);
        const VertexId c = tin_.apex(e), d = tin_.apex(tin_.twin(e));
        const Point2 pc = pt(c), pd = pt(d);
        if (orient2d(pc, pd, pt(q.u)) * orient2d(pc, pd, pt(q.v)) >= 0) {
          waiting_.push_back(q);  // not strictly convex: wait for a neighbour's swap
          continue;
        }
        tin_.flip(e);
        ++result_.flips_insertion;
        if (orient2d(pa, pb, pc) * orient2d(pa, pb, pd) < 0) {
          waiting_.push_back({c, d});
        } else {
          created_.push_back({c, d});
        }
      }
      // A round without a swap would repeat forever: the convexity argument failed.
      if (result_.flips_insertion == flips_before)
        throw InternalError("inserting a constraint: " + count_text(crossed_.size()) +
                            " crossed edges, none of which can be swapped");
      crossed_.swap(waiting_);
    }
  }

  // Paper step C.3 / D: improve the triangles around the new edges, never flipping a constraint.
  void restore() {
    if (options_.restore == Restore::none) return;
    std::vector<VertexPair>& stack = created_;
    while (!stack.empty()) {
      const VertexPair q = stack.back();
      stack.pop_back();
      const EdgeId e = tin_.find_edge(q.u, q.v);
      if (e == kNoId || tin_.is_constrained(e)) continue;
      if (!should_flip(e)) continue;
      const EdgeId f = tin_.twin(e);
      const VertexId a = tin_.origin(e), b = tin_.dest(e), c = tin_.apex(e), d = tin_.apex(f);
      tin_.flip(e);
      ++result_.flips_restoration;
      stack.push_back({a, d});
      stack.push_back({d, b});
      stack.push_back({b, c});
      stack.push_back({c, a});
    }
  }

  bool should_flip(EdgeId e) const {
    if (options_.restore == Restore::delaunay) return !mesh::is_locally_delaunay(tin_, e);
    const EdgeId f = tin_.twin(e);
    const VertexId a = tin_.origin(e), b = tin_.dest(e), c = tin_.apex(e), d = tin_.apex(f);
    if (a == kInfinite || b == kInfinite || c == kInfinite || d == kInfinite) return false;
    const Point2 pa = pt(a), pb = pt(b), pc = pt(c), pd = pt(d);
    if (orient2d(pc, pd, pa) * orient2d(pc, pd, pb) >= 0) return false;  // not swappable
    const double before = std::max(aspect_ratio(pa, pb, pc), aspect_ratio(pb, pa, pd));
    const double after = std::max(aspect_ratio(pc, pa, pd), aspect_ratio(pd, pb, pc));
    return after * (1 + 1e-12) < before;  // a strict decrease, so the loop ends
  }

  // Segment s crosses the constrained edge r-l: join them at a new vertex (or at a vertex that
  // already sits exactly there) and queue the four halves.
  void split_crossing(const Work& s, VertexId r, VertexId l) {
    if (!indexed_) {
      indexed_ = true;
      for (std::uint32_t p = 0; p < result_.pieces.size(); ++p) index_piece(p);
    }
    const std::uint32_t first_piece = index_.find(edge_key(r, l));
    std::uint32_t other = kNoId;
    // A constrained edge with no piece in this call (an earlier call's, not given again) is
    // crossed where it stands.
    std::optional<VertexPair> other_whole;
    for (std::uint32_t p = first_piece; p != kNoId && other == kNoId; p = next_piece_[p]) {
      other = result_.pieces[p].source;
      other_whole = whole_of(result_.pieces[p]);
    }
    const Point2 pa = pt(s.a), pb = pt(s.b), pr = pt(r), pl = pt(l);
    // The crossing point, from the signed areas (each a difference of nearby coordinates).
    const double area_a = (pl.x - pr.x) * (pa.y - pr.y) - (pl.y - pr.y) * (pa.x - pr.x);
    const double area_b = (pl.x - pr.x) * (pb.y - pr.y) - (pl.y - pr.y) * (pb.x - pr.x);
    // Nearly collinear segments cross nowhere well defined. When an end of one lies within a
    // hair of the other's line, the two join at that end: a ring laid over its own contour,
    // whose pieces end at rounded crossings, then shares their edges instead of crossing them
    // again and again. The rounded areas may even fail to put a and b on opposite sides of
    // r-l (no crossing point at all): the segment then bends through the nearer of r and l,
    // which lie exactly on opposite sides of it, as CGAL does.
    const double hair = hair_at({s.a, s.b, r, l});
    const bool placed = (area_a > 0 && area_b < 0) || (area_a < 0 && area_b > 0);
    const double t = placed ? area_a / (area_a - area_b) : 0;
    Point2 at{pa.x + t * (pb.x - pa.x), pa.y + t * (pb.y - pa.y)};
    VertexId nearer = kNoId;
    const double off_r = off_line(pa, pb, pr), off_l = off_line(pa, pb, pl);
    if (!placed || std::min(off_r, off_l) <= hair) {
      nearer = off_r <= off_l ? r : l;
    } else if (const double off_a = off_line(pr, pl, pa), off_b = off_line(pr, pl, pb);
               std::min(off_a, off_b) <= hair) {
      nearer = off_a <= off_b ? s.a : s.b;
    }
    if (nearer != kNoId) at = pt(nearer);
    WholeCrossing whole;
    const bool from_wholes =
        nearer == kNoId && other_whole && whole_crossing(s.whole, *other_whole, whole);
    if (from_wholes) at = whole.at;
    if (options_.on_crossing == OnCrossing::error) throw CrossingError(s.source, other, at);

    const double len2 = (pl.x - pr.x) * (pl.x - pr.x) + (pl.y - pr.y) * (pl.y - pr.y);
    const double u = ((at.x - pr.x) * (pl.x - pr.x) + (at.y - pr.y) * (pl.y - pr.y)) / len2;
    const double z_a = from_wholes ? whole.z_p : tin_.z(s.a) + t * (tin_.z(s.b) - tin_.z(s.a));
    const double z_b = from_wholes ? whole.z_q : tin_.z(r) + u * (tin_.z(l) - tin_.z(r));

    // The true crossing of two nearly parallel segments is ill-conditioned: the rounded point
    // sits an ulp off both lines, so the halves cross again next to it, and again, without end.
    // A crossing within a hair of one of the four ends joins that end instead, so no new piece
    // is shorter than that; a bound on the crossings met ends the rest.
    if (++crossings_met_ > crossing_bound_)
      throw GeometryError("constraints from features " + count_text(s.source) + " and " +
                          count_text(other) +
                          " cross more often than the input segments can: nearly parallel "
                          "lines whose crossings rounding cannot place");
    VertexId w = nearer != kNoId ? nearer : nearest_end({s.a, s.b, r, l}, at, hair);
    VertexId split_u = kNoId, split_v = kNoId;
    if (w != kNoId) {
      ++result_.split_at_vertices;  // the crossing joins an existing vertex
    } else {
      const mesh::Location loc = points_.locate(at, triangle_of(tin_.find_edge(r, l)));
      // Rounding can also put the crossing on another constraint's edge, which the insertion
      // then splits: its pieces must be split too, or they name an edge that is gone.
      if (loc.kind == mesh::Location::on_edge && tin_.is_constrained(loc.edge) &&
          edge_key(tin_.origin(loc.edge), tin_.dest(loc.edge)) != edge_key(r, l)) {
        split_u = tin_.origin(loc.edge);
        split_v = tin_.dest(loc.edge);
      }
      if (loc.kind == mesh::Location::on_vertex) {
        w = tin_.origin(loc.edge);  // rounding put the crossing on an existing vertex
      } else {
        w = tin_.add_vertex(at, 0.5 * (z_a + z_b));
        points_.insert(w, loc);
        result_.crossings.push_back({w, s.source, other, z_a, z_b});
        result_.max_z_disagreement = std::max(result_.max_z_disagreement, std::fabs(z_a - z_b));
      }
    }
    // The crossed constraint: unmark r-l if it survived (the new vertex may have split it) and
    // queue its halves for every source it carried.
    const EdgeId rl = tin_.find_edge(r, l);
    if (rl != kNoId) {  // freed, it may need flipping like any other edge
      tin_.set_constrained(rl, false);
      created_.assign(1, {r, l});
      restore();
    }
    requeue_through(first_piece, r, l, w);
    if (split_u != kNoId)
      requeue_through(index_.find(edge_key(split_u, split_v)), split_u, split_v, w);
    work_.push_back({w, s.b, s.source, s.whole});
    work_.push_back({s.a, w, s.source, s.whole});
  }

  struct WholeCrossing {
    Point2 at;
    double z_p, z_q;  // along each segment there
  };

  // Where the whole segments P and Q cross and the z along each there, from their ends taken in
  // an order of their coordinates (each segment from its smaller end, the segment with the
  // smaller ends first): the same doubles whichever of the two is being inserted. False when
  // rounding puts the ends of one on one side of the other.
  bool whole_crossing(VertexPair p, VertexPair q, WholeCrossing& x) const {
    const auto key = [&](VertexPair e) {
      return std::array{pt(e.u).x, pt(e.u).y, pt(e.v).x, pt(e.v).y};
    };
    const auto ordered = [&](VertexPair e) {
      const auto k = key(e);
      return std::tie(k[2], k[3]) < std::tie(k[0], k[1]) ? VertexPair{e.v, e.u} : e;
    };
    VertexPair first = ordered(p), second = ordered(q);
    const bool swapped = key(second) < key(first);
    if (swapped) std::swap(first, second);
    const Point2 fa = pt(first.u), fb = pt(first.v), sa = pt(second.u), sb = pt(second.v);
    const double area_a = (sb.x - sa.x) * (fa.y - sa.y) - (sb.y - sa.y) * (fa.x - sa.x);
    const double area_b = (sb.x - sa.x) * (fb.y - sa.y) - (sb.y - sa.y) * (fb.x - sa.x);
    if (!((area_a > 0 && area_b < 0) || (area_a < 0 && area_b > 0))) return false;
    const double t = area_a / (area_a - area_b);
    x.at = {fa.x + t * (fb.x - fa.x), fa.y + t * (fb.y - fa.y)};
    const double len2 = (sb.x - sa.x) * (sb.x - sa.x) + (sb.y - sa.y) * (sb.y - sa.y);
    const double u = ((x.at.x - sa.x) * (sb.x - sa.x) + (x.at.y - sa.y) * (sb.y - sa.y)) / len2;
    const double z_first = tin_.z(first.u) + t * (tin_.z(first.v) - tin_.z(first.u));
    const double z_second = tin_.z(second.u) + u * (tin_.z(second.v) - tin_.z(second.u));
    x.z_p = swapped ? z_second : z_first;
    x.z_q = swapped ? z_first : z_second;
    return true;
  }

  // A hair at the vertices ENDS: 2^-40 of their coordinates' magnitude, thousands of ulps yet a
  // few micrometres at UTM coordinates.
  double hair_at(std::initializer_list<VertexId> ends) const {
    double scale = 0;
    for (const VertexId v : ends) scale = std::max({scale, std::fabs(pt(v).x), std::fabs(pt(v).y)});
    return std::ldexp(scale, -40);
  }

  // How far X lies from the line through P and Q.
  static double off_line(Point2 p, Point2 q, Point2 x) {
    return std::fabs((q.x - p.x) * (x.y - p.y) - (q.y - p.y) * (x.x - p.x)) /
           std::hypot(q.x - p.x, q.y - p.y);
  }

  // The vertex among ENDS within HAIR of AT, or kNoId.
  VertexId nearest_end(std::initializer_list<VertexId> ends, Point2 at, double hair) const {
    VertexId best = kNoId;
    double best_d2 = hair * hair;
    for (const VertexId v : ends) {
      const double dx = pt(v).x - at.x, dy = pt(v).y - at.y;
      if (const double d2 = dx * dx + dy * dy; d2 <= best_d2) {
        best = v;
        best_d2 = d2;
      }
    }
    return best;
  }

  // Retires the pieces on edge u-v (the chain from FIRST_PIECE) and queues, for each source they
  // carried, the halves u-w and w-v.
  void requeue_through(std::uint32_t first_piece, VertexId u, VertexId v, VertexId w) {
    for (std::uint32_t p = first_piece; p != kNoId; p = next_piece_[p]) {
      Piece& piece = result_.pieces[p];
      if (piece.source == kNoId) continue;
      if (w != u) work_.push_back({u, w, piece.source, whole_of(piece)});
      if (w != v) work_.push_back({w, v, piece.source, whole_of(piece)});
      piece.source = kNoId;  // retired; removed at the end
    }
  }

  Triangulation& tin_;
  ConstraintOptions options_;
  mesh::PointInserter points_;
  ConstraintResult result_;
  bool indexed_ = false;
  std::uint64_t crossings_met_ = 0;
  // Twice the most crossings there can be (insert_constraints()): room for rounding.
  std::uint64_t crossing_bound_;
  IdMap index_;                            // edge -> its latest piece (only crossings look)
  std::vector<std::uint32_t> next_piece_;  // piece -> the previous piece on the same edge
  std::vector<Work> work_;
  std::vector<VertexPair> crossed_;
  std::vector<VertexPair> waiting_;  // crossed edges for the next round of swap_in()
  std::vector<VertexPair> created_;
};

}  // namespace

ConstraintResult insert_constraints(Triangulation& tin, const std::vector<Segment>& segments,
                                    const ConstraintOptions& options, const ProgressFn* progress) {
  // The new segments cross each other and the constraints already in (a later stage's lines
  // cross the contours): m new and k old make at most m (m - 1) / 2 + m k crossings.
  std::uint64_t old_constraints = 0;
  tin.for_each_constrained_edge([&](EdgeId) { ++old_constraints; });
  ConstraintInserter inserter(tin, options, segments.size(), old_constraints);
  inserter.result().pieces.reserve(segments.size());
  Progress report(progress, "constraints", segments.size());
  std::uint64_t done = 0;
  for (const Segment& s : segments) {
    if (s.a >= tin.vertex_count() || s.b >= tin.vertex_count())
      throw GeometryError("segment names a vertex that does not exist");
    if (s.a == s.b) {
      ++inserter.result().segments_skipped;
    } else {
      inserter.insert(s, report);
      ++inserter.result().segments;
    }
    report.tick(++done);
  }
  report.finish();
  ConstraintResult result = inserter.take_result();
  // Every crossing, joined at a new vertex or at one a hair away, retires the pieces it split.
  if (std::none_of(result.pieces.begin(), result.pieces.end(),
                   [](const Piece& p) { return p.source == kNoId; }))
    return result;  // no crossing: no piece retired or repeated, no triangle added

  // Drop retired pieces, and repeats of one edge for one source: two crossing points that round
  // to within an ulp of each other can make a chain step back over an edge it already holds.
  std::erase_if(result.pieces, [](const Piece& p) { return p.source == kNoId; });
  for (Piece& p : result.pieces)
    if (p.a > p.b) std::swap(p.a, p.b);
  std::sort(result.pieces.begin(), result.pieces.end(), [](const Piece& x, const Piece& y) {
    return std::tie(x.source, x.a, x.b) < std::tie(y.source, y.a, y.b);
  });
  result.pieces.erase(std::unique(result.pieces.begin(), result.pieces.end(),
                                  [](const Piece& x, const Piece& y) {
                                    return x.source == y.source && x.a == y.a && x.b == y.b;
                                  }),
                      result.pieces.end());
  if (!result.crossings.empty()) tin.recount();  // each crossing vertex added triangles
  return result;
}

std::string check_segments(const Triangulation& tin, const std::vector<Segment>& segments,
                           const std::vector<Piece>& pieces) {
  // Any half-edge leaving each vertex, to find an edge by turning around its origin.
  const std::vector<VertexId>& corners = tin.corners();
  std::vector<EdgeId> out(tin.vertex_count(), kNoId);
  for (std::size_t e = 0; e < corners.size(); ++e)
    if (corners[e] < kInfinite) out[corners[e]] = static_cast<EdgeId>(e);
  auto find_edge = [&](VertexId u, VertexId v) {
    if (out[u] == kNoId) return kNoId;  // a vertex in no triangle
    EdgeId e = out[u];
    do {
      if (tin.dest(e) == v) return e;
      e = tin.twin(prev_edge(e));
    } while (e != out[u]);
    return kNoId;
  };
  for (const Piece& p : pieces) {
    if (p.a >= tin.vertex_count() || p.b >= tin.vertex_count())
      return "a piece names a vertex that does not exist";
    const EdgeId e = find_edge(p.a, p.b);
    if (e == kNoId) return "piece " + count_text(p.a) + "-" + count_text(p.b) + " is not an edge";
    if (!tin.is_constrained(e))
      return "edge " + count_text(p.a) + "-" + count_text(p.b) + " is not constrained";
  }

  // Each piece both ways, by source and then first vertex: a vertex's neighbours along one
  // source's pieces are one range.
  struct Step {
    std::uint32_t source;
    VertexId from, to;
    auto key() const { return std::pair{source, from}; }
  };
  std::vector<Step> steps;
  steps.reserve(2 * pieces.size());
  for (const Piece& p : pieces) {
    steps.push_back({p.source, p.a, p.b});
    steps.push_back({p.source, p.b, p.a});
  }
  std::sort(steps.begin(), steps.end(),
            [](const Step& x, const Step& y) { return x.key() < y.key(); });

  // a reaches b through its source's pieces (a chain; a crossing can add a harmless spur).
  // Breadth first, so that b, a few pieces away, is found before the rest of a long line.
  std::vector<std::uint32_t> seen(tin.vertex_count(), 0);  // the segment that reached it, + 1
  std::vector<VertexId> queue;
  std::uint32_t stamp = 0;
  for (const Segment& s : segments) {
    if (s.a == s.b) continue;
    if (s.a >= tin.vertex_count() || s.b >= tin.vertex_count())
      return "a segment names a vertex that does not exist";
    ++stamp;
    queue.assign(1, s.a);
    seen[s.a] = stamp;
    bool joined = false;
    for (std::size_t next = 0; next < queue.size() && !joined; ++next) {
      const auto [first, last] =
          std::equal_range(steps.begin(), steps.end(), Step{s.source, queue[next], 0},
                           [](const Step& x, const Step& y) { return x.key() < y.key(); });
      for (auto it = first; it != last && !joined; ++it) {
        if (seen[it->to] == stamp) continue;
        seen[it->to] = stamp;
        joined = it->to == s.b;
        queue.push_back(it->to);
      }
    }
    if (!joined)
      return "segment " + count_text(s.a) + "-" + count_text(s.b) + " of source " +
             count_text(s.source) + " is not joined end to end by constrained edges";
  }
  return {};
}

}  // namespace tincdt::constraints
