#include "delaunay/spatial_order.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <random>

namespace tincdt::delaunay {
namespace {

TEST(SpatialOrder, HilbertIndexVisitsEveryCellOnceWithUnitSteps) {
  const int bits = 5;
  const std::uint32_t side = 1u << bits;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> cell_at(side * side, {side, side});
  for (std::uint32_t y = 0; y < side; ++y)
    for (std::uint32_t x = 0; x < side; ++x) {
      const std::uint32_t d = hilbert_index(x, y, bits);
      ASSERT_LT(d, side * side);
      ASSERT_EQ(cell_at[d].first, side) << "index " << d << " used twice";
      cell_at[d] = {x, y};
    }
  for (std::size_t d = 1; d < cell_at.size(); ++d) {
    const int dx =
        std::abs(static_cast<int>(cell_at[d].first) - static_cast<int>(cell_at[d - 1].first));
    const int dy =
        std::abs(static_cast<int>(cell_at[d].second) - static_cast<int>(cell_at[d - 1].second));
    EXPECT_EQ(dx + dy, 1) << "curve jumps at " << d;
  }
}

TEST(SpatialOrder, TableHilbertKeyIsTheReferenceCurve) {
  std::mt19937_64 rng(9);
  const std::uint32_t side = 1u << OrderKey::kHilbertBits;
  for (int i = 0; i < 100000; ++i) {
    const auto x = static_cast<std::uint32_t>(rng() % side),
               y = static_cast<std::uint32_t>(rng() % side);
    ASSERT_EQ(OrderKey::hilbert_key(x, y), hilbert_index(x, y, OrderKey::kHilbertBits))
        << x << ", " << y;
  }
}

TEST(SpatialOrder, IsAPermutationWithEqualPointsAdjacent) {
  std::mt19937_64 rng(5);
  std::vector<Point3> pts;
  BBox box;
  for (int i = 0; i < 20000; ++i) {
    const Point3 p{static_cast<double>(rng() % 100), static_cast<double>(rng() % 100), 0};
    pts.push_back(p);
    box.add(p.x, p.y);
  }
  const auto order = insertion_order(pts, box);
  ASSERT_EQ(order.size(), pts.size());
  std::vector<bool> seen(pts.size());
  for (auto i : order) {
    ASSERT_FALSE(seen[i]);
    seen[i] = true;
  }
  // Every group of equal points forms one contiguous run.
  std::vector<std::pair<double, double>> runs;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const auto key = std::make_pair(pts[order[k]].x, pts[order[k]].y);
    if (k == 0 || key != std::make_pair(pts[order[k - 1]].x, pts[order[k - 1]].y))
      runs.push_back(key);
  }
  std::sort(runs.begin(), runs.end());
  EXPECT_EQ(std::adjacent_find(runs.begin(), runs.end()), runs.end());
}

}  // namespace
}  // namespace tincdt::delaunay
