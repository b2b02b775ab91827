// Inputs this large are split into kRegionsPerSide^2 regions, the cells of a grid over the
// points' bounding box (independent of the thread count: the regions decide the result). Each
// region's points are simplified on their own, the regions on all threads at once, with the
// kept points and segments that lie in them. All a region inserted, except within kSeamShare
// of a cell's side of an edge it shares with another, seeds the run on all points (with all
// kept points and segments), which then has little left to do but the seams. The regions are
// only a start: the last run alone decides that every point is within the tolerance. Smaller
// regions are faster (their points stay in cache) but their seams cost vertices and time.
// Not with a vertex budget (see seeds.cpp).
#include "simplify/regions.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <functional>
#include <optional>
#include <string_view>
#include <thread>
#include <utility>

#include "core/error.hpp"
#include "core/parallel.hpp"
#include "core/thread_pool.hpp"

namespace tincdt::simplify::detail {
namespace {

constexpr std::size_t kRegionMinPoints = std::size_t{1} << 18;
constexpr int kRegionsPerSide = 2;
constexpr std::size_t kRegions = kRegionsPerSide * kRegionsPerSide;
constexpr double kSeamShare = 1.0 / 128;

using RegionRun = std::function<Unfinished(const ProgressFn*)>;

// The regions' runs on `threads` threads, the calling one included: only the calling thread
// calls the progress callback; its request to stop (or its exception) reaches the others through
// stop_. An error in a region's run does not stop the others, so that which one is reported
// (the first region's) does not depend on timing.
class RegionRuns {
 public:
  RegionRuns(std::vector<RegionRun> runs, std::vector<double> weights, const ProgressFn* progress)
      : runs_(std::move(runs)),
        weights_(std::move(weights)),
        progress_(progress && *progress ? progress : nullptr),
        done_(runs_.size()),
        done_runs_(runs_.size()),
        errors_(runs_.size()) {}

  std::vector<Unfinished> run(std::size_t threads) {
    caller_ = std::this_thread::get_id();
    ThreadPool pool(std::min(threads, runs_.size()));
    auto one = [this](std::size_t r, std::size_t) { run_one(r); };
    if (progress_) {  // the caller reports while the last regions run on other threads
      auto waiting = [this] { report(); };
      pool.run(one, runs_.size(), waiting, std::chrono::milliseconds(20));
    } else {
      pool.run(one, runs_.size());
    }
    if (callback_error_) std::rethrow_exception(callback_error_);
    for (const std::exception_ptr& e : errors_)
      if (e) std::rethrow_exception(e);
    if (stop_) throw Cancelled();
    return std::move(done_runs_);
  }

 private:
  void run_one(std::size_t r) {
    const bool caller = std::this_thread::get_id() == caller_;
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
  }

  // The regions' fractions, weighted, to the caller's callback; false when it asks to stop or
  // throws (rethrown once every region has ended). Calling thread only.
  bool report() {
    assert(std::this_thread::get_id() == caller_);
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

  std::vector<RegionRun> runs_;
  std::vector<double> weights_;  // each region's share of the points
  const ProgressFn* progress_;
  std::vector<std::atomic<double>> done_;  // each region's fraction
  std::vector<Unfinished> done_runs_;      // a region's run, or none
  std::vector<std::exception_ptr> errors_;
  std::exception_ptr callback_error_;  // only the calling thread sets it
  std::atomic<bool> stop_{false};
  std::thread::id caller_;
};

// The grid of regions over the box of the kept points: where a point is in cell units, cell
// (i, j) holding i <= x < i + 1, j <= y < j + 1 (the last ones up to kRegionsPerSide).
struct RegionGrid {
  static constexpr int side = kRegionsPerSide;
  const Point2* xy;
  Point2 lo, cell_size;

  Point2 place(std::uint32_t i) const {
    return Point2{(xy[i].x - lo.x) / cell_size.x, (xy[i].y - lo.y) / cell_size.y};
  }
  static int cell(double p) { return std::min(side - 1, static_cast<int>(p)); }
  std::size_t region(std::uint32_t i) const {
    const Point2 p = place(i);
    return static_cast<std::size_t>(cell(p.x) + side * cell(p.y));
  }
  // Whether point i, in region r, is near an edge r shares with another region, where r's run
  // inserted points for its own hull's sake.
  bool near_seam(std::uint32_t i, std::size_t r) const {
    const Point2 p = place(i);
    const auto x = static_cast<int>(r % side), y = static_cast<int>(r / side);
    return (x > 0 && p.x < x + kSeamShare) || (x + 1 < side && p.x > x + 1 - kSeamShare) ||
           (y > 0 && p.y < y + kSeamShare) || (y + 1 < side && p.y > y + 1 - kSeamShare);
  }
};

// The grid over the box of the kept points, or none when the box is flat.
std::optional<RegionGrid> region_grid(const PointSet& set, std::span<const std::uint32_t> kept) {
  Point2 lo{INFINITY, INFINITY}, hi{-INFINITY, -INFINITY};
  for (std::uint32_t i : kept) {
    lo = {std::min(lo.x, set.xy[i].x), std::min(lo.y, set.xy[i].y)};
    hi = {std::max(hi.x, set.xy[i].x), std::max(hi.y, set.xy[i].y)};
  }
  if (!(hi.x > lo.x && hi.y > lo.y)) return std::nullopt;
  constexpr int side = RegionGrid::side;
  return RegionGrid{set.xy.data(), lo, {(hi.x - lo.x) / side, (hi.y - lo.y) / side}};
}

// The points 0 .. n - 1 sorted by region into `points` (stable: each region's ascending);
// returns each region's share of it. A counting sort in chunks on all threads (a pass over the
// points costs what it reads: their regions are read once, and kept in a byte each).
std::vector<std::span<const std::uint32_t>> sort_by_region(const RegionGrid& grid, std::size_t n,
                                                           std::uint32_t* points,
                                                           unsigned threads) {
  ThreadPool pool(thread_count(threads));
  constexpr std::size_t regions = kRegions;
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
      const std::size_t r = grid.region(static_cast<std::uint32_t>(i));
      region_of[i] = static_cast<std::uint8_t>(r);
      ++counts[r];
    }
    std::copy(counts.begin(), counts.end(), at.begin() + static_cast<std::ptrdiff_t>(c * regions));
  };
  pool.run(count, chunks);
  std::vector<std::span<const std::uint32_t>> members(regions);
  std::size_t total = 0;
  for (std::size_t r = 0; r < regions; ++r) {
    const std::size_t first = total;
    for (std::size_t c = 0; c < chunks; ++c) total += std::exchange(at[c * regions + r], total);
    members[r] = {points + first, total - first};
  }
  assert(total == n);
  auto place_chunk = [&](std::size_t c, std::size_t) {
    std::array<std::size_t, regions> cursor;
    std::copy_n(at.begin() + static_cast<std::ptrdiff_t>(c * regions), regions, cursor.begin());
    for (auto [i, end] = chunk_points(c); i < end; ++i)
      points[cursor[region_of[i]]++] = static_cast<std::uint32_t>(i);
  };
  pool.run(place_chunk, chunks);
  return members;
}

// Each region's kept points and segments. A segment across regions is in neither (its ends are
// in two), but its ends are kept where they are: they are vertices of the last run, whatever the
// regions make of their surface.
struct RegionFeatures {
  std::vector<std::vector<std::uint32_t>> kept;
  std::vector<std::vector<constraints::Segment>> segments;

  RegionFeatures(const RegionGrid& grid, std::span<const std::uint32_t> all_kept,
                 std::span<const constraints::Segment> all_segments)
      : kept(kRegions), segments(kRegions) {
    for (std::uint32_t i : all_kept) kept[grid.region(i)].push_back(i);
    for (const constraints::Segment& s : all_segments) {
      if (grid.region(s.a) == grid.region(s.b)) {
        segments[grid.region(s.a)].push_back(s);
      } else {
        kept[grid.region(s.a)].push_back(s.a);
        kept[grid.region(s.b)].push_back(s.b);
      }
    }
  }
};

}  // namespace

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
  const std::optional<RegionGrid> grid = region_grid(set, kept);
  if (!grid) return {};
  Regions out;
  out.arena = std::make_unique_for_overwrite<std::uint32_t[]>(shared_arena);
  out.arena_size = shared_arena;
  out.members = sort_by_region(*grid, n, out.arena.get() + (shared_arena - n), options.threads);
  const RegionFeatures features(*grid, kept, segments);

  SimplifyOptions region_options = options;
  region_options.threads = 1;
  std::vector<RegionRun> runs;
  std::vector<double> weights;
  std::vector<std::vector<std::uint32_t>> seeds(kRegions);  // each region's, ascending
  for (std::size_t r = 0, arena_at = 0; r < kRegions; ++r) {
    const std::span<const std::uint32_t> members = out.members[r];
    const std::span<std::uint32_t> arena{out.arena.get() + arena_at, arena_slots(members.size())};
    arena_at += arena.size();
    assert(arena_at <= shared_arena - n);  // the arenas end where the point lists begin
    weights.push_back(static_cast<double>(members.size()) / static_cast<double>(n));
    runs.emplace_back([&, r, members, arena](const ProgressFn* fn) {
      if (members.empty()) return Unfinished{};  // (an empty PointSet would be all points)
      std::vector<std::uint32_t> own_kept = hull_corners(set.xy, members);
      if (own_kept.size() < 3) return Unfinished{};  // collinear
      own_kept.insert(own_kept.end(), features.kept[r].begin(), features.kept[r].end());
      Unfinished u = run_greedy({set.xy, set.z, members}, own_kept, features.segments[r],
                                region_options, fn, 0, arena);
      // Sorted here, on the region's thread, for the last run, which needs them so.
      for (std::uint32_t i : u.order)
        if (!grid->near_seam(i, r)) seeds[r].push_back(i);
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

}  // namespace tincdt::simplify::detail
