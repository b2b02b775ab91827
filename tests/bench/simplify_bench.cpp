// tincdt's simplification on a height grid, in the terms of ../shared/bench/node/delatin_run.mjs:
// cell (i, j) of a WIDTH x HEIGHT Float32 grid (row-major, as gdal_translate -of ENVI writes it)
// is the point x = i (column), y = j (row), z = its height. Times the simplification alone (not
// the file reading) and prints
//   RESULT tool=tincdt width=W height=H max_error=E vertices=V triangles=T run_s=S
//          achieved_max_error=M rmse=R
// MODE "points" (the default) times simplify() on the cells as given (row by row); "stage" times
// what the pipeline's simplify stage runs, simplify_tin() on the Delaunay TIN of the cells (its
// vertices in the Delaunay stage's Hilbert order; the triangulation itself untimed).
// Usage: simplify_bench GRID.f32 WIDTH HEIGHT MAX_ERROR [THREADS [MODE]]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <string>
#include <vector>

#include "core/memory.hpp"
#include "delaunay/delaunay.hpp"
#include "simplify/simplify.hpp"

int main(int argc, char** argv) {
  const std::string mode = argc > 6 ? argv[6] : "points";
  if (argc < 5 || argc > 7 || (mode != "points" && mode != "stage")) {
    std::fprintf(stderr, "usage: %s GRID.f32 WIDTH HEIGHT MAX_ERROR [THREADS [points|stage]]\n",
                 argv[0]);
    return 2;
  }
  const std::size_t width = std::strtoull(argv[2], nullptr, 10);
  const std::size_t height = std::strtoull(argv[3], nullptr, 10);
  const double max_error = std::strtod(argv[4], nullptr);
  const unsigned threads = argc > 5 ? static_cast<unsigned>(std::atoi(argv[5])) : 0;
  const std::size_t n = width * height;

  std::ifstream in(argv[1], std::ios::binary | std::ios::ate);
  if (!in || static_cast<std::size_t>(in.tellg()) != n * sizeof(float)) {
    std::fprintf(stderr, "%s: not a %zu x %zu Float32 grid\n", argv[1], width, height);
    return 1;
  }
  std::vector<float> grid(n);
  in.seekg(0);
  in.read(reinterpret_cast<char*>(grid.data()), static_cast<std::streamsize>(n * sizeof(float)));

  // As the pipeline's vertex arrays: huge pages where the kernel allows them on request.
  std::vector<tincdt::Point2> xy;
  std::vector<double> z;
  xy.reserve(n);
  z.reserve(n);
  tincdt::advise_huge_pages(xy);
  tincdt::advise_huge_pages(z);
  xy.resize(n);
  z.resize(n);
  for (std::size_t j = 0; j < height; ++j)
    for (std::size_t i = 0; i < width; ++i) {
      xy[j * width + i] = {static_cast<double>(i), static_cast<double>(j)};
      z[j * width + i] = grid[j * width + i];
    }
  std::vector<float>().swap(grid);

  tincdt::simplify::SimplifyOptions options;
  options.max_error = max_error;
  options.threads = threads;
  tincdt::mesh::Triangulation full;
  if (mode == "stage") {
    std::vector<tincdt::Point3> points(n);
    for (std::size_t k = 0; k < n; ++k) points[k] = {xy[k].x, xy[k].y, z[k]};
    std::vector<tincdt::Point2>().swap(xy);
    std::vector<double>().swap(z);
    full = tincdt::delaunay::triangulate(std::move(points), {.threads = threads}).tin;
  }
  const std::clock_t c0 = std::clock();
  const auto t0 = std::chrono::steady_clock::now();
  const tincdt::simplify::SimplifyResult r =
      mode == "stage" ? tincdt::simplify::simplify_tin(full, options)
                      : tincdt::simplify::simplify(xy, z, {}, {}, options);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;  // all threads
  std::printf(
      "RESULT tool=tincdt width=%zu height=%zu max_error=%g vertices=%llu triangles=%zu "
      "run_s=%.4f achieved_max_error=%.6f rmse=%.6f run_cpu_s=%.4f\n",
      width, height, max_error, static_cast<unsigned long long>(r.report.vertices),
      r.tin.triangle_count(), s, r.report.max_error, r.report.rmse, cpu);
  return 0;
}
