// DEM rasterization and contour tracing on a random TIN (Google Benchmark): cells and contour
// segments per second, one thread and all threads. The TIN is 1M uniform points over a 10 km
// square with the terrain of ../shared/bench/gen.py's kind (smooth hills), built once.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "delaunay/delaunay.hpp"
#include "products/contours.hpp"
#include "products/rasterize.hpp"

namespace {

using namespace tincdt;

const mesh::Triangulation& tin() {
  static const mesh::Triangulation t = [] {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(0, 10000);
    std::vector<Point3> pts(1'000'000);
    for (Point3& p : pts) {
      const double x = u(rng), y = u(rng);
      p = {500000 + x, 4000000 + y,
           300 + 150 * std::sin(x / 1300) * std::cos(y / 1700) + 20 * std::sin(x / 150)};
    }
    return delaunay::triangulate(std::move(pts)).tin;
  }();
  return t;
}

// Arg 0: cell size in cm; arg 1: threads.
void BM_Rasterize(benchmark::State& state) {
  const double res = static_cast<double>(state.range(0)) / 100;
  const products::Grid grid = products::grid_over(products::kept_extent(tin()), res, true);
  std::vector<float> cells(grid.cells());
  for (auto _ : state) {
    const products::RasterizeStats s = products::rasterize<float>(
        tin(), grid, -9999.0f, cells, {.threads = static_cast<unsigned>(state.range(1))});
    benchmark::DoNotOptimize(s.cells_with_value);
  }
  state.counters["cells/s"] = benchmark::Counter(static_cast<double>(grid.cells()),
                                                 benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_Rasterize)
    ->Args({100, 1})
    ->Args({100, 0})
    ->Args({400, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Arg 0: interval in m; arg 1: threads.
void BM_Contours(benchmark::State& state) {
  std::uint64_t points = 0;
  for (auto _ : state) {
    const products::ContourSet s =
        products::trace_contours(tin(), {.interval = static_cast<double>(state.range(0)),
                                         .threads = static_cast<unsigned>(state.range(1))});
    points = s.points.size();
    benchmark::DoNotOptimize(points);
  }
  state.counters["points/s"] = benchmark::Counter(static_cast<double>(points),
                                                  benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_Contours)->Args({2, 1})->Args({2, 0})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
