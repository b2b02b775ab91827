// The terrain functions on the shared real data (skipped when ../shared/data is absent): the
// contour-only TIN of the lidR 2016 "Topography" DEM, whose flats are fixed and whose heights
// are compared with the DEM itself; clip / erase / replace / trim on the same TIN.
#include <gdal.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <string>

#include "constraints/constraints.hpp"
#include "delaunay/delaunay.hpp"
#include "io/vector/line_reader.hpp"
#include "support/shared_data.hpp"
#include "terrain/flats.hpp"
#include "terrain/interpolate.hpp"
#include "terrain/polygons.hpp"
#include "terrain/quality.hpp"
#include "terrain/trim.hpp"

namespace tincdt::terrain {
namespace {

const std::string kData = ::tincdt::test::shared_data();
const std::string kContours = kData + "/contours/Topography_lidR2016_contours_2m_3d.shp";
const std::string kDem = kData + "/dem/Topography_lidR2016_dtm.tif";

bool have_data() {
  return std::filesystem::exists(kContours) && std::filesystem::exists(kDem);
}

struct ContourTin {
  mesh::Triangulation tin;
  std::vector<constraints::Segment> segments;
  std::vector<std::uint8_t> on_contour;
};

// Contours -> vertices -> Delaunay -> segments as constraints, plus optional extra rings
// (points with z, closed), as the pipeline does. Every vertex of this TIN lies on a contour
// except those of the extra rings and the crossings of rings and contours.
ContourTin contour_tin(const std::vector<std::vector<Point3>>& rings = {},
                       const std::string& path = kContours, const std::string& z_field = {}) {
  io::LineData lines;
  io::LineReadOptions options;
  options.z_field = z_field;
  io::read_lines(path, options, lines);
  std::vector<Point3> pts = lines.vertices;
  const auto contour_points = pts.size();
  std::vector<std::pair<std::uint32_t, std::uint32_t>> segs;
  for (const auto& s : lines.segments) segs.push_back({s.a, s.b});
  for (const auto& ring : rings) {
    const auto first = static_cast<std::uint32_t>(pts.size());
    pts.insert(pts.end(), ring.begin(), ring.end());
    const auto n = static_cast<std::uint32_t>(ring.size());
    for (std::uint32_t i = 0; i < n; ++i) segs.push_back({first + i, first + (i + 1) % n});
  }
  auto dt = delaunay::triangulate(std::move(pts), {.keep_point_map = true});
  ContourTin c{std::move(dt.tin), {}, {}};
  for (std::uint32_t i = 0; i < segs.size(); ++i)
    c.segments.push_back(
        {dt.vertex_of_point[segs[i].first], dt.vertex_of_point[segs[i].second], i});
  constraints::insert_constraints(c.tin, c.segments);
  c.on_contour.assign(c.tin.vertex_count(), 0);
  for (std::size_t p = 0; p < contour_points; ++p) c.on_contour[dt.vertex_of_point[p]] = 1;
  return c;
}

struct Dem {
  double gt[6];
  int nx = 0, ny = 0;
  std::vector<double> z;
  bool has_nodata = false;
  double nodata = 0;
};

Dem read_dem(const std::string& path = kDem) {
  GDALAllRegister();
  Dem d;
  GDALDatasetH ds = GDALOpen(path.c_str(), GA_ReadOnly);
  EXPECT_NE(ds, nullptr);
  if (!ds) return d;
  GDALGetGeoTransform(ds, d.gt);
  d.nx = GDALGetRasterXSize(ds);
  d.ny = GDALGetRasterYSize(ds);
  GDALRasterBandH band = GDALGetRasterBand(ds, 1);
  int ok = 0;
  d.nodata = GDALGetRasterNoDataValue(band, &ok);
  d.has_nodata = ok != 0;
  d.z.resize(static_cast<std::size_t>(d.nx) * static_cast<std::size_t>(d.ny));
  const CPLErr err =
      GDALRasterIO(band, GF_Read, 0, 0, d.nx, d.ny, d.z.data(), d.nx, d.ny, GDT_Float64, 0, 0);
  EXPECT_EQ(err, CE_None);
  GDALClose(ds);
  return d;
}

// Root mean square of TIN - DEM at the cell centres inside the TIN (and with data).
double rmse(const mesh::Triangulation& tin, const Dem& d, std::size_t& cells) {
  SurfaceSampler sampler(tin);
  double sum = 0;
  cells = 0;
  for (int j = 0; j < d.ny; ++j)
    for (int i = 0; i < d.nx; ++i) {
      const double dem = d.z[static_cast<std::size_t>(j) * static_cast<std::size_t>(d.nx) +
                             static_cast<std::size_t>(i)];
      if (d.has_nodata && dem == d.nodata) continue;
      const double u = i + 0.5, v = j + 0.5;
      const Point2 p{d.gt[0] + u * d.gt[1] + v * d.gt[2], d.gt[3] + u * d.gt[4] + v * d.gt[5]};
      const double z = sampler.z_at(p);
      if (std::isnan(z)) continue;
      sum += (z - dem) * (z - dem);
      ++cells;
    }
  return std::sqrt(sum / static_cast<double>(cells));
}

void expect_constraints_kept(const ContourTin& c) {
  mesh::Triangulation copy = c.tin;
  copy.build_vertex_index();
  std::size_t missing = 0;
  for (const auto& s : c.segments)
    if (s.a != s.b) {
      const EdgeId e = copy.find_edge(s.a, s.b);
      missing += e == kNoId || !copy.is_constrained(e);
    }
  EXPECT_EQ(missing, 0u);
}

TEST(RealData, FixFlatsOnTopographyContours) {
  if (!have_data()) GTEST_SKIP() << "no shared data at " << kData;
  ContourTin c = contour_tin();
  const Dem dem = read_dem();
  ASSERT_GT(dem.nx, 0);
  std::size_t cells_before = 0, cells_after = 0, cells_cdt = 0;
  const double before = rmse(c.tin, dem, cells_before);
  const QualityReport q_before = measure_quality(c.tin, &c.on_contour);

  ContourTin cdt = c;  // the Steiner-only variant, for comparison
  const FlatFixReport r = fix_flat_triangles(c.tin, c.on_contour);
  const FlatFixReport r_cdt = fix_flat_triangles(cdt.tin, cdt.on_contour, {.swap = false});
  const double after = rmse(c.tin, dem, cells_after);
  const double after_cdt = rmse(cdt.tin, dem, cells_cdt);
  const QualityReport q_after = measure_quality(c.tin, &c.on_contour);

  std::printf(
      "[ info ] Topography_lidR2016 contours (2 m): %zu vertices, %zu triangles\n"
      "[ info ] flats: %llu before, %llu after %llu swaps, %llu after %llu Steiner vertices "
      "(%llu interpolated, %llu extrapolated); non-Delaunay edges left by the swaps: %llu\n"
      "[ info ] RMSE vs DEM at %zu cell centres: %.4f m before, %.4f m after "
      "(Steiner only, no swaps: %.4f m, %llu vertices, flats %llu)\n"
      "[ info ] min angle %.2f -> %.2f deg; triangles under 20 deg %llu -> %llu\n"
      "[ info ] flats left: %llu with no level, %llu unplaced\n",
      c.tin.vertex_count() - r.vertices_added, q_before.triangles,
      (unsigned long long)r.flats_before, (unsigned long long)r.flats_after_swaps,
      (unsigned long long)r.swaps, (unsigned long long)r.flats_after,
      (unsigned long long)r.vertices_added, (unsigned long long)r.vertices_interpolated,
      (unsigned long long)r.vertices_extrapolated, (unsigned long long)r.non_delaunay_edges,
      cells_before, before, after, after_cdt, (unsigned long long)r_cdt.vertices_added,
      (unsigned long long)r_cdt.flats_after, q_before.min_angle_deg, q_after.min_angle_deg,
      (unsigned long long)q_before.triangles_below_20deg,
      (unsigned long long)q_after.triangles_below_20deg, (unsigned long long)r.flats_left_no_level,
      (unsigned long long)r.flats_left_unplaced);

  EXPECT_GT(r.flats_before, 100u);
  EXPECT_EQ(q_before.flat_triangles, r.flats_before);
  EXPECT_EQ(r.flats_after, r.flats_left_no_level + r.flats_left_unplaced + r.flats_left_not_tried);
  EXPECT_EQ(r.flats_after, 0u);
  EXPECT_EQ(r_cdt.flats_after, 0u);
  EXPECT_EQ(q_after.flat_triangles, 0u);
  EXPECT_EQ(cells_after, cells_before);  // the hull did not change
  EXPECT_LT(after, before);
  EXPECT_LT(after_cdt, before);
  EXPECT_EQ(c.tin.validate({.delaunay = false}), "");
  EXPECT_EQ(cdt.tin.validate(), "");
  expect_constraints_kept(c);
  expect_constraints_kept(cdt);
}

// The other contour / DEM pairs of the shared data: flats gone, TIN valid, heights no worse.
TEST(RealData, FixFlatsOnOtherContourSets) {
  struct Case {
    const char* contours;
    const char* z_field;
    const char* dem;
  };
  const Case cases[] = {
      {"pair_topography/Topography_contours_1m_3d.shp", "",
       "pair_topography/Topography_ground_dtm_2m.tif"},
      {"pair_autzen/autzen_trim_contours_2ft_3d.shp", "",
       "pair_autzen/autzen_trim_ground_dtm_6ft.tif"},
      {"contours/elev_vinschgau_contours_100m_3d.shp", "", "dem/elev_vinschgau.tif"},
      {"contours/elev_lux_contours_25m.shp", "ELEV", "dem/elev_lux.tif"},
  };
  int run = 0;
  for (const Case& k : cases) {
    const std::string contours = kData + "/" + k.contours, dem_path = kData + "/" + k.dem;
    if (!std::filesystem::exists(contours) || !std::filesystem::exists(dem_path)) continue;
    ++run;
    ContourTin c = contour_tin({}, contours, k.z_field);
    ContourTin cdt = c;
    const Dem dem = read_dem(dem_path);
    std::size_t cells_before = 0, cells_after = 0, cells_cdt = 0;
    const double before = rmse(c.tin, dem, cells_before);
    const FlatFixReport r = fix_flat_triangles(c.tin, c.on_contour);
    const FlatFixReport r_cdt = fix_flat_triangles(cdt.tin, cdt.on_contour, {.swap = false});
    const double after = rmse(c.tin, dem, cells_after);
    const double after_cdt = rmse(cdt.tin, dem, cells_cdt);
    std::printf(
        "[ info ] %s: flats %llu -> %llu (%llu swaps, %llu vertices; left: %llu no level, "
        "%llu unplaced); RMSE %.4f -> %.4f at %zu cells (no swaps: %.4f, %llu vertices)\n",
        k.contours, (unsigned long long)r.flats_before, (unsigned long long)r.flats_after,
        (unsigned long long)r.swaps, (unsigned long long)r.vertices_added,
        (unsigned long long)r.flats_left_no_level, (unsigned long long)r.flats_left_unplaced,
        before, after, cells_before, after_cdt, (unsigned long long)r_cdt.vertices_added);
    EXPECT_EQ(r_cdt.flats_after, 0u) << k.contours;
    EXPECT_LT(after_cdt, before) << k.contours;
    EXPECT_EQ(cdt.tin.validate(), "") << k.contours;
    EXPECT_GT(r.flats_before, 0u) << k.contours;
    EXPECT_EQ(r.flats_after, 0u) << k.contours;
    EXPECT_EQ(cells_after, cells_before) << k.contours;
    EXPECT_LT(after, before) << k.contours;
    EXPECT_EQ(c.tin.validate({.delaunay = false}), "") << k.contours;
    expect_constraints_kept(c);
  }
  if (!run) GTEST_SKIP() << "no shared data at " << kData;
}

TEST(RealData, ClipEraseReplaceTrim) {
  if (!have_data()) GTEST_SKIP() << "no shared data at " << kData;
  // 2D rings draped on the contour TIN (as the pipeline does for rings without z): a tilted
  // 41-gon clip, a square erase hole inside it, a hexagonal pad to flatten elsewhere in it.
  const ContourTin base = contour_tin();
  const Point2 centre{684975.3, 5018150.7};
  const auto drape = [&](const std::vector<Point2>& ring) {
    std::vector<Point3> out;
    for (const Point2& p : ring) {
      const double z = interpolate_z(base.tin, p);
      EXPECT_FALSE(std::isnan(z));
      out.push_back({p.x, p.y, z});
    }
    return out;
  };
  const auto regular = [&](Point2 c, double r, int n, double phase) {
    std::vector<Point2> ring;
    for (int k = 0; k < n; ++k) {
      const double a = phase + 2 * std::numbers::pi * k / n;
      ring.push_back({c.x + r * std::cos(a), c.y + r * std::sin(a)});
    }
    return ring;
  };
  const auto clip = regular(centre, 120, 41, 0.1);
  const auto hole = regular({centre.x - 40, centre.y + 10}, 25, 4, 0.3);
  const auto pad = regular({centre.x + 50, centre.y - 30}, 20, 6, 0.2);
  ContourTin c = contour_tin({drape(clip), drape(hole), drape(pad)});
  ASSERT_EQ(c.tin.validate(), "");

  const auto area = [](const std::vector<Point2>& ring) {
    double a = 0;  // relative to the first point: map coordinates would cancel
    const Point2 o = ring[0];
    for (std::size_t i = 0; i < ring.size(); ++i) {
      const Point2 p = ring[i], q = ring[(i + 1) % ring.size()];
      a += (p.x - o.x) * (q.y - o.y) - (q.x - o.x) * (p.y - o.y);
    }
    return std::fabs(a) / 2;
  };
  Polygon clip_polygon, erase_polygon, pad_polygon;
  clip_polygon.rings = {clip};
  erase_polygon.rings = {hole};
  pad_polygon.rings = {pad};
  pad_polygon.z = 444.25;

  const std::uint64_t replaced = set_polygon_z_inside(c.tin, {pad_polygon});
  EXPECT_GT(replaced, 20u);
  EXPECT_GT(remove_outside(c.tin, {clip_polygon}), 0u);
  EXPECT_GT(remove_inside(c.tin, {erase_polygon}), 0u);
  EXPECT_EQ(c.tin.validate(), "");
  const QualityReport q = measure_quality(c.tin);
  const double expected = area(clip) - area(hole);
  EXPECT_NEAR(q.area_2d, expected, 1e-9 * expected);

  // Replaced vertices: the pad's interior is at the pad's z.
  for (double fx = -0.9; fx <= 0.9; fx += 0.3)
    for (double fy = -0.9; fy <= 0.9; fy += 0.3)
      EXPECT_DOUBLE_EQ(interpolate_z(c.tin, {centre.x + 50 + 12 * fx, centre.y - 30 + 12 * fy}),
                       444.25);
  // Nothing outside the clip or inside the hole.
  const PolygonIndex clip_index({clip_polygon}), hole_index({erase_polygon});
  c.tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& t) {
    const Point2 a = c.tin.point(t[0]), b = c.tin.point(t[1]), d = c.tin.point(t[2]);
    const Point2 g{(a.x + b.x + d.x) / 3, (a.y + b.y + d.y) / 3};
    EXPECT_NE(clip_index.polygon_at(g), kNoId);
    EXPECT_EQ(hole_index.polygon_at(g), kNoId);
  });
  // Trimming eats nothing of this compact shape at a generous limit, and everything long at a
  // tight one, from the clip outline and the hole alike.
  EXPECT_EQ(trim_long_edges(c.tin, 1000), 0u);
  const std::uint64_t trimmed = trim_long_edges(c.tin, 3);
  EXPECT_GT(trimmed, 0u);
  EXPECT_EQ(c.tin.validate(), "");
  std::printf(
      "[ info ] clip/erase: %llu triangles kept, %.1f m2 (expected %.1f); replaced %llu "
      "vertices; trim at 3 m removed %llu\n",
      (unsigned long long)q.triangles, q.area_2d, expected, (unsigned long long)replaced,
      (unsigned long long)trimmed);
}

}  // namespace
}  // namespace tincdt::terrain
