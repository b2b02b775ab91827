// Progress: reports at most about 200 times over a stage, its heartbeat lets a stop request
// through while one item takes long, and a callback that says stop throws Cancelled.
#include "core/progress.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace tincdt {
namespace {

TEST(Progress, TicksReportAboutTwoHundredTimesInOrder) {
  std::vector<double> seen;
  const ProgressFn fn = [&](std::string_view stage, double fraction) {
    EXPECT_EQ(stage, "delaunay");
    seen.push_back(fraction);
    return true;
  };
  Progress p(&fn, "delaunay", 1'000'000);
  for (std::uint64_t i = 0; i < 1'000'000; ++i) p.tick(i);
  p.finish();
  EXPECT_GE(seen.size(), 190u);
  EXPECT_LE(seen.size(), 202u);
  for (std::size_t i = 1; i < seen.size(); ++i) EXPECT_LT(seen[i - 1], seen[i]);
  EXPECT_EQ(seen.back(), 1.0);
}

TEST(Progress, HeartbeatRepeatsTheLastFractionEvery65536Calls) {
  std::vector<double> seen;
  const ProgressFn fn = [&](std::string_view, double fraction) {
    seen.push_back(fraction);
    return true;
  };
  Progress p(&fn, "constraints", 4);
  p.tick(2);  // reports 0.5
  ASSERT_EQ(seen.size(), 1u);
  for (int i = 0; i < 3 * 65536; ++i) p.heartbeat();
  EXPECT_EQ(seen, (std::vector<double>{0.5, 0.5, 0.5, 0.5}));
}

TEST(Progress, AStopDuringOneLongItemThrowsCancelled) {
  bool stop = false;
  const ProgressFn fn = [&](std::string_view, double) { return !stop; };
  Progress p(&fn, "constraints", 10);
  p.tick(0);
  stop = true;  // a signal arrives while one segment's crossings take long
  EXPECT_THROW(for (int i = 0; i < 65536; ++i) p.heartbeat(), Cancelled);
}

}  // namespace
}  // namespace tincdt
