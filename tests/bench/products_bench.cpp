// DEM rasterization, contour tracing and the block-parallel TIN writers on a random TIN (Google
// Benchmark): cells, contour segments and written bytes per second, one thread and all threads.
// The TIN is 1M uniform points over a 10 km square with the terrain of ../shared/bench/gen.py's
// kind (smooth hills), built once. The writers write into /dev/shm when there is one, so that the
// figure is the formatting's, not the disk's.
#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "delaunay/delaunay.hpp"
#include "io/mesh/tin_writer.hpp"
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

struct WriterFormat {
  const char* extension;
  bool ply_ascii;
};
constexpr WriterFormat kWriterFormats[] = {
    {".ply", false}, {".ply", true}, {".obj", false}, {".stl", false}, {".geojson", false}};

std::filesystem::path scratch_folder() {
  const std::filesystem::path shm = "/dev/shm";
  return std::filesystem::is_directory(shm) ? shm : std::filesystem::temp_directory_path();
}

// Arg 0: format (PLY binary, PLY ASCII, OBJ, STL, GeoJSON); arg 1: threads.
void BM_WriteTin(benchmark::State& state) {
  const WriterFormat& f = kWriterFormats[state.range(0)];
  const std::string path =
      (scratch_folder() / (std::string("tincdt_products_bench") + f.extension)).string();
  io::TinWriteOptions options;
  options.ply_ascii = f.ply_ascii;
  options.overwrite = true;
  options.threads = static_cast<unsigned>(state.range(1));
  std::uint64_t bytes = 0;
  for (auto _ : state) bytes = io::write_tin(path, tin(), options).bytes;
  std::filesystem::remove(path);
  state.SetLabel(std::string(f.extension) + (f.ply_ascii ? " ascii" : ""));
  state.counters["MB/s"] = benchmark::Counter(static_cast<double>(bytes) / 1e6,
                                              benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_WriteTin)
    ->ArgsProduct({{0, 1, 2, 3, 4}, {1, 0}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
