// The two-thread path of the Delaunay stage (see parallel_delaunay.hpp): split the points at a
// pivot, sort and gather each half's distinct points, triangulate the halves, merge them.
#include "delaunay/parallel_delaunay.hpp"

#include <array>
#include <atomic>
#include <bit>
#include <cassert>
#include <cstdint>
#include <exception>
#include <optional>

#include "core/memory.hpp"
#include "core/parallel.hpp"
#include "delaunay/half_triangulation.hpp"
#include "delaunay/spatial_order.hpp"
#include "delaunay/split.hpp"

namespace tincdt::delaunay {
namespace {
using namespace mesh;  // the half-edge vocabulary: kInfinite, kNoId, ...
using detail::internal_error;
using detail::LeftOfPivot;

// Sorts one half's items into insertion order.
void sort_half(const std::vector<Point3>& input, std::uint64_t* items, std::size_t m) {
  ScratchArray<std::uint64_t> buffer(m);
  sort_by_key_then_xyz(input, items, buffer.data(), m);
}

// Passes one half's distinct points, in order and with equal x, y merged, to put(k, point);
// vertex_of_point (if not null) gets each point's index k within the half, duplicates (if not
// null) the merged groups with vertex ids within the half. Now and then calls consumed(k): the
// items before k are read.
struct HalfPoints {
  std::size_t count = 0;
  std::uint64_t duplicates = 0;
};

template <class Put, class Consumed>
HalfPoints gather_half(const std::vector<Point3>& input, const std::uint64_t* items, std::size_t m,
                       VertexId* vertex_of_point,
                       std::vector<DelaunayResult::Duplicate>* duplicates, DuplicatePolicy policy,
                       Put&& put, Consumed&& consumed) {
  HalfPoints half;
  Point3 current{};
  MergedZ merged{};
  for (std::size_t k = 0; k < m; ++k) {
    if ((k & 0x1ffff) == 0 && k > 0) consumed(k);  // items before k are read
    const auto i = static_cast<std::uint32_t>(items[k]);
    const Point3& p = input[i];
    if (half.count > 0 && current.x == p.x && current.y == p.y) {
      if (duplicates)
        record_duplicate(*duplicates, static_cast<VertexId>(half.count - 1), merged.z, p.z,
                         merged.count + 1);
      merged.add(p.z, i, policy);
      current.z = merged.z;
      ++half.duplicates;
    } else {
      if (half.count > 0) put(half.count - 1, current);
      current = p;
      merged = MergedZ::start(p.z, i);
      ++half.count;
    }
    if (vertex_of_point) vertex_of_point[i] = static_cast<VertexId>(half.count - 1);
  }
  if (half.count > 0) put(half.count - 1, current);
  return half;
}

// Until the triangles take them, the slots can hold sorted points: point k in corners
// [6k, 6k + 6), the last one (there are 6n - 6 corners) aside.
class PointStash {
 public:
  PointStash(Triangulation& tin, std::size_t n) : tin_(tin), n_(n) {}
  void put(std::size_t k, const Point3& p) {
    assert(k < n_);
    if (k + 1 == n_) {
      last_ = p;
      return;
    }
    const auto words = std::bit_cast<std::array<std::uint32_t, 6>>(p);
    for (std::size_t w = 0; w < 6; ++w) tin_.set_corner(static_cast<EdgeId>(6 * k + w), words[w]);
  }
  Point3 get(std::size_t k) const {
    assert(k < n_);
    if (k + 1 == n_) return last_;
    std::array<std::uint32_t, 6> words;
    for (std::size_t w = 0; w < 6; ++w) words[w] = tin_.origin(static_cast<EdgeId>(6 * k + w));
    return std::bit_cast<Point3>(words);
  }

 private:
  Triangulation& tin_;
  std::size_t n_;
  Point3 last_{};
};

// Appends the triangle slots of a triangulation of VERTICES distinct points: 2 VERTICES - 2.
void make_slots(Triangulation& tin, std::size_t vertices) {
  tin.reserve_triangles(2 * vertices - 2);
  tin.add_empty_triangles(2 * vertices - 2);
}

// Fills ITEMS with the (key, index) items of the points, left ones first, each side in input
// order, then sorts each side into insertion order. Returns the number of left items.
std::size_t sort_items(const std::vector<Point3>& input, const BBox& box, LeftOfPivot is_left,
                       bool concurrent, ScratchArray<std::uint64_t>& items) {
  const std::size_t n = input.size();
  const std::size_t mid = n / 2;
  std::size_t left_in_chunk[2] = {0, 0};
  run_two(
      concurrent,
      [&] {
        for (std::size_t i = 0; i < mid; ++i) left_in_chunk[0] += is_left(input[i]);
      },
      [&] {
        for (std::size_t i = mid; i < n; ++i) left_in_chunk[1] += is_left(input[i]);
      });
  const std::size_t left_items = left_in_chunk[0] + left_in_chunk[1];
  const OrderKey key(box);
  const auto fill = [&](std::size_t begin, std::size_t end, std::size_t at_left,
                        std::size_t at_right) {
    for (std::size_t i = begin; i < end; ++i) {
      const std::uint64_t item = (std::uint64_t{key(input[i])} << 32) | i;
      if (is_left(input[i])) {
        items[at_left++] = item;
      } else {
        items[at_right++] = item;
      }
    }
  };
  assert(left_items <= n);
  run_two(
      concurrent, [&] { fill(0, mid, 0, left_items); },
      [&] { fill(mid, n, left_in_chunk[0], left_items + (mid - left_in_chunk[0])); });
  run_two(
      concurrent, [&] { sort_half(input, items.data(), left_items); },
      [&] { sort_half(input, items.data() + left_items, n - left_items); });
  return left_items;
}

// Gathers each side's distinct points, in order: the left ones straight into the vertices while
// SLOTS are still being made, the right ones, once the slots exist, into STASH from LEFT_ITEMS on.
// Items are given back as they are read. Fills the result's point map and merged duplicates
// (vertex ids of the right half shifted past the left's). Returns the two halves' vertex counts.
std::array<VertexId, 2> gather_halves(const std::vector<Point3>& input,
                                      ScratchArray<std::uint64_t>& items, std::size_t left_items,
                                      const DelaunayOptions& options, bool concurrent,
                                      BackgroundJob& slots, PointStash& stash,
                                      DelaunayResult& result) {
  const std::size_t n = input.size();
  Triangulation& tin = result.tin;
  if (options.keep_point_map) result.vertex_of_point.assign(n, kNoId);
  VertexId* point_map = options.keep_point_map ? result.vertex_of_point.data() : nullptr;
  HalfPoints half[2];
  // Merged groups: the left half's straight into the result, the right half's (vertex ids within
  // the half) into a list of their own, appended once both are done.
  std::vector<DelaunayResult::Duplicate> right_duplicates;
  std::vector<DelaunayResult::Duplicate>* duplicates[2] = {nullptr, nullptr};
  if (options.keep_duplicates) {
    duplicates[0] = &result.duplicates;
    duplicates[1] = &right_duplicates;
  }
  run_two(
      concurrent,
      [&] {
        half[0] = gather_half(
            input, items.data(), left_items, point_map, duplicates[0], options.on_duplicate,
            [&](std::size_t, const Point3& p) {
              tin.add_vertex({p.x, p.y}, p.z);
            },
            [&](std::size_t k) { items.release(0, k); });
      },
      [&] {
        slots.wait();
        half[1] = gather_half(
            input, items.data() + left_items, n - left_items, point_map, duplicates[1],
            options.on_duplicate,
            [&](std::size_t k, const Point3& p) { stash.put(left_items + k, p); },
            [&](std::size_t k) {
              if (!point_map) items.release(left_items, left_items + k);  // else read below
            });
      });
  const auto nl = static_cast<VertexId>(half[0].count);
  assert(tin.vertex_count() == nl);
  if (point_map)
    for (std::size_t k = left_items; k < n; ++k)
      point_map[static_cast<std::uint32_t>(items[k])] += nl;
  result.duplicates_merged = half[0].duplicates + half[1].duplicates;
  if (options.keep_duplicates) {
    result.duplicates.reserve(result.duplicates.size() + right_duplicates.size());
    for (DelaunayResult::Duplicate d : right_duplicates) {
      d.vertex += nl;
      result.duplicates.push_back(d);
    }
  }
  return {nl, static_cast<VertexId>(half[1].count)};
}

// Adds the NR right vertices from STASH after the NL left ones. The slots were made for N
// distinct points: if some coincided, those the triangulation will not use are dropped (their
// memory stays with the triangulation, which the constraint stage may fill).
void add_right_vertices(Triangulation& tin, const PointStash& stash, std::size_t left_items,
                        VertexId nl, VertexId nr) {
  for (std::size_t k = 0; k < nr; ++k) {
    const Point3 p = stash.get(left_items + k);
    tin.add_vertex({p.x, p.y}, p.z);
  }
  tin.truncate_triangles(2 * std::size_t{nl + nr} - 2);
}

// Triangulates vertices [0, NL) and [NL, NV) of TIN at once, in slots [0, 2nl - 2) and
// [2nl - 2, 2nv - 4), and merges them with the last two slots as spares. Adds the flips to the
// result's.
void triangulate_and_merge(Triangulation& tin, VertexId nl, VertexId nv, bool concurrent,
                           const ProgressFn* progress, DelaunayResult& result) {
  assert(tin.vertex_count() == nv && tin.triangle_slots() == 2 * std::size_t{nv} - 2);
  Progress report(progress, "delaunay", nv);
  std::atomic<bool> stop{false};  // set when either half fails, so that the other gives up
  std::uint64_t flips[2] = {0, 0};
  EdgeId ghost[2] = {kNoId, kNoId};
  const TriangleId right_slot = 2 * nl - 2;
  const auto guarded = [&](auto&& work) {
    try {
      work();
    } catch (...) {
      stop.store(true);
      throw;
    }
  };
  run_two(
      concurrent,
      [&] {
        guarded([&] {
          ghost[0] = detail::triangulate_half(tin, 0, nl, 0, flips[0], [&](VertexId done) {
            report.tick(std::uint64_t{done} * nv / nl);  // both halves go at about one pace
            return !stop.load(std::memory_order_relaxed);
          });
        });
      },
      [&] {
        guarded([&] {
          ghost[1] = detail::triangulate_half(tin, nl, nv, right_slot, flips[1], [&](VertexId) {
            return !stop.load(std::memory_order_relaxed);
          });
        });
      });
  if (ghost[0] == kNoId || ghost[1] == kNoId) throw internal_error("a half stopped early");
  const auto spare = 2 * nv - 4;
  const std::uint64_t merge_flips = merge_triangulations(tin, ghost[0], ghost[1], spare, spare + 1);
  result.flips = flips[0] + flips[1] + merge_flips;
  tin.recount();
  report.finish();
}

}  // namespace

bool triangulate_in_two(std::vector<Point3>& input, const BBox& box, const DelaunayOptions& options,
                        const ProgressFn* progress, DelaunayResult& result) {
  const std::size_t n = input.size();
  if (n < 4) return false;
  // One thread or two, the work is the same, and so is every bit of the result.
  const bool concurrent = thread_count(options.threads) != 1;
  const std::optional<LeftOfPivot> is_left = detail::choose_pivot(input, concurrent);
  if (!is_left || !detail::can_split(input, *is_left)) return false;

  // Meanwhile another thread makes the triangle slots, betting that no two points coincide (then
  // there are 2n - 2); this is the one phase where they fit in the memory budget beside the input.
  // It is also the longest part before the insertion can start (the first touch of 48 bytes per
  // point in one thread, as Triangulation grows only by add_triangle), so as much work as possible
  // runs beside it. It touches only the triangle arrays of tin; until it is waited for, the other
  // threads touch only the vertex arrays (add_vertex), never the same member.
  Triangulation& tin = result.tin;
  tin.reserve_vertices(n);
  BackgroundJob slots(concurrent, [&tin, n] { make_slots(tin, n); });

  ScratchArray<std::uint64_t> items(n);
  const std::size_t left_items = sort_items(input, box, *is_left, concurrent, items);
  PointStash stash(tin, n);
  const auto [nl, nr] =
      gather_halves(input, items, left_items, options, concurrent, slots, stash, result);
  items.release();
  std::vector<Point3>().swap(input);
  add_right_vertices(tin, stash, left_items, nl, nr);
  triangulate_and_merge(tin, nl, nl + nr, concurrent, progress, result);
  return true;
}

}  // namespace tincdt::delaunay
