#include "products/contours.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "core/parallel.hpp"
#include "products/short_number.hpp"

namespace tincdt::products {

using mesh::prev_edge;
using mesh::triangle_of;

namespace {

constexpr std::int64_t kMaxLevels = 10'000'000;

// Smallest k with level(k) > z.
std::int64_t first_level_above(double base, double interval, double z) {
  auto k = static_cast<std::int64_t>(std::ceil((z - base) / interval));
  const auto below = [&](std::int64_t i) { return contour_level(base, interval, i) <= z; };
  // The estimate is off by at most a step or two from rounding; settle it with the formula.
  while (!below(k - 1)) --k;
  while (below(k)) ++k;
  return k;
}

// One level's work: the geometry of crossings and the chaining through twins.
//
// A triangle crossed by the level has one lone corner (alone on its side) and its segment joins
// the crossings on the two edges at that corner. The chain continues across the edge where the
// segment ends (its "up" edge) into the triangle on the other side, which starts there.
//
// One degenerate case needs more: a ridge exactly at the level. When a triangle's two corners
// above are both on the level and the triangle across that edge also has its third corner below,
// both triangles' segments lie on that edge, in opposite directions: the ridge, with lower
// ground on both sides, would be traced twice (and so it would, in doubles, when its corners are
// a rounding above the level). Those two segments are left out and the chains
// spliced at the ridge's ends (the chain arriving at one end continues with the one leaving it
// on the other side), so a ridge at the level gives no line, like a valley at the level.
class LevelTracer {
 public:
  // PROGRESS (may be null) hears a heartbeat for every triangle traced.
  LevelTracer(const mesh::Triangulation& tin, std::vector<std::uint32_t>& stamp, Progress* progress)
      : tin_(tin), stamp_(stamp), progress_(progress) {}

  // Traces every chain through the triangles of BUCKET (the kept triangles crossed by LEVEL),
  // appending lines to OUT. STAMP_VALUE marks the triangles already traced at this level.
  void trace(double level, std::uint32_t stamp_value, const TriangleId* bucket, std::size_t n,
             ContourSet& out) {
    level_ = level;
    for (std::size_t i = 0; i < n; ++i) {
      const TriangleId t = bucket[i];
      if (stamp_[t] == stamp_value || ridge_twin(t) != kNoId) continue;
      // Back to the start of t's chain: a triangle whose segment starts on the boundary of the
      // kept region, or t again (a ring).
      TriangleId start = t;
      bool ring = false;
      for (;;) {
        const TriangleId before = previous(start);
        if (before == kNoId) break;
        if (before == t) {
          ring = true;
          break;
        }
        start = before;
      }
      raw_.clear();
      TriangleId cur = start;
      raw_.push_back(crossing(crossed(cur).down));
      for (;;) {
        if (progress_ != nullptr) progress_->heartbeat();
        stamp_[cur] = stamp_value;
        raw_.push_back(crossing(crossed(cur).up));
        const TriangleId after = next(cur);
        if (after == start || after == kNoId) break;
        cur = after;
      }
      emit(ring, out);
    }
  }

 private:
  struct Crossed {
    EdgeId down;      // runs from above to below: the segment starts on it
    EdgeId up;        // runs from below to above: the segment ends on it
    EdgeId opposite;  // the edge opposite the lone corner
    bool lone_below;
  };

  bool above(VertexId v) const { return tin_.z(v) >= level_; }

  // The two crossed half-edges of a triangle the level crosses: the two at its lone corner.
  // Going from the crossing on `down` to the one on `up` keeps the ground above on the left.
  Crossed crossed(TriangleId t) const {
    const EdgeId e0 = 3 * t;
    const bool a0 = above(tin_.origin(e0)), a1 = above(tin_.origin(e0 + 1));
    const bool a2 = above(tin_.origin(e0 + 2));
    const EdgeId from_lone = a0 != a1 && a0 != a2 ? e0 : (a1 != a0 && a1 != a2 ? e0 + 1 : e0 + 2);
    const EdgeId to_lone = prev_edge(from_lone);
    const EdgeId opposite = mesh::next_edge(from_lone);
    if (above(tin_.origin(from_lone))) return {from_lone, to_lone, opposite, false};
    return {to_lone, from_lone, opposite, true};
  }

  // For a triangle whose segment is half of a ridge at the level (see the class comment), the
  // triangle on the ridge's other side; else kNoId. "At the level" is geometric: the crossings
  // are the ridge's end vertices themselves, which covers vertices whose z is so close above the
  // level that the crossing rounds onto them (two lines a rounding apart would be one line
  // twice in doubles).
  TriangleId ridge_twin(TriangleId t) const {
    if (!on_ridge_edge(t)) return kNoId;
    const EdgeId f = tin_.twin(crossed(t).opposite);
    const TriangleId other = triangle_of(f);
    if (!tin_.is_kept(other) || above(tin_.apex(f)) || !on_ridge_edge(other)) return kNoId;
    return other;
  }

  // True when T's corner alone below the level is the apex of an edge whose two ends are both
  // crossings: T's segment runs along that edge.
  bool on_ridge_edge(TriangleId t) const {
    const Crossed c = crossed(t);
    if (!c.lone_below) return false;
    return crossing(c.down) == tin_.point(tin_.origin(c.down)) &&
           crossing(c.up) == tin_.point(tin_.dest(c.up));
  }

  // The next and previous triangles along a chain, skipping ridge halves: the chain arriving at
  // a ridge half continues after the ridge's other half. (This ends: the triangle before a
  // triangle is unique, so the skips cannot cycle without passing the start again, which is not
  // a ridge half.)
  TriangleId next(TriangleId t) const {
    for (;;) {
      const TriangleId after = triangle_of(tin_.twin(crossed(t).up));
      if (!tin_.is_kept(after)) return kNoId;
      const TriangleId other = ridge_twin(after);
      if (other == kNoId) return after;
      t = other;
    }
  }
  TriangleId previous(TriangleId t) const {
    for (;;) {
      const TriangleId before = triangle_of(tin_.twin(crossed(t).down));
      if (!tin_.is_kept(before)) return kNoId;
      const TriangleId other = ridge_twin(before);
      if (other == kNoId) return before;
      t = other;
    }
  }

  // Where the level crosses the edge of E, computed from its (below, above) ends whichever
  // direction E runs, so both triangles of the edge get the same point to the bit. Exactly the
  // above end when that is on the level; otherwise interpolated from the nearer end.
  Point2 crossing(EdgeId e) const {
    VertexId lo = tin_.origin(e), hi = tin_.dest(e);
    if (above(lo)) std::swap(lo, hi);
    const Point2 p = tin_.point(lo), q = tin_.point(hi);
    const double zp = tin_.z(lo), zq = tin_.z(hi);
    if (zq == level_) return q;
    const double dz = zq - zp;
    const double t = (level_ - zp) / dz;
    if (t <= 0.5) return {p.x + t * (q.x - p.x), p.y + t * (q.y - p.y)};
    const double s = (zq - level_) / dz;
    return {q.x + s * (p.x - q.x), q.y + s * (p.y - q.y)};
  }

  // Appends raw_ as a line without its repeated points (the zero-length pieces next to a vertex
  // on the level), cyclically for a ring, unless nothing is left of it (a peak exactly at the
  // level, where all crossings are the peak itself).
  void emit(bool ring, ContourSet& out) {
    if (ring) raw_.pop_back();  // the trace ends where it began
    const std::size_t first = out.points.size();
    for (const Point2& p : raw_)
      if (out.points.size() == first || out.points.back() != p) out.points.push_back(p);
    if (ring)
      while (out.points.size() - first >= 2 && out.points.back() == out.points[first])
        out.points.pop_back();
    const std::size_t count = out.points.size() - first;
    if (count < (ring ? 3u : 2u)) {
      out.points.resize(first);
      return;
    }
    if (ring) out.points.push_back(out.points[first]);
    out.lines.push_back({level_, ring, first, out.points.size() - first});
  }

  const mesh::Triangulation& tin_;
  std::vector<std::uint32_t>& stamp_;
  Progress* progress_;
  double level_ = 0;
  std::vector<Point2> raw_;
};

// The z range of the kept triangles' corners; empty (min > max) when there are none.
struct ZRange {
  double min = std::numeric_limits<double>::infinity();
  double max = -std::numeric_limits<double>::infinity();
};

ZRange z_range(const mesh::Triangulation& tin) {
  ZRange z;
  tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& c) {
    for (const VertexId v : c) {
      z.min = std::min(z.min, tin.z(v));
      z.max = std::max(z.max, tin.z(v));
    }
  });
  if (z.min <= z.max && (!std::isfinite(z.min) || !std::isfinite(z.max)))
    throw Error("the TIN has a vertex whose z is not a finite number");
  return z;
}

// The levels that cross the TIN, numbered j = 0 .. count - 1 upward: those with
// z_min < level <= z_max (a level at z_min crosses nothing: the lowest vertices count as above
// it). Either base + (k_lo + j) * interval, or fixed[j].
struct Levels {
  std::size_t count = 0;
  double base = 0, interval = 0;
  std::int64_t k_lo = 0;
  std::vector<double> fixed;  // sorted, each once; empty for levels by interval
  bool by_interval = true;

  double value(std::size_t j) const {
    return by_interval ? contour_level(base, interval, k_lo + static_cast<std::int64_t>(j))
                       : fixed[j];
  }
  // The number of the first level above Z: < 0 below the lowest, count above the highest.
  std::int64_t first_above(double z) const {
    if (!by_interval) return std::upper_bound(fixed.begin(), fixed.end(), z) - fixed.begin();
    return first_level_above(base, interval, z) - k_lo;
  }
  // For messages: "a contour interval of 0.5", "3 fixed contour levels".
  std::string described() const {
    return by_interval ? "a contour interval of " + short_number(interval)
                       : count_text(fixed.size()) + " fixed contour levels";
  }
};

Levels interval_levels(ZRange z, double base, double interval) {
  Levels levels;
  levels.base = base;
  levels.interval = interval;
  if (!(z.min <= z.max)) return levels;
  // Levels closer than the doubles near them would repeat: 2^-40 of the magnitude is far below
  // any real interval and far above the spacing of doubles.
  const double magnitude = std::max({std::fabs(z.min), std::fabs(z.max), std::fabs(base)});
  if (interval < std::ldexp(magnitude, -40))
    throw Error("a contour interval of " + short_number(interval) +
                " is too small for elevations of magnitude " + short_number(magnitude));
  const double span = (z.max - z.min) / interval;
  if (span > static_cast<double>(kMaxLevels))
    throw Error("a contour interval of " + short_number(interval) + " gives more than " +
                count_text(kMaxLevels) + " levels over the TIN's z range");
  levels.k_lo = first_level_above(base, interval, z.min);
  const std::int64_t k_hi = first_level_above(base, interval, z.max) - 1;
  if (k_hi >= levels.k_lo) levels.count = static_cast<std::size_t>(k_hi - levels.k_lo + 1);
  return levels;
}

Levels fixed_levels(ZRange z, const std::vector<double>& given) {
  Levels levels;
  levels.by_interval = false;
  for (const double v : given) {
    if (!std::isfinite(v)) throw Error("the contour level " + short_number(v) + " is not finite");
    if (z.min < v && v <= z.max) levels.fixed.push_back(v);
  }
  std::sort(levels.fixed.begin(), levels.fixed.end());
  levels.fixed.erase(std::unique(levels.fixed.begin(), levels.fixed.end()), levels.fixed.end());
  levels.count = levels.fixed.size();
  return levels;
}

Levels levels_of(const mesh::Triangulation& tin, const ContourOptions& options) {
  if (!options.levels.empty()) return fixed_levels(z_range(tin), options.levels);
  const double interval = options.interval, base = options.base;
  if (!(interval > 0) || !std::isfinite(interval))
    throw Error("the contour interval must be a positive number, not " + short_number(interval));
  if (!std::isfinite(base)) throw Error("the contour base must be a finite number");
  return interval_levels(z_range(tin), base, interval);
}

// The levels [lo, hi] crossing kept triangle T (none when hi < lo).
void crossing_levels(const mesh::Triangulation& tin, const Levels& levels, TriangleId t,
                     std::int64_t& lo, std::int64_t& hi) {
  const auto c = tin.triangle(t);
  const double a = tin.z(c[0]), b = tin.z(c[1]), d = tin.z(c[2]);
  lo = levels.first_above(std::min({a, b, d}));
  hi = levels.first_above(std::max({a, b, d})) - 1;
}

// The crossed triangles of each level (CSR by level: level j's are crossed[start[j],
// start[j + 1]), in id order).
struct CrossedIndex {
  std::vector<std::size_t> start;
  std::vector<TriangleId> crossed;
};

// START of the index: the crossed triangles of each level counted and summed, so that
// start[count] is the number of segments the trace makes.
std::vector<std::size_t> level_starts(const mesh::Triangulation& tin, const Levels& levels,
                                      Progress& progress) {
  const auto slots = static_cast<TriangleId>(tin.triangle_slots());
  std::vector<std::size_t> start(levels.count + 1, 0);
  for (TriangleId t = 0; t < slots; ++t) {
    progress.heartbeat();
    if (!tin.is_kept(t)) continue;
    std::int64_t lo, hi;
    crossing_levels(tin, levels, t, lo, hi);
    for (std::int64_t j = lo; j <= hi; ++j) ++start[static_cast<std::size_t>(j) + 1];
  }
  for (std::size_t j = 0; j < levels.count; ++j) start[j + 1] += start[j];
  return start;
}

// Refuses a trace of more than MAX segments, naming the estimate and the levels.
void check_segments(std::uint64_t segments, std::uint64_t max, const Levels& levels) {
  if (segments <= max) return;
  constexpr double kFileBytesPerSegment = 40;  // a point of x, y, z in a GeoPackage, and more
  throw Error(levels.described() + " makes about " + short_number(static_cast<double>(segments)) +
              " line segments (some " +
              short_number(static_cast<double>(segments) * kFileBytesPerSegment / 1e9) +
              " GB to write), more than the " + short_number(static_cast<double>(max)) +
              " allowed (a larger interval, or fewer levels, makes fewer)");
}

CrossedIndex index_crossings(const mesh::Triangulation& tin, const Levels& levels,
                             std::uint64_t max_segments, Progress& progress) {
  CrossedIndex index;
  index.start = level_starts(tin, levels, progress);
  check_segments(index.start[levels.count], max_segments, levels);
  const auto slots = static_cast<TriangleId>(tin.triangle_slots());
  index.crossed.resize(index.start[levels.count]);
  std::vector<std::size_t> fill(index.start.begin(), index.start.end() - 1);
  for (TriangleId t = 0; t < slots; ++t) {
    progress.heartbeat();
    if (!tin.is_kept(t)) continue;
    std::int64_t lo, hi;
    crossing_levels(tin, levels, t, lo, hi);
    for (std::int64_t j = lo; j <= hi; ++j) index.crossed[fill[static_cast<std::size_t>(j)]++] = t;
  }
  return index;
}

// Appends the lines of every level, in level order, to RESULT, emptying PER_LEVEL as it goes.
void append_levels(std::vector<ContourSet>& per_level, ContourSet& result) {
  std::size_t n_lines = 0, n_points = 0;
  for (const ContourSet& s : per_level) {
    n_lines += s.lines.size();
    n_points += s.points.size();
  }
  result.lines.reserve(n_lines);
  result.points.reserve(n_points);
  for (ContourSet& s : per_level) {
    const std::size_t shift = result.points.size();
    for (ContourLine line : s.lines) {
      line.first += shift;
      result.lines.push_back(line);
    }
    result.points.insert(result.points.end(), s.points.begin(), s.points.end());
    std::vector<ContourLine>().swap(s.lines);
    std::vector<Point2>().swap(s.points);
  }
}

}  // namespace

std::uint64_t count_contour_segments(const mesh::Triangulation& tin,
                                     const ContourOptions& options) {
  const Levels levels = levels_of(tin, options);
  Progress progress(options.progress, "contours", levels.count);
  return levels.count == 0 ? 0 : level_starts(tin, levels, progress)[levels.count];
}

ContourSet trace_contours(const mesh::Triangulation& tin, const ContourOptions& options) {
  ContourSet result;
  const Levels levels = levels_of(tin, options);
  if (levels.count == 0) return result;
  const std::size_t count = levels.count;
  result.levels = count;
  Progress progress(options.progress, "contours", count);
  progress.tick(0);  // a request to stop made before this stage is heard here
  CrossedIndex index = index_crossings(tin, levels, options.max_segments, progress);

  // Levels are independent: threads take them in turn, each with its own stamps. The progress
  // callback need not be thread-safe: worker 0 alone calls it, between levels and within one.
  const std::size_t threads =
      std::clamp<std::size_t>(thread_count(options.threads), 1, std::min<std::size_t>(count, 64));
  const auto slots = static_cast<TriangleId>(tin.triangle_slots());
  std::vector<ContourSet> per_level(count);
  std::atomic<std::size_t> next_level{0}, levels_done{0};
  std::atomic<bool> stop{false};
  run_workers(threads, [&](std::size_t worker) {
    try {
      std::vector<std::uint32_t> stamp(slots, 0);
      LevelTracer tracer(tin, stamp, worker == 0 ? &progress : nullptr);
      while (!stop.load(std::memory_order_relaxed)) {
        const std::size_t j = next_level.fetch_add(1);
        if (j >= count) break;
        tracer.trace(levels.value(j), static_cast<std::uint32_t>(j + 1),
                     index.crossed.data() + index.start[j], index.start[j + 1] - index.start[j],
                     per_level[j]);
        const std::size_t done = levels_done.fetch_add(1) + 1;
        if (worker == 0) progress.tick(done);
      }
    } catch (...) {
      stop = true;
      throw;
    }
  });
  std::vector<TriangleId>().swap(index.crossed);
  append_levels(per_level, result);
  progress.finish();
  return result;
}

}  // namespace tincdt::products
