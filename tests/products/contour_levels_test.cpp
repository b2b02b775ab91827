// Contour levels beside the interval: fixed levels trace exactly the lines of the same levels by
// interval; the segment estimate is the levels crossing each triangle, counted by brute force;
// a trace past the bound is refused with the estimate before any tracing; a request to stop is
// heard before the trace starts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "products/contours.hpp"
#include "products_test_util.hpp"

namespace tincdt::products {
namespace {

using test::Kind;

// The lines of SET at LEVELS (with their points), in order.
ContourSet only_levels(const ContourSet& set, const std::set<double>& levels) {
  ContourSet out;
  for (ContourLine line : set.lines) {
    if (levels.count(line.level) == 0) continue;
    const std::size_t first = out.points.size();
    out.points.insert(out.points.end(), set.points.begin() + static_cast<long>(line.first),
                      set.points.begin() + static_cast<long>(line.first + line.count));
    line.first = first;
    out.lines.push_back(line);
  }
  return out;
}

TEST(ContourLevels, FixedLevelsTraceTheLinesOfTheSameLevelsByInterval) {
  for (const Kind kind : {Kind::random, Kind::lattice, Kind::lattice_holes}) {
    SCOPED_TRACE(test::kind_name(kind));
    const mesh::Triangulation tin = test::make_tin(kind, 3);
    const ContourSet all = trace_contours(tin, {.interval = 0.5, .base = 0.25});
    ASSERT_GT(all.levels, 4u);
    const std::set<double> chosen = {all.lines.front().level, all.lines.back().level, 2.75};
    // In any order, repeated, and with levels outside the TIN's z range.
    const ContourSet fixed = trace_contours(
        tin, {.levels = {all.lines.back().level, 2.75, -100, all.lines.front().level, 2.75, 1e9}});
    EXPECT_EQ(fixed.levels, 3u);
    const ContourSet same = only_levels(all, chosen);
    EXPECT_EQ(fixed.lines, same.lines);
    EXPECT_EQ(fixed.points, same.points);
  }
}

// The levels L with z_min < L <= z_max of each kept triangle, by brute force over LEVELS.
std::uint64_t crossings(const mesh::Triangulation& tin, const std::vector<double>& levels) {
  std::uint64_t n = 0;
  tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& c) {
    const double lo = std::min({tin.z(c[0]), tin.z(c[1]), tin.z(c[2])});
    const double hi = std::max({tin.z(c[0]), tin.z(c[1]), tin.z(c[2])});
    for (const double level : levels) n += lo < level && level <= hi ? 1 : 0;
  });
  return n;
}

TEST(ContourLevels, SegmentEstimateIsTheLevelsCrossingEachTriangle) {
  for (const Kind kind : {Kind::random, Kind::lattice, Kind::lattice_holes}) {
    SCOPED_TRACE(test::kind_name(kind));
    const mesh::Triangulation tin = test::make_tin(kind, 5);
    std::vector<double> levels;
    for (int k = -10; k <= 150; ++k) levels.push_back(contour_level(0.1, 0.1, k));
    const std::uint64_t expected = crossings(tin, levels);
    EXPECT_GT(expected, 100u);
    EXPECT_EQ(count_contour_segments(tin, {.interval = 0.1, .base = 0.1}), expected);
    EXPECT_EQ(count_contour_segments(tin, {.levels = levels}), expected);
  }
}

TEST(ContourLevels, RefusedPastTheBoundWithTheEstimate) {
  const mesh::Triangulation tin = test::make_tin(Kind::random, 7);
  const std::uint64_t segments = count_contour_segments(tin, {.interval = 0.001});
  ASSERT_GT(segments, 1000u);
  EXPECT_NO_THROW(trace_contours(tin, {.interval = 0.001, .max_segments = segments}));
  try {
    trace_contours(tin, {.interval = 0.001, .max_segments = segments - 1});
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    const std::string text = e.what();
    EXPECT_NE(text.find("a contour interval of 0.001 makes about"), std::string::npos) << text;
    EXPECT_NE(text.find("segments"), std::string::npos) << text;
    EXPECT_LT(text.size(), 200u) << text;
  }
  EXPECT_THROW(trace_contours(tin, {.levels = {1, 2, 3}, .max_segments = 1}), Error);
  EXPECT_GE(kMaxContourSegments, 10'000'000u);  // the documented bound is a real job's room
}

TEST(ContourLevels, NonFiniteLevelsAreRefused) {
  const mesh::Triangulation tin = test::make_tin(Kind::random, 1);
  EXPECT_THROW(trace_contours(tin, {.levels = {1, NAN}}), Error);
  EXPECT_THROW(trace_contours(tin, {.levels = {INFINITY}}), Error);
}

TEST(ContourLevels, StopRequestHeardBeforeTracing) {
  const mesh::Triangulation tin = test::make_tin(Kind::random, 1);
  int calls = 0;
  const ProgressFn stop = [&calls](std::string_view stage, double) {
    EXPECT_EQ(stage, "contours");
    ++calls;
    return false;
  };
  EXPECT_THROW(trace_contours(tin, {.interval = 0.5, .progress = &stop}), Cancelled);
  EXPECT_EQ(calls, 1);
}

}  // namespace
}  // namespace tincdt::products
