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

// A well-spread hash of a point's x, y, equal for -0.0 and 0.0: BRIO rounds and samples drawn
// from it are a rule of the points alone, whatever their order in the input.
std::uint64_t point_hash(double x, double y);

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

// Sorts items (key << 32 | point index) by key, then within equal keys by the points' x, y, z
// (then index), so that points with equal x, y are adjacent and in increasing z. The order is a
// function of the points alone, never of their order in the input. `buffer` is scratch space for
// n items.
void sort_by_key_then_xyz(const std::vector<Point3>& points, std::uint64_t* items,
                          std::uint64_t* buffer, std::size_t n);

// Point indices in insertion order (the sequential path); keys computed on THREADS (0 = all).
std::vector<std::uint32_t> insertion_order(const std::vector<Point3>& points, const BBox& box,
                                           unsigned threads = 0);

// The z of a vertex that several points with equal x, y are merged into. They come in increasing
// z (sort_by_key_then_xyz), so the mean is summed in one canonical order: any order of the same
// points in the input gives the same bits. `first` keeps the z of the first point in input order.
struct MergedZ {
  double z;
  std::uint32_t count;        // points so far
  std::uint32_t first_point;  // input index of the point whose z `first` keeps

  static MergedZ start(double z, std::uint32_t point) { return {z, 1, point}; }
  void add(double other, std::uint32_t point, DuplicatePolicy policy) {
    ++count;
    switch (policy) {
      case DuplicatePolicy::first:
        if (point < first_point) {
          z = other;
          first_point = point;
        }
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
};

// Notes in `list` (DelaunayOptions::keep_duplicates) that `vertex` takes one more point with equal
// x, y and height `other`; `count` is its points so far, this one included. Call it before
// MergedZ::add(): at count 2, `z` is then still the first point's.
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
