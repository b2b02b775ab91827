// A crossing vertex is made from the two whole segments: the same doubles (x, y and z) whatever
// the order of insertion and whatever other segments the job holds, so that tiled jobs, each
// holding some of the segments, make the same vertex where the same two segments cross.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include "constraints/constraints.hpp"
#include "delaunay/delaunay.hpp"

namespace tincdt::constraints {
namespace {

using Ends = std::pair<Point3, Point3>;
using Pair = std::pair<std::uint32_t, std::uint32_t>;  // two segments' ids, smaller first

// The crossing vertices of SEGMENTS (ids = their index) inserted in the order ORDER, by pair.
std::map<Pair, std::array<double, 3>> crossings(const std::vector<Ends>& segments,
                                                const std::vector<std::uint32_t>& order) {
  std::vector<Point3> points;
  for (const std::uint32_t i : order) {
    points.push_back(segments[i].first);
    points.push_back(segments[i].second);
  }
  delaunay::DelaunayResult dt = delaunay::triangulate(std::move(points), {.keep_point_map = true});
  std::vector<Segment> given;
  for (std::uint32_t k = 0; k < order.size(); ++k)
    given.push_back({dt.vertex_of_point[2 * k], dt.vertex_of_point[2 * k + 1], order[k]});
  const ConstraintResult r = insert_constraints(dt.tin, given);
  EXPECT_EQ(dt.tin.validate(), "");
  std::map<Pair, std::array<double, 3>> by_pair;
  for (const Crossing& x : r.crossings) {
    const Point2 p = dt.tin.point(x.vertex);
    by_pair[std::minmax(x.source_a, x.source_b)] = {p.x, p.y, dt.tin.z(x.vertex)};
  }
  return by_pair;
}

// 40 random segments over a kilometre square, and their ids in order.
std::vector<Ends> random_segments(std::uint64_t seed, std::vector<std::uint32_t>& all) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> at(0, 1000), height(100, 200);
  std::vector<Ends> segments;
  for (int i = 0; i < 40; ++i)
    segments.push_back({{500000 + at(rng), 4000000 + at(rng), height(rng)},
                        {500000 + at(rng), 4000000 + at(rng), height(rng)}});
  all.resize(segments.size());
  for (std::uint32_t i = 0; i < all.size(); ++i) all[i] = i;
  return segments;
}

TEST(CrossingVertices, DoNotDependOnTheOrderNorOnTheOtherSegments) {
  std::vector<std::uint32_t> all;
  const std::vector<Ends> segments = random_segments(31, all);
  std::mt19937_64 rng(31);
  const auto whole = crossings(segments, all);
  ASSERT_GT(whole.size(), 100u);
  for (int trial = 0; trial < 6; ++trial) {
    SCOPED_TRACE(trial);
    std::vector<std::uint32_t> some = all;
    std::shuffle(some.begin(), some.end(), rng);
    if (trial % 2 == 1) some.resize(some.size() / 2);  // half the segments, in another order
    const auto part = crossings(segments, some);
    std::size_t same = 0;
    for (const auto& [pair, vertex] : part) {
      const auto it = whole.find(pair);
      ASSERT_NE(it, whole.end()) << pair.first << " x " << pair.second;
      EXPECT_EQ(it->second, vertex) << pair.first << " x " << pair.second;
      ++same;
    }
    EXPECT_GT(same, 10u);
  }
}

// In two calls, as the surface stage inserts its rings after the hard lines: the first call's
// pieces are given again with their whole segments, so that where a new segment crosses one the
// vertex is the one a single call makes, not one computed from a piece cut by other crossings.
TEST(CrossingVertices, OfALaterCallAreMadeFromTheWholeSegmentsOfAnEarlierOne) {
  std::vector<std::uint32_t> all;
  const std::vector<Ends> segments = random_segments(32, all);
  const auto one_call = crossings(segments, all);

  std::vector<Point3> points;
  for (const Ends& e : segments) points.insert(points.end(), {e.first, e.second});
  delaunay::DelaunayResult dt = delaunay::triangulate(std::move(points), {.keep_point_map = true});
  const auto segment = [&](std::uint32_t i) {
    return Segment{dt.vertex_of_point[2 * i], dt.vertex_of_point[2 * i + 1], i};
  };
  std::vector<Segment> first, second;
  for (std::uint32_t i = 0; i < 20; ++i) first.push_back(segment(i));
  const ConstraintResult earlier = insert_constraints(dt.tin, first);
  for (const Piece& p : earlier.pieces)
    second.push_back({p.a, p.b, p.source, p.whole_a, p.whole_b});
  for (std::uint32_t i = 20; i < segments.size(); ++i) second.push_back(segment(i));
  const ConstraintResult later = insert_constraints(dt.tin, second);
  EXPECT_EQ(dt.tin.validate(), "");
  std::size_t across = 0;
  for (const Crossing& x : later.crossings) {
    const Pair pair = std::minmax(x.source_a, x.source_b);
    if (pair.first >= 20 || pair.second < 20) continue;  // not an earlier one with a later one
    const Point2 p = dt.tin.point(x.vertex);
    const auto it = one_call.find(pair);
    ASSERT_NE(it, one_call.end()) << pair.first << " x " << pair.second;
    EXPECT_EQ(it->second, (std::array{p.x, p.y, dt.tin.z(x.vertex)}))
        << pair.first << " x " << pair.second;
    ++across;
  }
  EXPECT_GT(across, 50u);
}

}  // namespace
}  // namespace tincdt::constraints
