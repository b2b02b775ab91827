// The full TIN sampled on each given web-terrain tile's rectangle as a SIZE x SIZE height grid, for
// a grid simplifier (martini) to mesh the same tile as tincdt's pyramid (compare_martini.sh).
//   terrain_tile_grids TIN.ply CRS FILL SIZE OUT_DIR Z/X/Y...
// TIN.ply: a TIN tincdt wrote (binary or ASCII); CRS: its CRS as WKT or a .prj file. The vertices
// go to longitude/latitude on WGS 84 and metres by the library's own transform (the pyramid's);
// the tile rectangles are the library's (the geographic TMS tiling). Sample (i, j) is at
// longitude west + i * (east - west) / (SIZE - 1), latitude north - j * (north - south) / (SIZE -
// 1) (so the corners and sides are the tile's), its height the TIN's linear interpolation in the
// triangle holding it in longitude/latitude, or FILL outside every triangle: the surface the
// pyramid's tiles approximate. Writes OUT_DIR/Z_X_Y.f32 (float32, row-major, first row north,
// as martini_run.mjs reads) and prints one line a tile:
//   GRID tile=Z/X/Y inside=F min=H max=H
// with F the fraction of the samples inside the TIN.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "io/mesh/ply_reader.hpp"
#include "io/terrain/geographic_tiling.hpp"
#include "io/terrain/lon_lat.hpp"

namespace {

using tincdt::Point3;
namespace qm = tincdt::io::terrain;

// The triangles of a TIN in longitude/latitude behind a uniform grid of buckets (each triangle in
// every bucket its box meets), for the height at a point.
class Surface {
 public:
  Surface(std::vector<Point3> vertices, std::vector<std::array<std::uint32_t, 3>> triangles,
          double fill)
      : v_(std::move(vertices)), t_(std::move(triangles)), fill_(fill) {
    west_ = south_ = INFINITY;
    double east = -INFINITY, north = -INFINITY;
    for (const Point3& p : v_) {
      west_ = std::min(west_, p.x);
      south_ = std::min(south_, p.y);
      east = std::max(east, p.x);
      north = std::max(north, p.y);
    }
    n_ = std::max<std::size_t>(
        1, static_cast<std::size_t>(std::sqrt(static_cast<double>(t_.size()) / 2)));
    cell_w_ = std::max(east - west_, 1e-12) / static_cast<double>(n_);
    cell_h_ = std::max(north - south_, 1e-12) / static_cast<double>(n_);
    buckets_.assign(n_ * n_, {});
    for (std::uint32_t k = 0; k < t_.size(); ++k) {
      double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
      for (const std::uint32_t c : t_[k]) {
        x0 = std::min(x0, v_[c].x), x1 = std::max(x1, v_[c].x);
        y0 = std::min(y0, v_[c].y), y1 = std::max(y1, v_[c].y);
      }
      for (std::size_t r = row(y0); r <= row(y1); ++r)
        for (std::size_t c = column(x0); c <= column(x1); ++c) buckets_[r * n_ + c].push_back(k);
    }
  }

  // The height at LON, LAT and whether a triangle holds it.
  std::pair<double, bool> at(double lon, double lat) const {
    const double east = west_ + cell_w_ * static_cast<double>(n_);
    const double north = south_ + cell_h_ * static_cast<double>(n_);
    if (lon < west_ || lon > east || lat < south_ || lat > north) return {fill_, false};
    for (const std::uint32_t k : buckets_[row(lat) * n_ + column(lon)]) {
      const Point3 &a = v_[t_[k][0]], &b = v_[t_[k][1]], &c = v_[t_[k][2]];
      const double area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
      if (area == 0) continue;
      // Barycentric weights; a point on a shared edge may take either triangle (same height).
      const double wa = ((b.x - lon) * (c.y - lat) - (b.y - lat) * (c.x - lon)) / area;
      const double wb = ((c.x - lon) * (a.y - lat) - (c.y - lat) * (a.x - lon)) / area;
      const double wc = 1 - wa - wb;
      constexpr double kSlack = -1e-12;
      if (wa >= kSlack && wb >= kSlack && wc >= kSlack)
        return {wa * a.z + wb * b.z + wc * c.z, true};
    }
    return {fill_, false};
  }

 private:
  std::size_t column(double x) const {
    const double c = std::floor((x - west_) / cell_w_);
    return static_cast<std::size_t>(std::clamp(c, 0.0, static_cast<double>(n_ - 1)));
  }
  std::size_t row(double y) const {
    const double r = std::floor((y - south_) / cell_h_);
    return static_cast<std::size_t>(std::clamp(r, 0.0, static_cast<double>(n_ - 1)));
  }

  std::vector<Point3> v_;
  std::vector<std::array<std::uint32_t, 3>> t_;
  double fill_;
  double west_ = 0, south_ = 0, cell_w_ = 1, cell_h_ = 1;
  std::size_t n_ = 1;
  std::vector<std::vector<std::uint32_t>> buckets_;
};

std::string crs_text(const std::string& arg) {
  std::ifstream in(arg);
  if (!in) return arg;
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// "Z/X/Y" into KEY; false when it is not three whole numbers.
bool parse_key(const std::string& text, qm::TileKey& key) {
  unsigned z = 0, x = 0, y = 0;
  char end = 0;
  if (std::sscanf(text.c_str(), "%u/%u/%u%c", &z, &x, &y, &end) != 3) return false;
  key = {static_cast<int>(z), x, y};
  return z <= static_cast<unsigned>(qm::kMaxTileLevel) && x < qm::tiles_across(key.level) &&
         y < qm::tiles_down(key.level);
}

int write_grid(const Surface& surface, const qm::TileKey& key, int size, const std::string& dir) {
  const qm::GeoRectangle r = qm::tile_rectangle(key);
  std::vector<float> grid(static_cast<std::size_t>(size) * size);
  std::size_t inside = 0;
  double low = INFINITY, high = -INFINITY;
  for (int j = 0; j < size; ++j)
    for (int i = 0; i < size; ++i) {
      const double lon = r.west + (r.east - r.west) * i / (size - 1);
      const double lat = r.north - (r.north - r.south) * j / (size - 1);
      const auto [h, in] = surface.at(lon, lat);
      inside += in;
      low = std::min(low, h), high = std::max(high, h);
      grid[static_cast<std::size_t>(j) * size + i] = static_cast<float>(h);
    }
  const std::string name =
      std::to_string(key.level) + "/" + std::to_string(key.x) + "/" + std::to_string(key.y);
  const std::string path = dir + "/" + std::to_string(key.level) + "_" + std::to_string(key.x) +
                           "_" + std::to_string(key.y) + ".f32";
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(grid.data()),
            static_cast<std::streamsize>(grid.size() * sizeof(float)));
  if (!out) {
    std::fprintf(stderr, "cannot write %s\n", path.c_str());
    return 1;
  }
  std::printf("GRID tile=%s inside=%.6f min=%.3f max=%.3f\n", name.c_str(),
              static_cast<double>(inside) / static_cast<double>(grid.size()), low, high);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 7) {
    std::fprintf(stderr, "usage: terrain_tile_grids TIN.ply CRS FILL SIZE OUT_DIR Z/X/Y...\n");
    return 2;
  }
  try {
    tincdt::io::PlyMesh mesh = tincdt::io::read_ply(argv[1]);
    qm::to_lon_lat_metres(crs_text(argv[2]), mesh.vertices, argv[1]);
    const double fill = std::atof(argv[3]);
    const int size = std::atoi(argv[4]);
    if (size < 2) {
      std::fprintf(stderr, "SIZE must be at least 2\n");
      return 2;
    }
    const Surface surface(std::move(mesh.vertices), std::move(mesh.faces), fill);
    for (int a = 6; a < argc; ++a) {
      qm::TileKey key{};
      if (!parse_key(argv[a], key)) {
        std::fprintf(stderr, "'%s' is not a tile Z/X/Y\n", argv[a]);
        return 2;
      }
      if (write_grid(surface, key, size, argv[5]) != 0) return 1;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  return 0;
}
