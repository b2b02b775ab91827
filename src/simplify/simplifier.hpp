// One greedy run: the TIN of the kept points, the input points kept in ranges by the triangle
// holding them, and the queue of triangles beyond the tolerance.
//
// The state, per triangle slot t of the TIN: its points are ids_[begin_[t], begin_[t] +
// count_[t]) (the arena), their worst point worst_[t] with error worst_error_[t], and the sum of
// their squared errors sum_sq_[t]. Every point of the set that is not a vertex is in exactly one
// triangle's range, and a triangle is in the queue exactly when its worst error is above the
// tolerance. Inserting a point replaces the triangles around it (Lawson flips only replace
// triangles by triangles that have the new vertex as a corner), so the points to measure again
// are exactly those of the triangles of the new vertex's star.
//
// The jobs, by file: simplifier.cpp starts a run (start, assign_points, finish), greedy.cpp is
// the loop (run, insert, redistribute), adopt.cpp starts a run from the regions' runs.
#pragma once

#include <algorithm>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "constraints/constraints.hpp"
#include "core/error.hpp"
#include "core/id_map.hpp"
#include "core/progress.hpp"
#include "core/thread_pool.hpp"
#include "core/types.hpp"
#include "core/xorshift.hpp"
#include "mesh/point_insertion.hpp"
#include "mesh/triangulation.hpp"
#include "predicates/interior_filter.hpp"
#include "predicates/predicates.hpp"
#include "simplify/fan.hpp"
#include "simplify/measure.hpp"
#include "simplify/simplify.hpp"
#include "simplify/worst_queue.hpp"

namespace tincdt::simplify::detail {

using mesh::Triangulation;

// ids_[j] before the ranges are made: the j-th point is a vertex (kept). Never a triangle slot.
constexpr std::uint32_t kKept = kNoId - 1;
// The most points a run takes: its arena (2 per point) has 32-bit places.
constexpr std::size_t kMaxPoints = (std::size_t{UINT32_MAX} - 1024) / 2;

// The size of the arena of a run on `points` points (see Simplifier::ids_).
constexpr std::size_t arena_slots(std::size_t points) {
  return 2 * points + 1024;
}

// The points a run simplifies: all of xy, z, or those named by `ids` (ascending).
struct PointSet {
  std::span<const Point2> xy;
  std::span<const double> z;
  std::span<const std::uint32_t> ids;  // empty: all

  std::size_t size() const { return ids.empty() ? xy.size() : ids.size(); }
  // The point of the j-th member.
  std::uint32_t operator[](std::size_t j) const {
    return ids.empty() ? static_cast<std::uint32_t>(j) : ids[j];
  }
  // The place of point i among the members, or size() when it is not one.
  std::size_t find(std::uint32_t i) const {
    if (ids.empty()) return i < xy.size() ? i : xy.size();
    const auto it = std::lower_bound(ids.begin(), ids.end(), i);
    return it != ids.end() && *it == i ? static_cast<std::size_t>(it - ids.begin()) : ids.size();
  }
};

class Simplifier {
 public:
  // `arena`: where the run keeps its points' ids (see ids_), at least arena_slots() of them;
  // empty: an arena of its own.
  Simplifier(const PointSet& set, const SimplifyOptions& options,
             std::span<std::uint32_t> arena = {});

  // The constrained Delaunay triangulation of the kept points, the segments' ends and the
  // seeds (points inserted up front, counted as inserted; none of them kept). All are points of
  // the set.
  void start(std::span<const std::uint32_t> kept, std::span<const constraints::Segment> segments,
             std::span<const std::uint32_t> seeds = {});

  // A part of the points that an earlier run (or none) simplified on its own: see adopt().
  struct Part {
    const Simplifier* run;                  // after run(); null: none
    std::span<const std::uint32_t> points;  // all of the part's points
  };

  // What assign_points() does, taking the triangles of the parts' runs that this TIN has too
  // (the same three points) as they are: such a triangle lies in the part's hull, which holds
  // no other part's point, so it holds exactly the points it held there, measured against the
  // same plane. Only the other points are located and measured. The parts hold every point of
  // the set (all of xy) once.
  void adopt(std::span<const Part> parts);

  // Every other point into the range of the triangle holding it, its error measured: on all
  // threads, each walking from the triangle of its previous point. ids_[j] holds the triangle
  // of the j-th point (kKept for a vertex) until a counting sort makes the ranges, in
  // [m, m + candidates).
  void assign_points();

  // The greedy loop: the worst point in, the points of the triangles it replaced measured
  // again, until all are within the tolerance or the vertex budget is spent.
  void run(const ProgressFn* progress);

  // The points the greedy loop inserted, in the order it did.
  std::vector<std::uint32_t> greedy_order() const {
    return {point_of_vertex_.begin() + static_cast<std::ptrdiff_t>(first_greedy_vertex_),
            point_of_vertex_.end()};
  }

  SimplifyResult finish();

 private:
  struct Range {
    std::size_t begin, count;
  };
  // What adopt() takes from the parts (see adopt.cpp).
  struct Adoption;
  // Work is split in chunks of at least this many points (fewer are not worth a handoff
  // between threads), at most kMaxChunks of them, whatever the thread count: what a chunk
  // computes never depends on the thread that runs it, so neither does the result.
  static constexpr std::size_t kChunkPoints = 1 << 13;
  static constexpr std::size_t kMaxChunks = 16;
  static constexpr std::size_t kPrefetch = 16;  // points ahead

  static std::size_t chunks_for(std::size_t points) {
    return std::clamp<std::size_t>(points / kChunkPoints, 1, kMaxChunks);
  }

  Point2 pt(VertexId v) const { return tin_.point(v); }

  // Locates points one after another, each from the triangle of the one before: most are
  // strictly inside it, which InteriorFilter tells without locate()'s walk. (`seed`: of the
  // walk's random edge order; the triangle found does not depend on it.)
  class Walk {
   public:
    Walk(const Simplifier& s, std::uint64_t seed)
        : s_(s), random_(0x9e3779b97f4a7c15ULL ^ seed), t_(s.first_real()), inside_(filter(t_)) {}

    TriangleId to(Point2 q) {
      if (inside_.surely_inside(q)) return t_;
      const TriangleId u = s_.locate(q, t_, random_);
      if (u != t_) inside_ = filter(u);
      return t_ = u;
    }

   private:
    predicates::InteriorFilter filter(TriangleId t) const {
      const EdgeId e = 3 * t;
      return {s_.pt(s_.tin_.origin(e)), s_.pt(s_.tin_.origin(e + 1)), s_.pt(s_.tin_.origin(e + 2))};
    }

    const Simplifier& s_;
    std::uint64_t random_;
    TriangleId t_;
    predicates::InteriorFilter inside_;
  };

  TriangleId first_real() const {
    TriangleId t = 0;
    while (tin_.is_ghost(t)) ++t;
    return t;
  }

  // What slot t holds, as a tally, and a tally (its count aside) as what slot t holds.
  Tally tally_of(std::size_t t) const {
    return {worst_error_[t], sum_sq_[t], worst_[t], count_[t]};
  }
  void set_tally(std::size_t t, const Tally& tally) {
    assert(tally.count == count_[t]);
    worst_[t] = tally.worst;
    worst_error_[t] = tally.worst_error;
    sum_sq_[t] = tally.sum_sq;
  }

  // The points of triangle slot t measured against its plane.
  Tally measure(std::size_t t) const {
    const Plane plane = plane_of(static_cast<TriangleId>(t));
    Tally tally;
    for (std::size_t k = begin_[t]; k < begin_[t] + count_[t]; ++k) {
      const std::uint32_t q = ids_[k];
      tally.add(plane.error(xy_[q], z_[q]), q, xy_.data());
    }
    return tally;
  }

  // The plane of triangle slot t.
  Plane plane_of(TriangleId t) const {
    assert(!tin_.is_ghost(t));
    const EdgeId e = 3 * t;
    const VertexId a = tin_.origin(e), b = tin_.origin(e + 1), d = tin_.origin(e + 2);
    const Gradient g(pt(a), tin_.z(a), pt(b), tin_.z(b), pt(d), tin_.z(d));
    return {pt(a), tin_.z(a), g.gx, g.gy};
  }

  // Calls f(t) for every triangle slot t holding points, on all threads, in chunks of slots
  // holding similar point counts.
  template <class F>
  void for_each_range(F&& f) {
    const std::size_t slots = count_.size();
    std::size_t points = 0;
    for (std::size_t t = 0; t < slots; ++t) points += count_[t];
    const std::size_t chunks = chunks_for(points);
    std::vector<std::size_t> first_slot{0};
    for (std::size_t t = 0, seen = 0; t < slots; ++t) {
      seen += count_[t];
      if (seen * chunks >= first_slot.size() * points && first_slot.size() < chunks)
        first_slot.push_back(t + 1);
    }
    first_slot.push_back(slots);
    auto chunk = [&](std::size_t c, std::size_t) {
      for (std::size_t t = first_slot[c]; t < first_slot[c + 1]; ++t)
        if (count_[t] > 0) f(t);
    };
    pool_.run(chunk, first_slot.size() - 1);
  }

  void grow() {
    const std::size_t slots = tin_.triangle_slots();
    if (begin_.size() >= slots) return;
    begin_.resize(slots, 0);
    count_.resize(slots, 0);
    worst_.resize(slots, kNoId);
    worst_error_.resize(slots, -1.0);
    sum_sq_.resize(slots, 0.0);
    queue_.grow(slots);
  }

  // Adds a tally to triangle u.
  void absorb(const Tally& t, TriangleId u) {
    if (t.count == 0) return;
    count_[u] += t.count;
    sum_sq_[u] += t.sum_sq;
    if (worse(t.worst_error, t.worst, worst_error_[u], worst_[u], xy_.data())) {
      worst_error_[u] = t.worst_error;
      worst_[u] = t.worst;
    }
  }

  // The real triangle holding p (inside or on its boundary), walking from real triangle t with
  // a random first edge at each step, which terminates on any triangulation. When p is on an
  // edge, of its two triangles the one with the smaller slot: the walk's route must not decide.
  TriangleId locate(Point2 p, TriangleId t, std::uint64_t& random) const;

  // start(): the places in the set of the kept points and segment ends (ascending, in
  // vertex_places_), merged with those of the seeds that are none of them; returns how many
  // seeds were new.
  std::size_t place_vertices(std::span<const std::uint32_t> kept,
                             std::span<const constraints::Segment> segments,
                             std::span<const std::uint32_t> seeds);
  // start(): the segments as constrained edges between the vertices made of their ends.
  void insert_segments(std::span<const constraints::Segment> segments,
                       std::span<const VertexId> vertex_of_place);
  // The j-th member of the set, which must be one.
  std::uint32_t member(std::uint32_t i) const;

  // Every triangle beyond the tolerance into the queue; the others' points counted as settled.
  void queue_ranges();

  // adopt(), in turn: which triangles are taken as they are, and which points are loose;
  // where the loose points are; the ranges made; and their log.
  Adoption match_parts(std::span<const Part> parts);
  void match_part(const Part& part, std::size_t k, const IdMap& vertex_of, Adoption& a);
  TriangleId shared_triangle(const Simplifier& r, std::span<const VertexId> here,
                             TriangleId t) const;
  std::size_t past_parts_arenas(std::span<const Part> parts) const;
  std::vector<std::uint8_t> place_ranges(std::span<const Part> parts, const Adoption& a);
  void log_adopted_ranges(std::span<const Part> parts, const Adoption& a,
                          std::span<const std::uint8_t> measured);

  // insert(), in turn: the new triangles around v as a fan (returns whether v is inside the
  // hull); the replaced triangles' ranges released (returns their point count); the queue
  // updated for the star's slots.
  void insert(mesh::PointInserter& inserter, std::uint32_t p, TriangleId t);
  bool build_fan(VertexId v, Point2 at, double z);
  std::size_t release_star();
  void requeue_star();

  template <class C>
  void redistribute(const Fan& fan, std::uint32_t p, std::size_t total, std::vector<C>& cone_of,
                    C skip);
  template <class C>
  int scan(const Fan& shared_fan, const std::uint32_t* ids, std::size_t count, std::uint32_t p,
           C* cone, C skip, Tally* tally, int hint) const;

  // Moves the live ranges to the front of the arena, in the order they lie.
  // (The log of ranges is in arena order: a range is live if its slot still has it.)
  void compact();

  PointSet set_;
  std::span<const Point2> xy_;
  std::span<const double> z_;
  SimplifyOptions options_;
  Triangulation tin_;
  std::vector<std::uint32_t> point_of_vertex_;
  SimplifyReport report_;
  ThreadPool pool_;

  // The points of each triangle are one range of ids_, an arena: new ranges are appended, old
  // ones abandoned, and compact() closes the gaps when the end is reached.
  std::uint32_t* ids_;
  std::size_t arena_size_ = 0, arena_end_ = 0;
  std::unique_ptr<std::uint32_t[]> own_ids_;  // the arena, when the run has its own
  // The ranges with points as they were appended: (begin, slot), in arena order.
  std::vector<std::pair<std::uint32_t, TriangleId>> ranges_;
  // Per triangle slot: its range and what it holds.
  std::vector<std::size_t> begin_;
  std::vector<std::uint32_t> count_;
  std::vector<std::uint32_t> worst_;  // the point with the largest error, or kNoId
  std::vector<double> worst_error_;
  std::vector<double> sum_sq_;  // of the errors of its points, as last measured
  WorstQueue queue_;            // the triangles with a point beyond the tolerance
  std::size_t first_greedy_vertex_ = 0;
  std::vector<std::uint32_t> vertex_places_;    // of the points start() made vertices, ascending
  std::uint64_t candidates_ = 0, settled_ = 0;  // points, and those in triangles within max_error

  // Scratch of insert().
  std::vector<EdgeId> star_;
  std::vector<Point2> ring_, spokes_;
  std::vector<double> bounds_;
  std::vector<Cone> cones_;
  std::vector<Range> old_;
  std::vector<std::uint32_t> gathered_;
  std::vector<std::uint8_t> cone8_;
  std::vector<std::uint32_t> cone32_;
  std::vector<Tally> tallies_;
};

inline TriangleId Simplifier::locate(Point2 p, TriangleId t, std::uint64_t& random) const {
  using mesh::triangle_of;
  assert(!tin_.is_ghost(t));
  EdgeId from = kNoId;
  for (;;) {
    const auto first = static_cast<EdgeId>(random_edge(random));
    EdgeId crossed = kNoId, zero = kNoId;
    int zeros = 0;
    for (EdgeId i = 0; i < 3; ++i) {
      const EdgeId e = 3 * t + (first + i) % 3;
      const int o = e == from ? 1 : predicates::orient2d(pt(tin_.origin(e)), pt(tin_.dest(e)), p);
      if (o < 0) {
        crossed = e;
        break;
      }
      if (o == 0) {
        zero = e;
        ++zeros;
      }
    }
    if (crossed == kNoId) {
      if (zeros == 0) return t;
      if (zeros > 1)
        throw GeometryError(
            "simplify: a point shares x, y with a kept point or a crossing of "
            "two segments (merge duplicates first)");
      const TriangleId u = triangle_of(tin_.twin(zero));
      return u < t && !tin_.is_ghost(u) ? u : t;
    }
    from = tin_.twin(crossed);
    t = triangle_of(from);
    if (tin_.apex(from) == mesh::kInfinite)
      throw InternalError("simplify: a point lies outside the hull of the kept points");
  }
}

}  // namespace tincdt::simplify::detail
