// Google Benchmark of the Delaunay and constraint stages on generated points (no files needed).
// Ratios against CGAL come from tests/bench/compare_cgal.sh, which runs both in one session.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "constraints/constraints.hpp"
#include "delaunay/delaunay.hpp"

namespace {

using tincdt::Point3;

std::vector<Point3> uniform_points(std::size_t n) {
  std::mt19937_64 rng(20240601);
  std::uniform_real_distribution<double> u(0, 10000);
  std::vector<Point3> p(n);
  for (auto& q : p) q = {500000 + u(rng), 4000000 + u(rng), 0};
  return p;
}

std::vector<Point3> grid_points(std::size_t n) {
  const auto side = static_cast<std::size_t>(std::sqrt(static_cast<double>(n)));
  std::vector<Point3> p;
  p.reserve(side * side);
  for (std::size_t j = 0; j < side; ++j)
    for (std::size_t i = 0; i < side; ++i)
      p.push_back({500000.0 + static_cast<double>(i), 4000000.0 + static_cast<double>(j), 0});
  return p;
}

template <std::vector<Point3> (*Make)(std::size_t)>
void BM_Delaunay(benchmark::State& state) {
  const std::vector<Point3> points = Make(static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) {
    state.PauseTiming();
    std::vector<Point3> copy = points;
    state.ResumeTiming();
    auto result = tincdt::delaunay::triangulate(std::move(copy));
    benchmark::DoNotOptimize(result.tin.triangle_count());
  }
  state.counters["ns_per_point"] = benchmark::Counter(
      static_cast<double>(points.size()),
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_Delaunay<uniform_points>)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Delaunay<grid_points>)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond);

// Concentric rings of constraints through uniform points, like contour lines.
void BM_Constraints(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  std::vector<Point3> points = uniform_points(n);
  std::vector<tincdt::constraints::Segment> rings;
  const std::size_t per_ring = 2000;
  for (int r = 1; r <= 20; ++r) {
    const auto first = static_cast<std::uint32_t>(points.size());
    for (std::size_t i = 0; i < per_ring; ++i) {
      const double a = 2 * M_PI * static_cast<double>(i) / per_ring, radius = 240.0 * r;
      points.push_back({505000 + radius * std::cos(a), 4005000 + radius * std::sin(a), 1.0 * r});
      rings.push_back({static_cast<std::uint32_t>(first + i),
                       static_cast<std::uint32_t>(first + (i + 1) % per_ring), 0});
    }
  }
  for (auto _ : state) {
    state.PauseTiming();
    std::vector<Point3> copy = points;
    auto dt = tincdt::delaunay::triangulate(std::move(copy), {.keep_point_map = true});
    std::vector<tincdt::constraints::Segment> segments = rings;
    for (auto& s : segments) {
      s.a = dt.vertex_of_point[s.a];
      s.b = dt.vertex_of_point[s.b];
    }
    state.ResumeTiming();
    auto result = tincdt::constraints::insert_constraints(dt.tin, segments);
    benchmark::DoNotOptimize(result.flips_insertion);
  }
}
BENCHMARK(BM_Constraints)->Arg(1000000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
