// The order in which points enter the Delaunay stage, and the primitives both the sequential and
// the two-thread paths build it from.
#pragma once

#include <cstdint>
#include <vector>

#include "core/types.hpp"
#include "delaunay/delaunay.hpp"

namespace tincdt::delaunay {

// Index along the Hilbert curve of cell (x, y) of a 2^bits x 2^bits grid: the reference
// definition, one level per step (OrderKey uses a two-levels-per-step table of the same curve).
std::uint32_t hilbert_index(std::uint32_t x, std::uint32_t y, int bits);

// A point's insertion key: biased randomized insertion order (BRIO) rounds, a small random sample
// first and each round about 8 times the previous, above the index of its cell along a Hilbert
// curve over `box`, so that each point lands near the one before it. The round is drawn from a
// hash of the coordinates, so points with equal x, y share round and cell.
class OrderKey {
 public:
  static constexpr int kHilbertBits = 14;  // per axis: 2^28 cells, far more than points per round
  explicit OrderKey(const BBox& box);
  std::uint32_t operator()(const Point3& p) const;
  // The Hilbert part alone, for cells of the 2^14 grid (tests compare it with hilbert_index).
  static std::uint32_t hilbert_key(std::uint32_t x, std::uint32_t y);

 private:
  BBox box_;
  double scale_ = 0;
};

// Sorts items (key << 32 | point index) by key, then within equal keys by the points' x, y, so
// that equal points are adjacent. `buffer` is scratch space for n items.
void sort_by_key_then_xy(const std::vector<Point3>& points, std::uint64_t* items,
                         std::uint64_t* buffer, std::size_t n);

// Point indices in insertion order (the sequential path); keys computed on THREADS (0 = all).
std::vector<std::uint32_t> insertion_order(const std::vector<Point3>& points, const BBox& box,
                                           unsigned threads = 0);

// z of a vertex that takes one more point with equal x, y; `count` is the points so far,
// this one included.
inline void merge_duplicate_z(double& z, double other, std::uint32_t count,
                              DuplicatePolicy policy) {
  switch (policy) {
    case DuplicatePolicy::first:
      break;
    case DuplicatePolicy::min:
      z = other < z ? other : z;
      break;
    case DuplicatePolicy::max:
      z = other > z ? other : z;
      break;
    case DuplicatePolicy::mean:
      z += (other - z) / count;  // running mean: no sum to overflow
      break;
  }
}

// Notes in `list` (DelaunayOptions::keep_duplicates) that `vertex` takes one more point with equal
// x, y and height `other`; `count` is its points so far, this one included. Call it before
// merge_duplicate_z(z, other, count, ...): at count 2, `z` is then still the first point's.
inline void record_duplicate(std::vector<DelaunayResult::Duplicate>& list, VertexId vertex,
                             double z, double other, std::uint32_t count) {
  if (count == 2) {
    list.push_back({vertex, 2, other < z ? other : z, other > z ? other : z});
    return;
  }
  DelaunayResult::Duplicate& d = list.back();
  d.points = count;
  if (other < d.z_min) d.z_min = other;
  if (other > d.z_max) d.z_max = other;
}

}  // namespace tincdt::delaunay
