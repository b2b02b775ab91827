#include "simplify/simplify.hpp"
#include "core/xorshift.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <utility>

#include "core/error.hpp"
#include "core/id_map.hpp"
#include "core/memory.hpp"
#include "mesh/point_insertion.hpp"
#include "predicates/interior_filter.hpp"
#include "predicates/predicates.hpp"

namespace tincdt::simplify {
namespace {

using namespace mesh;  // the half-edge vocabulary: next_edge, triangle_of, kInfinite, ...
using predicates::InteriorFilter;
using predicates::orient2d;

// ids_[j] before the ranges are made: the j-th point is a vertex (kept). Never a triangle slot.
constexpr std::uint32_t kKept = kNoId - 1;
// The most points a run takes: its arena (2 per point) has 32-bit places.
constexpr std::size_t kMaxPoints = (std::size_t{UINT32_MAX} - 1024) / 2;

// The size of the arena of a run on `points` points (see Simplifier::ids_).
constexpr std::size_t arena_slots(std::size_t points) {
  return 2 * points + 1024;
}

unsigned thread_count(unsigned requested) {
  return requested ? requested : std::max(1u, std::thread::hardware_concurrency());
}

bool xy_less(Point2 a, Point2 b) {
  return a.x < b.x || (a.x == b.x && a.y < b.y);
}

// The gradient of the plane through three points, relative to the first, so that large
// coordinates (UTM) do not cancel: z = za + gx (x - a.x) + gy (y - a.y). Doubles are enough for
// an error value; which triangle a point is in is decided exactly elsewhere.
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
bool worse(double e, std::uint32_t p, double we, std::uint32_t w, const Point2* xy) {
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

// A triangle's worst point, as the queue holds it.
struct Entry {
  double error;
  std::uint32_t point;
  TriangleId tri;
};

// The triangles beyond the tolerance, largest error first (equal errors by the points' x, then
// y), as a 4-ary heap that knows where each triangle is: an insertion updates or removes the
// entries of the slots it reused, so the heap holds one entry per unsettled triangle and never
// a stale one. (A lazy heap of duplicates grew to twice the triangle count, and its sift-downs
// were cache misses.) Four children are one or two cache lines, and half the levels of a
// binary heap.
class WorstQueue {
 public:
  explicit WorstQueue(const Point2* xy) : xy_(xy) {}

  bool empty() const { return heap_.empty(); }
  const Entry& top() const { return heap_.front(); }
  void grow(std::size_t slots) {
    if (pos_.size() < slots) pos_.resize(slots, kNoId);
  }

  // Adds an entry (its slot absent) without ordering; build() orders them all.
  void append(const Entry& e) {
    pos_[e.tri] = static_cast<std::uint32_t>(heap_.size());
    heap_.push_back(e);
  }
  void build() {
    for (std::size_t i = heap_.size() / 4 + 1; i-- > 0;)
      if (i < heap_.size()) down(static_cast<std::uint32_t>(i));
  }

  // The entry of e.tri becomes e (added if absent).
  void set(const Entry& e) {
    std::uint32_t i = pos_[e.tri];
    if (i == kNoId) {
      i = static_cast<std::uint32_t>(heap_.size());
      heap_.push_back(e);
      up(i);
      return;
    }
    const bool rises = before(e, heap_[i]);
    heap_[i] = e;
    if (rises)
      up(i);
    else
      down(i);
  }

  void erase(TriangleId t) {
    const std::uint32_t i = pos_[t];
    if (i == kNoId) return;
    pos_[t] = kNoId;
    const Entry last = heap_.back();
    heap_.pop_back();
    if (i == heap_.size()) return;
    heap_[i] = last;
    if (i > 0 && before(last, heap_[(i - 1) / 4]))
      up(i);
    else
      down(i);
  }

 private:
  bool before(const Entry& a, const Entry& b) const {
    if (a.error != b.error) return a.error > b.error;
    return xy_less(xy_[a.point], xy_[b.point]);
  }
  void up(std::uint32_t i) {
    const Entry e = heap_[i];
    while (i > 0) {
      const std::uint32_t parent = (i - 1) / 4;
      if (!before(e, heap_[parent])) break;
      heap_[i] = heap_[parent];
      pos_[heap_[i].tri] = i;
      i = parent;
    }
    heap_[i] = e;
    pos_[e.tri] = i;
  }
  void down(std::uint32_t i) {
    const Entry e = heap_[i];
    const auto n = static_cast<std::uint32_t>(heap_.size());
    for (;;) {
      const std::uint32_t first = 4 * i + 1;
      if (first >= n) break;
      std::uint32_t best = first;
      for (std::uint32_t c = first + 1; c < std::min(first + 4, n); ++c)
        if (before(heap_[c], heap_[best])) best = c;
      if (!before(heap_[best], e)) break;
      heap_[i] = heap_[best];
      pos_[heap_[i].tri] = i;
      i = best;
    }
    heap_[i] = e;
    pos_[e.tri] = i;
  }

  const Point2* xy_;
  std::vector<Entry> heap_;
  std::vector<std::uint32_t> pos_;  // per triangle slot: its place in heap_, or kNoId
};

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
    return orient2d(apex, ring[i], q);
  }

  // The cone holding q (known to lie in the fan), scanning from `hint`. A point on the spoke
  // between two cones goes to the one with the smaller slot, whatever the scan order.
  // Inlined: called, it took q and d through the stack as halves and read them back whole,
  // a failed store forwarding per point (14% of the stage on a 4096^2 grid).
  [[gnu::always_inline]] int classify(Point2 q, Point2 d, int hint) const {
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

inline void cpu_relax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

// Threads kept for the whole run, so that splitting a few thousand points between cores costs
// microseconds, not a thread start. run(f, chunks) calls f(c, chunks) once for every chunk c;
// the calling thread and the workers claim chunks in turn, so a worker that is late (asleep,
// or descheduled on a busy machine) only means the caller does more of them. What a chunk
// computes must not depend on which thread runs it. Idle workers spin briefly for the next
// job, then sleep on a futex.
class Pool {
 public:
  explicit Pool(std::size_t threads) {
    for (std::size_t i = 1; i < threads; ++i) workers_.emplace_back([this] { work(); });
  }
  ~Pool() {
    stop_ = true;
    generation_.fetch_add(1, std::memory_order_release);
    generation_.notify_all();
    for (std::thread& t : workers_) t.join();
  }
  Pool(const Pool&) = delete;
  Pool& operator=(const Pool&) = delete;

  std::size_t threads() const { return workers_.size() + 1; }

  template <class F>
  void run(F& f, std::size_t chunks) {
    if (chunks <= 1 || workers_.empty()) {
      for (std::size_t c = 0; c < chunks; ++c) f(c, chunks);
      return;
    }
    job_ = [](void* fn, std::size_t c, std::size_t n) { (*static_cast<F*>(fn))(c, n); };
    fn_ = &f;
    chunks_ = chunks;
    next_.store(0, std::memory_order_relaxed);
    done_.store(0, std::memory_order_relaxed);
    generation_.fetch_add(1, std::memory_order_release);
    generation_.notify_all();
    claim_all();
    for (int spin = 0;; ++spin) {
      const std::size_t done = done_.load(std::memory_order_acquire);
      if (done == chunks) break;
      if (spin > kSpins)
        done_.wait(done, std::memory_order_acquire);
      else
        cpu_relax();
    }
    std::exception_ptr error = std::move(error_);
    error_ = nullptr;
    if (error) std::rethrow_exception(error);
  }

 private:
  static constexpr int kSpins = 4000;  // with a pause each: some tens of microseconds

  // Runs chunks until none is left to claim.
  void claim_all() {
    for (;;) {
      const std::size_t c = next_.fetch_add(1, std::memory_order_relaxed);
      if (c >= chunks_) return;
      try {
        job_(fn_, c, chunks_);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(error_mutex_);
        if (!error_) error_ = std::current_exception();
      }
      if (done_.fetch_add(1, std::memory_order_acq_rel) + 1 == chunks_) done_.notify_all();
    }
  }

  void work() {
    std::uint64_t seen = 0;
    for (;;) {
      for (int spin = 0;; ++spin) {
        const std::uint64_t g = generation_.load(std::memory_order_acquire);
        if (g != seen) {
          seen = g;
          break;
        }
        if (spin > kSpins)
          generation_.wait(g, std::memory_order_acquire);
        else
          cpu_relax();
      }
      if (stop_) return;
      claim_all();
    }
  }

  std::vector<std::thread> workers_;
  std::atomic<std::uint64_t> generation_{0};
  std::atomic<std::size_t> next_{0}, done_{0};
  std::atomic<bool> stop_{false};
  void (*job_)(void*, std::size_t, std::size_t) = nullptr;
  void* fn_ = nullptr;
  std::size_t chunks_ = 0;
  std::mutex error_mutex_;
  std::exception_ptr error_;
};

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
             std::span<std::uint32_t> arena = {})
      : set_(set),
        xy_(set.xy),
        z_(set.z),
        options_(options),
        pool_(thread_count(options.threads)),
        queue_(set.xy.data()) {
    if (xy_.size() != z_.size()) throw Error("simplify: x, y and z counts differ");
    if (xy_.size() >= kKept || set.size() > kMaxPoints)
      throw GeometryError("simplify: too many points for 32-bit ids");
    if (!(options.max_error >= 0))
      throw Error("simplify: the maximum error must be a number >= 0, not " +
                  std::to_string(options.max_error));
    // Left unwritten: every entry is written before it is read, and fresh pages cost more than
    // the writes. (Huge pages were no faster here, and asking for them cost 0.2 s a 16M-point
    // run when memory was fragmented.)
    if (arena.empty()) {
      own_ids_ = std::make_unique_for_overwrite<std::uint32_t[]>(arena_slots(set.size()));
      arena = {own_ids_.get(), arena_slots(set.size())};
    }
    if (arena.size() < arena_slots(set.size()))
      throw InternalError("simplify: an arena too small for its run");
    ids_ = arena.data();
    arena_size_ = arena.size();
  }

  // The constrained Delaunay triangulation of the kept points, the segments' ends and the
  // seeds (points inserted up front, counted as inserted; none of them kept). All are points of
  // the set.
  void start(std::span<const std::uint32_t> kept, std::span<const constraints::Segment> segments,
             std::span<const std::uint32_t> seeds = {}) {
    const std::size_t m = set_.size();
    const auto member = [&](std::uint32_t i) {
      const std::size_t j = set_.find(i);
      if (j == m) throw Error("simplify: a kept point or segment end is not one of the points");
      return static_cast<std::uint32_t>(j);
    };
    // The kept points and segment ends, then the seeds that are none of them (a region may
    // insert the end of a segment it was not given).
    const auto sort_unique = [](std::vector<std::uint32_t>& v) {
      if (!std::is_sorted(v.begin(), v.end())) std::sort(v.begin(), v.end());
      v.erase(std::unique(v.begin(), v.end()), v.end());
    };
    std::vector<std::uint32_t>& places = vertex_places_;
    places.clear();
    for (std::uint32_t i : kept) places.push_back(member(i));
    for (const constraints::Segment& s : segments)
      places.insert(places.end(), {member(s.a), member(s.b)});
    sort_unique(places);
    std::vector<std::uint32_t> seed_places;
    for (std::uint32_t i : seeds) {
      const std::uint32_t j = member(i);
      if (!std::binary_search(places.begin(), places.end(), j)) seed_places.push_back(j);
    }
    sort_unique(seed_places);
    const std::size_t kept_places = places.size();
    places.insert(places.end(), seed_places.begin(), seed_places.end());
    std::inplace_merge(places.begin(), places.begin() + static_cast<std::ptrdiff_t>(kept_places),
                       places.end());
    std::vector<Point3> points;
    points.reserve(places.size());
    for (std::uint32_t j : places) {
      const std::uint32_t i = set_[j];
      points.push_back({xy_[i].x, xy_[i].y, z_[i]});
    }
    report_.points = m;
    report_.kept_vertices = kept_places;
    report_.inserted = seed_places.size();
    candidates_ = m - places.size();
    delaunay::DelaunayOptions d;
    d.keep_point_map = true;
    d.threads = options_.threads;
    delaunay::DelaunayResult r = delaunay::triangulate(std::move(points), d);
    if (r.duplicates_merged > 0)
      throw GeometryError("simplify: two kept points share x, y (merge duplicates first)");
    tin_ = std::move(r.tin);
    point_of_vertex_.assign(tin_.vertex_count(), kNoId);
    for (std::size_t k = 0; k < places.size(); ++k)
      point_of_vertex_[r.vertex_of_point[k]] = set_[places[k]];
    if (!segments.empty()) {
      const auto vertex = [&](std::uint32_t i) {
        const auto k = std::lower_bound(places.begin(), places.end(), member(i)) - places.begin();
        return r.vertex_of_point[static_cast<std::size_t>(k)];
      };
      std::vector<constraints::Segment> s;
      s.reserve(segments.size());
      for (const constraints::Segment& g : segments)
        s.push_back({vertex(g.a), vertex(g.b), g.source});
      // In an order of their geometry, so that the caller's order does not decide.
      const auto key = [&](const constraints::Segment& g) {
        const Point2 a = tin_.point(g.a), b = tin_.point(g.b);
        return xy_less(a, b) ? std::pair{a, b} : std::pair{b, a};
      };
      std::sort(s.begin(), s.end(),
                [&](const constraints::Segment& a, const constraints::Segment& b) {
                  const auto ka = key(a), kb = key(b);
                  if (ka.first != kb.first) return xy_less(ka.first, kb.first);
                  return xy_less(ka.second, kb.second);
                });
      constraints::insert_constraints(tin_, s);
      point_of_vertex_.resize(tin_.vertex_count(), kNoId);  // crossings
    }
    if (!tin_.has_vertex_index()) tin_.build_vertex_index();
    first_greedy_vertex_ = tin_.vertex_count();
  }

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
  void adopt(std::span<const Part> parts) {
    if (!set_.ids.empty()) throw InternalError("simplify: adopt() on a subset");
    grow();
    const std::size_t slots = tin_.triangle_slots();
    // The triangle of three points, if this TIN has it, is found around the first one's vertex.
    IdMap vertex_of;  // of a point (the vertices are few next to the points)
    for (VertexId v = 0; v < point_of_vertex_.size(); ++v)
      if (point_of_vertex_[v] != kNoId) vertex_of.insert(point_of_vertex_[v], v);  // not a crossing
    // (`here`: this TIN's vertex of each of r's vertices, or kNoId.)
    const auto find = [&](const Simplifier& r, const std::vector<VertexId>& here, TriangleId t) {
      VertexId v[3];
      for (int i = 0; i < 3; ++i) {
        v[i] = here[r.tin_.origin(3 * t + static_cast<EdgeId>(i))];
        if (v[i] == kNoId) return kNoId;
      }
      const EdgeId first = tin_.edge_from(v[0]);
      EdgeId e = first;
      do {
        if (tin_.dest(e) == v[1]) return tin_.apex(e) == v[2] ? triangle_of(e) : kNoId;
        e = tin_.twin(prev_edge(e));
      } while (e != first);
      return kNoId;
    };

    // Per slot of this TIN: the part and slot it takes as it is, if any; the rest is loose.
    // A part at a time, on all threads (no two parts share a triangle of this TIN). Each part's
    // loose points in the order of their ids, which is spatial (a grid, or the Delaunay stage's
    // Hilbert order), so that the walks that locate them are short and stay in cache.
    std::vector<std::pair<std::uint32_t, TriangleId>> source(slots, {kNoId, kNoId});
    std::vector<std::vector<TriangleId>> target_of(parts.size());  // the other way round
    std::vector<std::vector<std::uint32_t>> loose_of(parts.size());
    auto match_part = [&](std::size_t k, std::size_t) {
      std::vector<std::uint32_t>& loose = loose_of[k];
      const auto add_loose = [&](std::uint32_t q) {
        if (vertex_of.find(q) == kNoId) loose.push_back(q);  // not a vertex
      };
      const Simplifier* r = parts[k].run;
      if (!r) {  // (ascending already)
        for (std::uint32_t q : parts[k].points) add_loose(q);
        return;
      }
      target_of[k].assign(r->count_.size(), kNoId);
      std::vector<VertexId> here(r->point_of_vertex_.size());  // (a lookup per vertex, not corner)
      for (VertexId w = 0; w < here.size(); ++w) {
        const std::uint32_t q = r->point_of_vertex_[w];
        here[w] = q == kNoId ? kNoId : vertex_of.find(q);
      }
      for (TriangleId t = 0; t < r->count_.size(); ++t) {
        if (r->count_[t] == 0) continue;
        const TriangleId u = find(*r, here, static_cast<TriangleId>(t));
        if (u != kNoId) {
          source[u] = {static_cast<std::uint32_t>(k), t};
          target_of[k][t] = u;
          continue;
        }
        for (std::size_t j = r->begin_[t]; j < r->begin_[t] + r->count_[t]; ++j)
          add_loose(r->ids_[j]);
      }
      for (VertexId w = 0; w < here.size(); ++w)
        if (r->point_of_vertex_[w] != kNoId && here[w] == kNoId)
          loose.push_back(r->point_of_vertex_[w]);
      std::sort(loose.begin(), loose.end());
    };
    pool_.run(match_part, parts.size());
    std::vector<std::uint32_t> loose;
    for (const auto& l : loose_of) loose.insert(loose.end(), l.begin(), l.end());
    release(loose_of);

    // The loose points located, on all threads.
    std::vector<TriangleId> loose_triangle(loose.size());
    auto locate_chunk = [&](std::size_t c, std::size_t chunks) {
      Walk walk(*this, c);
      for (std::size_t i = loose.size() * c / chunks; i < loose.size() * (c + 1) / chunks; ++i)
        loose_triangle[i] = walk.to(xy_[loose[i]]);
    };
    pool_.run(locate_chunk, std::clamp<std::size_t>(loose.size() / kChunkPoints, 1, kMaxChunks));

    // The parts' runs kept their ranges in this run's arena (see run_regions): an adopted
    // triangle keeps its range where it is. A triangle with loose points gets a new one past
    // the arenas of the parts that ran (over the parts' point lists, now read): its adopted
    // points, then its loose ones, each in their order.
    std::size_t at = 0;                            // past the parts' arenas
    const std::less<const std::uint32_t*> before;  // (a total order on any pointers)
    for (const Part& part : parts) {
      if (!part.run) continue;
      if (before(part.run->ids_, ids_) ||
          before(ids_ + arena_size_, part.run->ids_ + part.run->arena_size_))
        throw InternalError("simplify: a part's arena is not in the adopting run's");
      at = std::max(at, static_cast<std::size_t>(part.run->ids_ - ids_) + part.run->arena_size_);
    }
    for (const TriangleId t : loose_triangle) ++count_[t];
    std::vector<std::size_t> cursor(slots);
    std::vector<std::uint8_t> measured(slots, 1);  // else adopted as it was
    std::uint64_t points = 0;
    for (std::size_t u = 0; u < slots; ++u) {
      const std::uint32_t loose_count = count_[u];
      if (source[u].first != kNoId) {
        const Simplifier& r = *parts[source[u].first].run;
        const TriangleId t = source[u].second;
        count_[u] += r.count_[t];
        if (loose_count == 0) {
          begin_[u] = static_cast<std::size_t>(r.ids_ - ids_) + r.begin_[t];
          set_tally(u, r.tally_of(t));
          measured[u] = 0;
          points += count_[u];
          continue;
        }
      }
      if (count_[u] == 0) continue;
      if (at + count_[u] > arena_size_)
        throw InternalError("simplify: the adopted ranges overflow the arena");
      begin_[u] = at;
      cursor[u] = at + count_[u] - loose_count;
      if (source[u].first != kNoId) {
        const Simplifier& r = *parts[source[u].first].run;
        std::copy_n(r.ids_ + r.begin_[source[u].second], count_[u] - loose_count, ids_ + at);
      }
      at += count_[u];
      points += count_[u];
    }
    arena_end_ = at;
    if (points != candidates_)  // each point once: in a triangle, or a vertex
      throw InternalError("simplify: the regions' triangles do not hold every point once");
    for (std::size_t i = 0; i < loose.size(); ++i) ids_[cursor[loose_triangle[i]]++] = loose[i];
    release(cursor);
    release(loose);
    release(loose_triangle);
    for_each_range([&](std::size_t u) {
      if (measured[u]) set_tally(u, measure(u));
    });
    queue_ranges();
    // The log of ranges in arena order, as compact() needs it: the ranges kept in place as
    // their runs' logs list them (the parts' arenas in the order they lie), then the new ones.
    ranges_.clear();
    std::vector<std::size_t> by_place;
    for (std::size_t k = 0; k < parts.size(); ++k)
      if (parts[k].run) by_place.push_back(k);
    std::sort(by_place.begin(), by_place.end(), [&](std::size_t a, std::size_t b) {
      return before(parts[a].run->ids_, parts[b].run->ids_);
    });
    for (const std::size_t k : by_place) {
      const Simplifier& r = *parts[k].run;
      const auto offset = static_cast<std::uint32_t>(r.ids_ - ids_);
      for (const auto& [begin, t] : r.ranges_) {
        if (r.count_[t] == 0 || r.begin_[t] != begin) continue;  // not live
        const TriangleId u = target_of[k][t];
        if (u != kNoId && !measured[u]) ranges_.push_back({offset + begin, u});
      }
    }
    for (std::size_t u = 0; u < slots; ++u)
      if (count_[u] > 0 && measured[u])
        ranges_.push_back({static_cast<std::uint32_t>(begin_[u]), static_cast<TriangleId>(u)});
  }

  // Every other point into the range of the triangle holding it, its error measured: on all
  // threads, each walking from the triangle of its previous point. ids_[j] holds the triangle
  // of the j-th point (kKept for a vertex) until a counting sort makes the ranges, in
  // [m, m + candidates).
  void assign_points() {
    const std::size_t n = set_.size();
    const std::size_t slots = tin_.triangle_slots();
    grow();

    // Where each point is, in chunks of consecutive points (every entry written: the arena
    // holds whatever its memory held).
    auto locate_chunk = [&](std::size_t c, std::size_t chunks) {
      Walk walk(*this, c);
      const std::size_t begin = n * c / chunks, end = n * (c + 1) / chunks;
      auto vertex = std::lower_bound(vertex_places_.begin(), vertex_places_.end(), begin);
      for (std::size_t i = begin; i < end; ++i) {
        if (vertex != vertex_places_.end() && *vertex == i) {
          ids_[i] = kKept;
          ++vertex;
          continue;
        }
        ids_[i] = walk.to(xy_[set_[i]]);
      }
    };
    pool_.run(locate_chunk, std::clamp<std::size_t>(n / kChunkPoints, 1, kMaxChunks));

    // The ranges, in slot order, each in point order.
    for (std::size_t i = 0; i < n; ++i)
      if (ids_[i] != kKept) ++count_[ids_[i]];
    std::size_t at = n;
    for (std::size_t t = 0; t < slots; ++t) {
      begin_[t] = at;
      at += count_[t];
    }
    arena_end_ = at;
    // Each point measured as it is placed: in point order, the order of its range (the
    // points' arrays are read in order, and the triangles' planes and tallies are few).
    std::vector<std::size_t> cursor(begin_.begin(),
                                    begin_.begin() + static_cast<std::ptrdiff_t>(slots));
    std::vector<Plane> planes(slots);
    for (std::size_t t = 0; t < slots; ++t)
      if (count_[t] > 0) planes[t] = plane_of(static_cast<TriangleId>(t));
    std::vector<Tally> tallies(slots);
    for (std::size_t i = 0; i < n; ++i) {
      const TriangleId t = ids_[i];
      if (t == kKept) continue;
      const std::uint32_t q = set_[i];
      ids_[cursor[t]++] = q;
      tallies[t].add(planes[t].error(xy_[q], z_[q]), q, xy_.data());
    }
    release(cursor);
    for (std::size_t t = 0; t < slots; ++t)
      if (count_[t] > 0) set_tally(t, tallies[t]);

    queue_ranges();
    // The log of ranges, in slot order, which is arena order here.
    ranges_.clear();
    for (std::size_t t = 0; t < slots; ++t)
      if (count_[t] > 0)
        ranges_.push_back({static_cast<std::uint32_t>(begin_[t]), static_cast<TriangleId>(t)});
  }

  // Every triangle beyond the tolerance into the queue; the others' points counted as settled.
  void queue_ranges() {
    for (std::size_t t = 0; t < count_.size(); ++t) {
      if (count_[t] == 0) continue;
      if (worst_error_[t] <= options_.max_error)
        settled_ += count_[t];
      else
        queue_.append({worst_error_[t], worst_[t], static_cast<TriangleId>(t)});
    }
    queue_.build();
  }

  // The greedy loop: the worst point in, the points of the triangles it replaced measured
  // again, until all are within the tolerance or the vertex budget is spent.
  void run(const ProgressFn* progress) {
    Progress report(progress, "simplify", candidates_ ? candidates_ : 1);
    mesh::PointInserter inserter(tin_);
    while (!queue_.empty()) {
      const Entry top = queue_.top();  // insert() updates its slot
      if (options_.max_vertices && tin_.vertex_count() >= options_.max_vertices) {
        report_.stopped_at_max_vertices = true;
        break;
      }
      insert(inserter, top.point, top.tri);
      ++report_.inserted;
      report.tick(settled_);
    }
    report.finish();
  }

  // The points the greedy loop inserted, in the order it did.
  std::vector<std::uint32_t> greedy_order() const {
    return {point_of_vertex_.begin() + static_cast<std::ptrdiff_t>(first_greedy_vertex_),
            point_of_vertex_.end()};
  }

  SimplifyResult finish() {
    // The squares as each triangle's points were last measured, in slot order: the same for
    // any thread count.
    double max_error = 0, sum_sq = 0;
    for (std::size_t t = 0; t < count_.size(); ++t) {
      if (count_[t] == 0) continue;
      max_error = std::max(max_error, worst_error_[t]);
      sum_sq += sum_sq_[t];
    }
    report_.max_error = max_error;
    report_.rmse = report_.points ? std::sqrt(sum_sq / static_cast<double>(report_.points)) : 0;
    tin_.recount();
    report_.vertices = tin_.vertex_count();
    SimplifyResult result;
    result.tin = std::move(tin_);
    result.point_of_vertex = std::move(point_of_vertex_);
    result.report = report_;
    return result;
  }

 private:
  struct Range {
    std::size_t begin, count;
  };
  // Work is split in chunks of at least this many points (fewer are not worth a handoff
  // between threads), at most kMaxChunks of them, whatever the thread count: what a chunk
  // computes never depends on the thread that runs it, so neither does the result.
  static constexpr std::size_t kChunkPoints = 1 << 13;
  static constexpr std::size_t kMaxChunks = 16;
  static constexpr std::size_t kPrefetch = 16;  // points ahead

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
    InteriorFilter filter(TriangleId t) const {
      const EdgeId e = 3 * t;
      return {s_.pt(s_.tin_.origin(e)), s_.pt(s_.tin_.origin(e + 1)), s_.pt(s_.tin_.origin(e + 2))};
    }

    const Simplifier& s_;
    std::uint64_t random_;
    TriangleId t_;
    InteriorFilter inside_;
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
    const std::size_t chunks = std::clamp<std::size_t>(points / kChunkPoints, 1, kMaxChunks);
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
  TriangleId locate(Point2 p, TriangleId t, std::uint64_t& random) const {
    EdgeId from = kNoId;
    for (;;) {
      const auto first = static_cast<EdgeId>(random_edge(random));
      EdgeId crossed = kNoId, zero = kNoId;
      int zeros = 0;
      for (EdgeId i = 0; i < 3; ++i) {
        const EdgeId e = 3 * t + (first + i) % 3;
        const int o = e == from ? 1 : orient2d(pt(tin_.origin(e)), pt(tin_.dest(e)), p);
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
      if (tin_.apex(from) == kInfinite)
        throw InternalError("simplify: a point lies outside the hull of the kept points");
    }
  }

  // Inserts point p, which lies in triangle t, and measures again the points of the triangles
  // the insertion replaced: they are exactly the triangles now around the new vertex (Lawson
  // flips only replace triangles by triangles that have it as a corner).
  void insert(mesh::PointInserter& inserter, std::uint32_t p, TriangleId t) {
    const Point2 at = xy_[p];
    const mesh::Location where = inserter.locate(at, t);
    if (where.kind == mesh::Location::on_vertex)
      throw GeometryError("simplify: a point shares x, y with a vertex (merge duplicates first)");
    const VertexId v = tin_.add_vertex(at, z_[p]);
    point_of_vertex_.push_back(p);
    inserter.insert(v, where);
    grow();

    // The star of v, counter-clockwise. Its real triangles form one cyclic run (v inside the
    // hull) or, v on the hull, one run from the vertex after the edge v -> inf.
    star_.clear();
    const EdgeId e0 = tin_.edge_from(v);
    EdgeId e = e0;
    do {
      star_.push_back(e);
      e = tin_.twin(prev_edge(e));
    } while (e != e0);
    const std::size_t k = star_.size();
    std::size_t ghost = k;
    for (std::size_t i = 0; i < k; ++i)
      if (tin_.dest(star_[i]) == kInfinite) ghost = i;
    const bool cyclic = ghost == k;
    const std::size_t first = cyclic ? 0 : ghost + 1;
    ring_.clear();
    spokes_.clear();
    cones_.clear();
    for (std::size_t i = 0; i < (cyclic ? k : k - 1); ++i)
      ring_.push_back(pt(tin_.dest(star_[(first + i) % k])));
    if (cyclic) ring_.push_back(ring_.front());
    double reach = 0;
    for (const Point2& r : ring_) {
      spokes_.push_back({r.x - at.x, r.y - at.y});
      reach = std::max({reach, std::fabs(spokes_.back().x), std::fabs(spokes_.back().y)});
    }
    bounds_.clear();
    for (const Point2& d : spokes_) bounds_.push_back(predicates::cross_bound(d, reach));
    for (std::size_t i = 0; i < (cyclic ? k : k - 2); ++i) {
      const EdgeId s = star_[(first + i) % k];
      const VertexId a = tin_.dest(s), b = tin_.apex(s);
      cones_.push_back({triangle_of(s), Gradient(at, z_[p], pt(a), tin_.z(a), pt(b), tin_.z(b))});
    }

    // The replaced triangles' ranges (the star's slots that held points); their slots reset.
    std::size_t total = 0;
    for (const EdgeId s : star_) total += count_[triangle_of(s)];
    if (arena_end_ + total > arena_size_) compact();
    old_.clear();
    for (const EdgeId s : star_) {
      const TriangleId u = triangle_of(s);
      if (count_[u] == 0) continue;
      old_.push_back({begin_[u], count_[u]});
      if (worst_error_[u] <= options_.max_error) settled_ -= count_[u];
      count_[u] = 0;
      worst_[u] = kNoId;
      worst_error_[u] = -1.0;
      sum_sq_[u] = 0;
    }
    const Fan fan{at,
                  z_[p],
                  ring_.data(),
                  spokes_.data(),
                  bounds_.data(),
                  cones_.data(),
                  static_cast<int>(cones_.size()),
                  cyclic};
    if (cones_.size() < 255)
      redistribute(fan, p, total, cone8_, std::uint8_t{255});
    else
      redistribute(fan, p, total, cone32_, kNoId);

    // The star's slots held the replaced triangles: their entries go or take the new values.
    for (const EdgeId s : star_) {
      const TriangleId u = triangle_of(s);
      if (count_[u] == 0 || worst_error_[u] <= options_.max_error) queue_.erase(u);
    }
    for (const Cone& cone : cones_) {
      const TriangleId u = cone.tri;
      if (count_[u] == 0) continue;
      if (worst_error_[u] <= options_.max_error)
        settled_ += count_[u];
      else
        queue_.set({worst_error_[u], worst_[u], u});
    }
  }

  // The points of the old ranges (all but p) into new ranges, one per cone, at the arena's
  // end: first each point's cone and error (split among threads when there are many), then
  // the moves. Each new range keeps its points in their old order.
  template <class C>
  void redistribute(const Fan& fan, std::uint32_t p, std::size_t total, std::vector<C>& cone_of,
                    C skip) {
    const auto m = static_cast<std::size_t>(fan.m);
    if (cone_of.size() < total) cone_of.resize(total);
    const std::size_t chunks = std::clamp<std::size_t>(total / kChunkPoints, 1, kMaxChunks);
    tallies_.assign(chunks * m, Tally{});
    // A few ranges become one run of ids, so that the prefetches in scan() run across them
    // (most ranges are shorter than the prefetch distance).
    const std::uint32_t* gathered = nullptr;
    if (chunks == 1 && old_.size() > 1) {
      gathered_.clear();
      for (const Range& r : old_)
        gathered_.insert(gathered_.end(), ids_ + r.begin, ids_ + r.begin + r.count);
      gathered = gathered_.data();
    }
    // Calls f(ids, count, j) on the slices of the old ranges that hold points [lo, hi) of their
    // concatenation, j being the first one's place in it.
    const auto for_slices = [&](std::size_t lo, std::size_t hi, auto&& f) {
      if (gathered) {
        if (lo < hi) f(gathered + lo, hi - lo, lo);
        return;
      }
      std::size_t j = 0;
      for (const Range& r : old_) {
        const std::size_t from = std::max(lo, j), to = std::min(hi, j + r.count);
        if (from < to) f(ids_ + r.begin + (from - j), to - from, from);
        j += r.count;
      }
    };
    auto scan_chunk = [&](std::size_t c, std::size_t n_chunks) {
      Tally* tally = tallies_.data() + c * m;
      int hint = 0;
      for_slices(total * c / n_chunks, total * (c + 1) / n_chunks,
                 [&](const std::uint32_t* ids, std::size_t count, std::size_t j) {
                   hint = scan(fan, ids, count, p, cone_of.data() + j, skip, tally, hint);
                 });
    };
    pool_.run(scan_chunk, chunks);
    // New ranges cone by cone, each chunk's share in chunk order; a tally's count becomes
    // its chunk's write position.
    std::size_t at = arena_end_;
    for (std::size_t i = 0; i < m; ++i) {
      const TriangleId u = fan.cones[i].tri;
      begin_[u] = at;
      for (std::size_t c = 0; c < chunks; ++c) {
        Tally& t = tallies_[c * m + i];
        absorb(t, u);
        const std::size_t count = t.count;
        t.count = static_cast<std::uint32_t>(at - arena_end_);
        at += count;
      }
      if (count_[u] > 0) ranges_.push_back({static_cast<std::uint32_t>(begin_[u]), u});
    }
    std::uint32_t* out = ids_ + arena_end_;
    arena_end_ = at;
    auto move_chunk = [&](std::size_t c, std::size_t n_chunks) {
      Tally* cursor = tallies_.data() + c * m;
      for_slices(total * c / n_chunks, total * (c + 1) / n_chunks,
                 [&](const std::uint32_t* ids, std::size_t count, std::size_t j) {
                   const C* cone = cone_of.data() + j;
                   for (std::size_t i = 0; i < count; ++i)
                     if (cone[i] != skip) out[cursor[cone[i]].count++] = ids[i];
                 });
    };
    pool_.run(move_chunk, chunks);
  }

  // Classifies and measures `count` points: their cones into `cone` (p, the new vertex,
  // gets `skip`), their errors into the cones' tallies. Returns the last cone, the next hint.
  template <class C>
  int scan(const Fan& shared_fan, const std::uint32_t* ids, std::size_t count, std::uint32_t p,
           C* cone, C skip, Tally* tally, int hint) const {
    // A copy in registers: the byte stores to `cone` may alias anything in memory.
    const Fan fan = shared_fan;
    const Point2* xy = xy_.data();
    const double* z = z_.data();
    for (std::size_t i = 0; i < count; ++i) {
      if (i + kPrefetch < count) {  // the points are scattered: ask for them ahead
        __builtin_prefetch(xy + ids[i + kPrefetch]);
        __builtin_prefetch(z + ids[i + kPrefetch]);
      }
      const std::uint32_t q = ids[i];
      if (q == p) {
        cone[i] = skip;
        continue;
      }
      const Point2 xq = xy[q];
      const Point2 d{xq.x - fan.apex.x, xq.y - fan.apex.y};
      hint = fan.classify(xq, d, hint);
      cone[i] = static_cast<C>(hint);
      const Gradient& g = fan.cones[hint].plane;
      tally[hint].add(std::fabs(z[q] - (fan.apex_z + g.gx * d.x + g.gy * d.y)), q, xy);
    }
    return hint;
  }

  // Moves the live ranges to the front of the arena, in the order they lie.
  // (The log of ranges is in arena order: a range is live if its slot still has it.)
  void compact() {
    std::size_t at = 0, live = 0;
    for (const auto& [begin, t] : ranges_) {
      if (count_[t] == 0 || begin_[t] != begin) continue;
      std::copy_n(ids_ + begin, count_[t], ids_ + at);  // at <= begin
      begin_[t] = at;
      ranges_[live++] = {static_cast<std::uint32_t>(at), t};
      at += count_[t];
    }
    ranges_.resize(live);
    arena_end_ = at;
  }

  PointSet set_;
  std::span<const Point2> xy_;
  std::span<const double> z_;
  SimplifyOptions options_;
  Triangulation tin_;
  std::vector<std::uint32_t> point_of_vertex_;
  SimplifyReport report_;
  Pool pool_;

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

}  // namespace

namespace {

// Inputs this large start from seeds (below); smaller ones are cheap enough without.
constexpr std::size_t kSeedMinPoints = std::size_t{1} << 16;
// The coarse run sees about one point in 2^kThinningBits (kThinningBits of a hash per depth),
// stops at kSeedTolerance times the tolerance and hands on all its insertions.
constexpr int kThinningBits = 4;
constexpr double kSeedTolerance = 3;

// A greedy run before finish(): its state, and the points it inserted, seeds first, in order.
struct Unfinished {
  std::unique_ptr<Simplifier> run;
  std::vector<std::uint32_t> order;
};

Unfinished run_greedy(const PointSet& set, std::span<const std::uint32_t> kept,
                      std::span<const constraints::Segment> segments,
                      const SimplifyOptions& options, const ProgressFn* progress, int depth,
                      std::span<std::uint32_t> arena = {});

// A hash of a point's x, y bits: which points the coarse run sees depends on nothing else.
std::uint64_t xy_hash(Point2 p) {
  const auto mix = [](std::uint64_t h) {
    h ^= h >> 31;
    h *= 0x7fb5d329728ea185ULL;
    h ^= h >> 27;
    h *= 0x81dadef4bc2dd44dULL;
    return h ^ (h >> 33);
  };
  std::uint64_t x, y;
  const double px = p.x + 0.0, py = p.y + 0.0;  // -0 as +0
  std::memcpy(&x, &px, sizeof x);
  std::memcpy(&y, &py, sizeof y);
  return mix(x ^ mix(y + 0x9e3779b97f4a7c15ULL));
}

// The early insertions of the greedy loop rescan nearly every point each (the first triangles
// hold millions): O(n log k) work for the first k insertions. The same greedy run on a thinned
// subset (the kept points and segments, and about one point in 2^kThinningBits, chosen by a
// hash of x, y; other bits of it at each depth) finds nearly the same first insertions at a
// fraction of that cost. It runs to kSeedTolerance times the tolerance (the greedy run's first
// third or so of its insertions, as the vertex count needed goes about as the inverse of the
// tolerance), and all its insertions start the full run, which then refines as before.
// (Recursively: a large subset is itself seeded.) Within 1.5% in vertex count either way on the
// benchmark grids (3 rather than 4: 4-6% faster, and no more vertices). Not with a vertex budget:
// there the greedy order alone decides which vertices are in.
std::vector<std::uint32_t> coarse_seeds(const PointSet& set, std::span<const std::uint32_t> kept,
                                        std::span<const constraints::Segment> segments,
                                        const SimplifyOptions& options, int depth) {
  const std::size_t n = set.size();
  if (n < kSeedMinPoints || options.max_vertices) return {};
  // The points that must be in (few next to n), sorted: merged with the scan below, so that no
  // array of n entries is needed (fresh pages cost more than their use here). Points that are
  // not in the set are left to the full run to report.
  std::vector<std::uint32_t> must;
  const auto in_set = [&](std::uint32_t i) { return set.find(i) < n; };
  for (std::uint32_t i : kept)
    if (in_set(i)) must.push_back(i);
  for (const constraints::Segment& s : segments)
    if (in_set(s.a) && in_set(s.b)) must.insert(must.end(), {s.a, s.b});
  std::sort(must.begin(), must.end());
  must.erase(std::unique(must.begin(), must.end()), must.end());
  std::vector<Point2> sub_xy;
  std::vector<double> sub_z;
  std::vector<std::uint32_t> point_of_sub;
  const std::size_t expected = must.size() + (n >> kThinningBits) + (n >> (kThinningBits + 3));
  sub_xy.reserve(expected);
  sub_z.reserve(expected);
  point_of_sub.reserve(expected);
  const std::uint64_t mask = (std::uint64_t{1} << kThinningBits) - 1;
  std::size_t next = 0;  // in must
  for (std::size_t j = 0; j < n; ++j) {
    const std::uint32_t i = set[j];
    const bool required = next < must.size() && must[next] == i;
    next += required;
    if (!required && ((xy_hash(set.xy[i]) >> (kThinningBits * depth)) & mask) != 0) continue;
    point_of_sub.push_back(i);
    sub_xy.push_back(set.xy[i]);
    sub_z.push_back(set.z[i]);
  }
  const auto sub_of = [&](std::uint32_t i) {
    return static_cast<std::uint32_t>(
        std::lower_bound(point_of_sub.begin(), point_of_sub.end(), i) - point_of_sub.begin());
  };
  std::vector<std::uint32_t> sub_kept;
  for (std::uint32_t i : kept)
    if (in_set(i)) sub_kept.push_back(sub_of(i));
  std::vector<constraints::Segment> sub_segments;
  for (const constraints::Segment& s : segments)
    if (in_set(s.a) && in_set(s.b)) sub_segments.push_back({sub_of(s.a), sub_of(s.b), s.source});
  SimplifyOptions coarse_options = options;
  coarse_options.max_error *= kSeedTolerance;
  const Unfinished coarse =
      run_greedy({sub_xy, sub_z, {}}, sub_kept, sub_segments, coarse_options, nullptr, depth + 1);
  std::vector<std::uint32_t> seeds;
  seeds.reserve(coarse.order.size());
  for (const std::uint32_t k : coarse.order) seeds.push_back(point_of_sub[k]);
  return seeds;
}

// The greedy run on the points of `set`, from the seeds coarse_seeds() finds (depth: of coarse
// runs), in `arena` (empty: its own).
Unfinished run_greedy(const PointSet& set, std::span<const std::uint32_t> kept,
                      std::span<const constraints::Segment> segments,
                      const SimplifyOptions& options, const ProgressFn* progress, int depth,
                      std::span<std::uint32_t> arena) {
  const std::vector<std::uint32_t> seeds = coarse_seeds(set, kept, segments, options, depth);
  Unfinished u{std::make_unique<Simplifier>(set, options, arena), {}};
  u.run->start(kept, segments, seeds);
  u.run->assign_points();
  u.run->run(progress);
  u.order.assign(seeds.begin(), seeds.end());
  const std::vector<std::uint32_t> order = u.run->greedy_order();
  u.order.insert(u.order.end(), order.begin(), order.end());
  return u;
}

// Inputs this large are split into kRegionsPerSide^2 regions, the cells of a grid over the
// points' bounding box (independent of the thread count: the regions decide the result). Each
// region's points are simplified on their own, the regions on all threads at once, with the
// kept points and segments that lie in them. All a region inserted, except within kSeamShare
// of a cell's side of an edge it shares with another, seeds the run on all points (with all
// kept points and segments), which then has little left to do but the seams. The regions are
// only a start: the last run alone decides that every point is within the tolerance. Smaller
// regions are faster (their points stay in cache) but their seams cost vertices and time.
// Not with a vertex budget (see coarse_seeds).
constexpr std::size_t kRegionMinPoints = std::size_t{1} << 18;
constexpr int kRegionsPerSide = 2;
constexpr std::size_t kRegions = kRegionsPerSide * kRegionsPerSide;
constexpr double kSeamShare = 1.0 / 128;
// The share of the stage's progress the regions take (the last run has the rest).
constexpr double kRegionProgress = 0.9;

// The regions' runs on `threads` threads, the calling one included: only the calling thread
// calls the progress callback; its request to stop (or its exception) reaches the others through
// stop_. An error in a region's run does not stop the others, so that which one is reported
// (the first region's) does not depend on timing.
class RegionRuns {
 public:
  RegionRuns(std::vector<std::function<Unfinished(const ProgressFn*)>> runs,
             std::vector<double> weights, const ProgressFn* progress)
      : runs_(std::move(runs)),
        weights_(std::move(weights)),
        progress_(progress && *progress ? progress : nullptr),
        done_(runs_.size()),
        done_runs_(runs_.size()),
        errors_(runs_.size()) {}

  std::vector<Unfinished> run(unsigned threads) {
    const auto n = static_cast<unsigned>(runs_.size());
    left_ = n;
    std::vector<std::jthread> workers;  // joined however this ends
    try {
      for (unsigned i = 1; i < std::min(threads, n); ++i)
        workers.emplace_back([this] { work(false); });
    } catch (...) {  // no thread to be had: the others stop at their next report
      stop_ = true;
      throw;
    }
    work(true);
    if (progress_) {
      std::unique_lock lock(mutex_);
      while (left_ > 0) {
        if (finished_.wait_for(lock, std::chrono::milliseconds(20)) == std::cv_status::timeout) {
          lock.unlock();
          report();
          lock.lock();
        }
      }
    }
    for (std::jthread& t : workers) t.join();
    if (callback_error_) std::rethrow_exception(callback_error_);
    for (const std::exception_ptr& e : errors_)
      if (e) std::rethrow_exception(e);
    if (stop_) throw Cancelled();
    return std::move(done_runs_);
  }

 private:
  void work(bool caller) {
    for (;;) {
      const unsigned r = next_.fetch_add(1);
      if (r >= runs_.size()) return;
      const ProgressFn fn = [this, r, caller](std::string_view, double fraction) {
        done_[r].store(fraction, std::memory_order_relaxed);
        return caller ? report() : !stop_.load(std::memory_order_relaxed);
      };
      try {
        if (!stop_) done_runs_[r] = runs_[r](&fn);
      } catch (const Cancelled&) {
        stop_ = true;
      } catch (...) {
        errors_[r] = std::current_exception();
      }
      const std::lock_guard lock(mutex_);
      if (--left_ == 0) finished_.notify_all();
    }
  }

  // The regions' fractions, weighted, to the caller's callback; false when it asks to stop or
  // throws (rethrown once every thread is joined).
  bool report() {
    if (stop_) return false;
    if (!progress_) return true;
    double sum = 0;
    for (std::size_t r = 0; r < runs_.size(); ++r)
      sum += weights_[r] * done_[r].load(std::memory_order_relaxed);
    try {
      if (!(*progress_)("simplify", kRegionProgress * sum)) stop_ = true;
    } catch (...) {
      callback_error_ = std::current_exception();
      stop_ = true;
    }
    return !stop_;
  }

  std::vector<std::function<Unfinished(const ProgressFn*)>> runs_;
  std::vector<double> weights_;  // each region's share of the points
  const ProgressFn* progress_;
  std::vector<std::atomic<double>> done_;  // each region's fraction
  std::vector<Unfinished> done_runs_;      // a region's run, or none
  std::vector<std::exception_ptr> errors_;
  std::exception_ptr callback_error_;  // only the calling thread sets it
  std::atomic<unsigned> next_{0};
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::condition_variable finished_;
  unsigned left_ = 0;  // regions not finished; under mutex_
};

// The regions' runs (see kRegionsPerSide) and what they hand on to the last run. The regions'
// runs and the last run share one arena, so that the last run takes the triangles it adopts as
// they are, in memory already written (fresh pages cost more than their use): each region's
// arena (arena_slots() of its points) in turn, then the regions' point lists, which the last
// run's new ranges overwrite once adopt() has read them.
struct Regions {
  std::unique_ptr<std::uint32_t[]> arena;
  std::size_t arena_size = 0;
  std::vector<std::span<const std::uint32_t>> members;  // each region's points, ascending
  std::vector<Unfinished> runs;                         // each region's, or none
  std::vector<std::uint32_t> seeds;  // all they inserted but near the seams, ascending
};

// The regions' runs, or none when the input is too small or the regions do not apply. `kept`
// holds the corners of the points' hull, so it spans their box.
Regions run_regions(const PointSet& set, std::span<const std::uint32_t> kept,
                    std::span<const constraints::Segment> segments, const SimplifyOptions& options,
                    const ProgressFn* progress) {
  const std::size_t n = set.size();
  const std::size_t shared_arena = arena_slots(n) + (kRegions - 1) * arena_slots(0) + n;
  if (n < kRegionMinPoints || options.max_vertices || !set.ids.empty() ||
      shared_arena > UINT32_MAX)  // its places are 32-bit (regions to about 1.4e9 points)
    return {};
  for (std::uint32_t i : kept)
    if (i >= n) return {};  // the last run reports it
  for (const constraints::Segment& s : segments)
    if (s.a >= n || s.b >= n) return {};
  Point2 lo{INFINITY, INFINITY}, hi{-INFINITY, -INFINITY};
  for (std::uint32_t i : kept) {
    lo = {std::min(lo.x, set.xy[i].x), std::min(lo.y, set.xy[i].y)};
    hi = {std::max(hi.x, set.xy[i].x), std::max(hi.y, set.xy[i].y)};
  }
  if (!(hi.x > lo.x && hi.y > lo.y)) return {};
  // Where a point is in cell units: cell (i, j) holds i <= x < i + 1, j <= y < j + 1 (the last
  // ones up to kRegionsPerSide).
  constexpr int side = kRegionsPerSide;
  const Point2 cell_size{(hi.x - lo.x) / side, (hi.y - lo.y) / side};
  const auto place = [&](std::uint32_t i) {
    return Point2{(set.xy[i].x - lo.x) / cell_size.x, (set.xy[i].y - lo.y) / cell_size.y};
  };
  const auto cell = [](double p) { return std::min(side - 1, static_cast<int>(p)); };
  const auto region = [&](std::uint32_t i) {
    const Point2 p = place(i);
    return static_cast<std::size_t>(cell(p.x) + side * cell(p.y));
  };
  constexpr std::size_t regions = kRegions;
  Regions out;
  out.arena = std::make_unique_for_overwrite<std::uint32_t[]>(shared_arena);
  out.arena_size = shared_arena;
  std::uint32_t* const points = out.arena.get() + (shared_arena - n);
  out.members.resize(regions);
  std::vector<std::vector<std::uint32_t>> region_kept(regions);
  std::vector<std::vector<constraints::Segment>> region_segments(regions);
  {  // A counting sort of the points by region, in chunks on all threads (a pass over the
     // points costs what it reads: their regions are read once, and kept in a byte each).
    Pool pool(thread_count(options.threads));
    constexpr std::size_t chunks = 16;
    static_assert(regions <= 256);
    const auto region_of = std::make_unique_for_overwrite<std::uint8_t[]>(n);
    std::vector<std::size_t> at(chunks * regions, 0);  // chunk c's first place in region r
    const auto chunk_points = [&](std::size_t c) {
      return std::pair{n * c / chunks, n * (c + 1) / chunks};
    };
    // (Each chunk counts in an array of its own: the chunks' counts share cache lines.)
    auto count = [&](std::size_t c, std::size_t) {
      std::array<std::size_t, regions> counts{};
      for (auto [i, end] = chunk_points(c); i < end; ++i) {
        const std::size_t r = region(static_cast<std::uint32_t>(i));
        region_of[i] = static_cast<std::uint8_t>(r);
        ++counts[r];
      }
      std::copy(counts.begin(), counts.end(),
                at.begin() + static_cast<std::ptrdiff_t>(c * regions));
    };
    pool.run(count, chunks);
    std::size_t total = 0;
    for (std::size_t r = 0; r < regions; ++r) {
      const std::size_t first = total;
      for (std::size_t c = 0; c < chunks; ++c) total += std::exchange(at[c * regions + r], total);
      out.members[r] = {points + first, total - first};
    }
    auto place_chunk = [&](std::size_t c, std::size_t) {
      std::array<std::size_t, regions> cursor;
      std::copy_n(at.begin() + static_cast<std::ptrdiff_t>(c * regions), regions, cursor.begin());
      for (auto [i, end] = chunk_points(c); i < end; ++i)
        points[cursor[region_of[i]]++] = static_cast<std::uint32_t>(i);
    };
    pool.run(place_chunk, chunks);
  }
  for (std::uint32_t i : kept) region_kept[region(i)].push_back(i);
  // A segment across regions is in neither (its ends are in two), but its ends are kept where
  // they are: they are vertices of the last run, whatever the regions make of their surface.
  for (const constraints::Segment& s : segments) {
    if (region(s.a) == region(s.b)) {
      region_segments[region(s.a)].push_back(s);
    } else {
      region_kept[region(s.a)].push_back(s.a);
      region_kept[region(s.b)].push_back(s.b);
    }
  }
  // Near a shared edge, a region's run inserted points for its own hull's sake.
  const auto near_seam = [&](std::uint32_t i, std::size_t r) {
    const Point2 p = place(i);
    const auto x = static_cast<int>(r % side), y = static_cast<int>(r / side);
    return (x > 0 && p.x < x + kSeamShare) || (x + 1 < side && p.x > x + 1 - kSeamShare) ||
           (y > 0 && p.y < y + kSeamShare) || (y + 1 < side && p.y > y + 1 - kSeamShare);
  };

  SimplifyOptions region_options = options;
  region_options.threads = 1;
  std::vector<std::function<Unfinished(const ProgressFn*)>> runs;
  std::vector<double> weights;
  std::vector<std::vector<std::uint32_t>> seeds(regions);  // each region's, ascending
  for (std::size_t r = 0, arena_at = 0; r < regions; ++r) {
    const std::span<const std::uint32_t> members = out.members[r];
    const std::span<std::uint32_t> arena{out.arena.get() + arena_at, arena_slots(members.size())};
    arena_at += arena.size();
    weights.push_back(static_cast<double>(members.size()) / static_cast<double>(n));
    runs.emplace_back([&, r, members, arena](const ProgressFn* fn) {
      if (members.empty()) return Unfinished{};  // (an empty PointSet would be all points)
      std::vector<std::uint32_t> own_kept = hull_corners(set.xy, members);
      if (own_kept.size() < 3) return Unfinished{};  // collinear
      own_kept.insert(own_kept.end(), region_kept[r].begin(), region_kept[r].end());
      Unfinished u = run_greedy({set.xy, set.z, members}, own_kept, region_segments[r],
                                region_options, fn, 0, arena);
      // Sorted here, on the region's thread, for the last run, which needs them so.
      for (std::uint32_t i : u.order)
        if (!near_seam(i, r)) seeds[r].push_back(i);
      std::sort(seeds[r].begin(), seeds[r].end());
      return u;
    });
  }
  out.runs =
      RegionRuns(std::move(runs), std::move(weights), progress).run(thread_count(options.threads));
  for (const std::vector<std::uint32_t>& region_seeds : seeds) {
    const auto middle = static_cast<std::ptrdiff_t>(out.seeds.size());
    out.seeds.insert(out.seeds.end(), region_seeds.begin(), region_seeds.end());
    std::inplace_merge(out.seeds.begin(), out.seeds.begin() + middle, out.seeds.end());
  }
  return out;
}

// The whole simplification: the regions' runs when they apply, then the run on all points,
// seeded by them, which adopts the triangles it shares with them.
SimplifyResult simplify_all(const PointSet& set, std::span<const std::uint32_t> kept,
                            std::span<const constraints::Segment> segments,
                            const SimplifyOptions& options, const ProgressFn* progress) {
  if (set.size() > kMaxPoints)  // before any work, and before ids are narrowed to 32 bits
    throw GeometryError("simplify: too many points for 32-bit ids");
  Regions regions = run_regions(set, kept, segments, options, progress);
  if (regions.runs.empty())
    return run_greedy(set, kept, segments, options, progress, 0).run->finish();
  ProgressFn rest;
  if (progress && *progress)
    rest = [progress](std::string_view stage, double fraction) {
      return (*progress)(stage, kRegionProgress + (1 - kRegionProgress) * fraction);
    };
  const std::unique_ptr<std::uint32_t[]> arena = std::move(regions.arena);
  Simplifier s(set, options, {arena.get(), regions.arena_size});
  s.start(kept, segments, regions.seeds);
  std::uint32_t ran = 0;
  {
    std::vector<Simplifier::Part> parts;
    for (std::size_t r = 0; r < regions.runs.size(); ++r) {
      parts.push_back({regions.runs[r].run.get(), regions.members[r]});
      ran += parts.back().run != nullptr;
    }
    s.adopt(parts);
  }
  regions = {};  // their memory, before the run needs more
  s.run(progress ? &rest : nullptr);
  SimplifyResult out = s.finish();
  out.report.regions = ran;
  return out;
}

}  // namespace

SimplifyResult simplify(std::span<const Point2> xy, std::span<const double> z,
                        std::span<const std::uint32_t> kept,
                        std::span<const constraints::Segment> segments,
                        const SimplifyOptions& options, const ProgressFn* progress) {
  std::vector<std::uint32_t> all = hull_corners(xy);
  all.insert(all.end(), kept.begin(), kept.end());
  return simplify_all({xy, z, {}}, all, segments, options, progress);
}

SimplifyResult simplify_tin(const mesh::Triangulation& full, const SimplifyOptions& options,
                            const ProgressFn* progress) {
  std::vector<std::uint32_t> kept;
  std::vector<constraints::Segment> segments;
  full.for_each_constrained_edge([&](EdgeId e) {
    segments.push_back({full.origin(e), full.dest(e), 0});
  });
  // Strict hull corners, around the ring of ghosts (not a pass over every triangle, which reads
  // 400 MB on a 16M-point TIN): ghost (u, v, inf) lies outside hull edge v -> u, and the ghost
  // across its edge v -> inf lies outside the hull edge w -> v before it.
  const std::size_t slots = full.triangle_slots();
  TriangleId first = 0;
  while (first < slots && !full.is_ghost(first)) ++first;
  TriangleId t = first;
  for (std::size_t steps = 0; first < slots; ++steps) {
    if (steps == slots) throw InternalError("simplify: the ghosts are not one ring");
    const auto tri = full.triangle(t);
    int k = 0;
    while (k < 3 && tri[k] != kInfinite) ++k;
    const VertexId u = tri[(k + 1) % 3], v = tri[(k + 2) % 3];
    const EdgeId inf_v = full.twin(3 * t + static_cast<EdgeId>((k + 2) % 3));
    const VertexId w = full.dest(next_edge(inf_v));
    if (orient2d(full.point(w), full.point(v), full.point(u)) != 0) kept.push_back(v);
    t = triangle_of(inf_v);
    if (t == first) break;
  }
  return simplify_all({full.points(), full.heights(), {}}, kept, segments, options, progress);
}

}  // namespace tincdt::simplify
