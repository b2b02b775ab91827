// Writes the realistic Delaunay benchmark sets as points.bin (little-endian float64 x, y, z; the
// format of ../shared/bench), beside the synthetic uniform and grid sets:
//   make_real_points lidar IN.las|laz MIN_POINTS OUT.bin   real LiDAR spacing and file order:
//       IN's points, copied onto a grid of tiles side by side until there are MIN_POINTS
//   make_real_points dem IN.tif MIN_CELLS OUT.bin            a gridded DEM as points, row by
//       row: IN's first band resampled (bilinear) to the smallest square grid of MIN_CELLS cells
//       or more, no-data cells left out (the holes a real DEM has)
//   make_real_points duplicates N OUT.bin                    duplicate-heavy: N / 4 sites on a
//       1 cm grid in a 10 km square, each written 4 times (as overlapping flight strips repeat
//       a quantized point), every pass over the sites in its own order
// The same arguments give the same file.
#include <gdal_priv.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <numeric>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/types.hpp"
#include "io/points/point_reader.hpp"
#include "support/splitmix.hpp"

namespace {

using tincdt::Point3;

std::vector<Point3> lidar(const std::string& in, std::uint64_t min_points) {
  std::vector<Point3> tile;
  tincdt::io::read_points(in, {}, tile, 0);
  if (tile.empty()) throw tincdt::InputError(in, "", "no points");
  double x0 = tile[0].x, x1 = x0, y0 = tile[0].y, y1 = y0;
  for (const Point3& p : tile) {
    x0 = std::min(x0, p.x), x1 = std::max(x1, p.x);
    y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
  }
  const std::uint64_t copies = (min_points + tile.size() - 1) / tile.size();
  const auto columns = static_cast<std::uint64_t>(std::ceil(std::sqrt(double(copies))));
  // Whole units between copies: the copies' coordinates stay on the file's own scale.
  const double step_x = std::ceil(x1 - x0) + 1, step_y = std::ceil(y1 - y0) + 1;
  std::vector<Point3> out;
  out.reserve(copies * tile.size());
  for (std::uint64_t k = 0; k < copies; ++k) {
    const double dx = double(k % columns) * step_x, dy = double(k / columns) * step_y;
    for (const Point3& p : tile) out.push_back({p.x + dx, p.y + dy, p.z});
  }
  return out;
}

std::vector<Point3> dem(const std::string& in, std::uint64_t min_cells) {
  GDALAllRegister();
  GDALDataset* ds = GDALDataset::Open(in.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY);
  if (ds == nullptr) throw tincdt::InputError(in, "", "GDAL cannot open it as a raster");
  double gt[6];
  ds->GetGeoTransform(gt);
  GDALRasterBand* band = ds->GetRasterBand(1);
  int has_nodata = 0;
  const double nodata = band->GetNoDataValue(&has_nodata);
  const auto side = static_cast<int>(std::ceil(std::sqrt(double(min_cells))));
  std::vector<double> z(std::size_t(side) * std::size_t(side));
  GDALRasterIOExtraArg extra;
  INIT_RASTERIO_EXTRA_ARG(extra);
  extra.eResampleAlg = GRIORA_Bilinear;
  const CPLErr err = band->RasterIO(GF_Read, 0, 0, ds->GetRasterXSize(), ds->GetRasterYSize(),
                                    z.data(), side, side, GDT_Float64, 0, 0, &extra);
  const double cell_x = gt[1] * ds->GetRasterXSize() / side;
  const double cell_y = gt[5] * ds->GetRasterYSize() / side;
  GDALClose(ds);
  if (err != CE_None) throw tincdt::InputError(in, "", "cannot read its first band");
  std::vector<Point3> out;
  out.reserve(z.size());
  for (int row = 0; row < side; ++row) {
    for (int col = 0; col < side; ++col) {
      const double h = z[std::size_t(row) * std::size_t(side) + std::size_t(col)];
      if ((has_nodata && h == nodata) || !std::isfinite(h) || h < -1e4) continue;
      out.push_back({gt[0] + (col + 0.5) * cell_x, gt[3] + (row + 0.5) * cell_y, h});
    }
  }
  return out;
}

std::vector<Point3> duplicates(std::uint64_t n) {
  const std::uint64_t sites = n / 4;
  tincdt::test::SplitMix64 rng{20261127};
  std::vector<Point3> site(sites);
  for (Point3& p : site) {
    const double x = double(rng.next() % 1000000) / 100, y = double(rng.next() % 1000000) / 100;
    p = {500000 + x, 4000000 + y, 100 + std::sin(x / 300) * 40 + std::cos(y / 500) * 25};
  }
  std::vector<std::uint32_t> order(sites);
  std::vector<Point3> out;
  out.reserve(4 * sites);
  for (int pass = 0; pass < 4; ++pass) {
    std::iota(order.begin(), order.end(), 0u);
    for (std::size_t i = sites; i > 1; --i) std::swap(order[i - 1], order[rng.next() % i]);
    for (const std::uint32_t i : order) out.push_back(site[i]);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string kind = argc > 1 ? argv[1] : "";
  const bool from_file = kind == "lidar" || kind == "dem";
  if (!(from_file && argc == 5) && !(kind == "duplicates" && argc == 4)) {
    std::fprintf(stderr,
                 "usage: make_real_points lidar IN.las|laz MIN_POINTS OUT.bin\n"
                 "       make_real_points dem IN.tif MIN_CELLS OUT.bin\n"
                 "       make_real_points duplicates N OUT.bin\n");
    return 2;
  }
  try {
    const std::uint64_t count = std::strtoull(argv[from_file ? 3 : 2], nullptr, 10);
    const std::vector<Point3> points = kind == "lidar" ? lidar(argv[2], count)
                                       : kind == "dem" ? dem(argv[2], count)
                                                       : duplicates(count);
    const std::string out = argv[argc - 1];
    std::ofstream file(out + ".tmp", std::ios::binary | std::ios::trunc);
    file.write(reinterpret_cast<const char*>(points.data()),
               static_cast<std::streamsize>(points.size() * sizeof(Point3)));
    file.close();
    if (!file || std::rename((out + ".tmp").c_str(), out.c_str()) != 0) {
      std::fprintf(stderr, "make_real_points: cannot write %s\n", out.c_str());
      return 1;
    }
    std::printf("%s: %zu points\n", out.c_str(), points.size());
  } catch (const tincdt::Error& e) {
    std::fprintf(stderr, "make_real_points: %s\n", e.what());
    return 1;
  }
  return 0;
}
