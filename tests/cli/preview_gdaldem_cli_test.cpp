// The preview's shading against GDAL's: tincdt writes a DEM and a preview of a surface with
// slopes facing every way and an erased hole, on the same cells (the preview's SIZE pixels span
// the kept extent's longer side, which the DEM's resolution divides exactly; no -tap), and
// `gdaldem hillshade -multidirectional -compute_edges` shades the DEM. Grey pixel for grey pixel
// they agree to one level. Where they could differ: the picture's sides (gdaldem extrapolates a
// row or column beyond them; the DEM's last row and column are grey in the picture, the outline
// being drawn just outside them), cells beside the hole (a neighbour without a height takes the
// cell's own, in both), the z factor on longitude/latitude (the preview's is gdaldem's
// -s 111120), and rounding (below). Pixels drawn over (the outline, the hole's ring) are left out;
// transparent pixels must be the DEM's nodata and gdaldem's 0.
#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "support/files.hpp"
#include "support/splitmix.hpp"
#include "support/tincdt_run.hpp"

namespace {

namespace fs = std::filesystem;

constexpr const char* kGdaldem = "/usr/bin/gdaldem";

// Hills and hollows on a tilted plane (x, y in metres from the corner): slopes facing every way,
// steep and gentle.
double surface(double x, double y) {
  return 30 + 12 * std::sin(x / 23) * std::cos(y / 17) + 0.03 * x - 0.02 * y;
}

// Where the surface lies: 200 x 100 units of UNIT from (X0, Y0), in the CRS SRS. The unit is
// the metre, or 2^-17 degree (about 0.85 m: exact in binary, so the cells of the DEM and of the
// picture are the same doubles) on longitude/latitude, where gdaldem needs -s 111120.
struct Place {
  std::string srs;
  double x0, y0, unit;
  std::string resolution;  // UNIT, in decimal
  std::string gdaldem_scale;
};

const Place kProjected{"EPSG:32632", 500000, 5000000, 1, "1", ""};
const Place kGeographic{"EPSG:4326", 10, 45, 0x1p-17, "0.00000762939453125", " -s 111120"};

// Points about 2 units apart over 200 x 100 units (the corners and sides exact, so that the
// kept extent is that rectangle), the inside jittered.
std::string points_text(const Place& place) {
  tincdt::test::SplitMix64 random{2024};
  std::string text;
  char line[128];
  for (int i = 0; i <= 100; ++i)
    for (int j = 0; j <= 50; ++j) {
      const bool side = i == 0 || i == 100 || j == 0 || j == 50;
      const double u = 2 * i + (side ? 0 : random.unit() - 0.5);
      const double v = 2 * j + (side ? 0 : random.unit() - 0.5);
      const int n =
          std::snprintf(line, sizeof line, "%.17g %.17g %.6f\n", place.x0 + u * place.unit,
                        place.y0 + v * place.unit, surface(u, v));
      text.append(line, static_cast<std::size_t>(n));
    }
  return text;
}

// An octagon of radius 12 units round (140, 60), to erase: a hole in the surface, cells without
// a value inside the picture. In the place's CRS (GeoJSON's old "crs" member; none is WGS 84).
std::string hole_geojson(const Place& place) {
  std::string ring;
  for (int k = 0; k <= 8; ++k) {
    const double angle = (k % 8) * std::numbers::pi / 4;
    char corner[96];
    std::snprintf(corner, sizeof corner, "%s[%.17g, %.17g]", k == 0 ? "" : ", ",
                  place.x0 + (140 + 12 * std::cos(angle)) * place.unit,
                  place.y0 + (60 + 12 * std::sin(angle)) * place.unit);
    ring += corner;
  }
  const std::string crs =
      place.srs == "EPSG:4326"
          ? ""
          : R"("crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::)" +
                place.srs.substr(5) + "\"}}, ";
  return "{\"type\": \"FeatureCollection\", " + crs +
         R"("features": [{"type": "Feature", "properties": {},
"geometry": {"type": "Polygon", "coordinates": [[)" +
         ring + "]]}}]}";
}

struct Band {
  int width = 0, height = 0;
  std::array<double, 6> geotransform{};
  std::vector<double> values;
  bool has_nodata = false;
  double nodata = 0;
};

Band read_band(const std::string& path, int band) {
  Band b;
  GDALDatasetUniquePtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER));
  if (!ds) {
    ADD_FAILURE() << "GDAL cannot open " << path;
    return b;
  }
  b.width = ds->GetRasterXSize();
  b.height = ds->GetRasterYSize();
  ds->GetGeoTransform(b.geotransform.data());
  GDALRasterBand* rb = ds->GetRasterBand(band);
  int has = 0;
  b.nodata = rb->GetNoDataValue(&has);
  b.has_nodata = has != 0;
  b.values.resize(std::size_t(b.width) * b.height);
  EXPECT_EQ(rb->RasterIO(GF_Read, 0, 0, b.width, b.height, b.values.data(), b.width, b.height,
                         GDT_Float64, 0, 0),
            CE_None);
  return b;
}

// tincdt writes the DEM and the preview of the surface at PLACE, gdaldem shades the DEM; the
// pixels of the three, in that order.
struct Rasters {
  Band dem, shade;
  std::array<Band, 4> preview;  // red, green, blue, alpha
};

Rasters make_rasters(const Place& place) {
  const std::string dir = tincdt::test::scratch_dir("preview_gdaldem_cli");
  tincdt::test::spit(fs::path(dir) / "pts.xyz", points_text(place));
  tincdt::test::spit(fs::path(dir) / "hole.geojson", hole_geojson(place));
  // 200 pixels on the longer side of a 200 x 100 extent: cells of one unit, the DEM's.
  const tincdt::test::ShellRun r = tincdt::test::run_tincdt(
      dir, "pts.xyz --a-srs " + place.srs + " --erase hole.geojson -o t.ply --dem d.tif" +
               " --resolution " + place.resolution + " --preview p.png --preview-size 200");
  EXPECT_EQ(r.exit_code, 0) << r.messages;
  EXPECT_EQ(std::system(("cd '" + dir + "' && " + kGdaldem + " hillshade -q -multidirectional" +
                         " -compute_edges" + place.gdaldem_scale + " d.tif h.tif")
                            .c_str()),
            0);
  GDALAllRegister();
  Rasters out;
  out.dem = read_band(dir + "/d.tif", 1);
  out.shade = read_band(dir + "/h.tif", 1);
  for (int k = 0; k < 4; ++k) out.preview[k] = read_band(dir + "/p.png", k + 1);
  return out;
}

void expect_shading_as_gdaldem(const Place& place) {
  const Rasters rasters = make_rasters(place);
  const Band& dem = rasters.dem;
  const Band& shade = rasters.shade;
  const std::array<Band, 4>& preview = rasters.preview;
  // The same cells: the preview's grid is the DEM's (no geotransform in a PNG, so its size).
  ASSERT_EQ(dem.width, 200);
  ASSERT_EQ(dem.height, 100);
  EXPECT_EQ(dem.geotransform, (std::array<double, 6>{place.x0, place.unit, 0,
                                                     place.y0 + 100 * place.unit, 0, -place.unit}));
  ASSERT_EQ(preview[0].width, dem.width);
  ASSERT_EQ(preview[0].height, dem.height);
  ASSERT_TRUE(dem.has_nodata);
  ASSERT_EQ(shade.values.size(), dem.values.size());
  for (const Band& band : preview) ASSERT_EQ(band.values.size(), dem.values.size());

  // Each pixel is transparent (no surface), an edge drawn in colour, or grey: the shading.
  std::size_t compared = 0, transparent = 0, matching = 0;
  double largest = 0;
  for (std::size_t i = 0; i < dem.values.size(); ++i) {
    const bool value = dem.values[i] != dem.nodata;
    if (preview[3].values[i] == 0) {
      // No surface in the picture: none in the DEM either, and gdaldem's 0 (its nodata).
      ++transparent;
      EXPECT_FALSE(value) << "pixel " << i;
      EXPECT_EQ(shade.values[i], 0) << "pixel " << i;
      continue;
    }
    if (preview[0].values[i] != preview[1].values[i] ||
        preview[0].values[i] != preview[2].values[i])
      continue;  // an edge (the outline, the hole's ring), drawn over whatever is there
    EXPECT_TRUE(value) << "grey without a height, pixel " << i;
    const double diff = std::abs(preview[0].values[i] - shade.values[i]);
    ++compared;
    if (diff == 0) ++matching;
    largest = std::max(largest, diff);
  }
  std::printf("%zu grey pixels compared, %zu equal, largest difference %g; %zu transparent\n",
              compared, matching, largest, transparent);
  EXPECT_GT(transparent, 300u);  // the hole: 12 units round, cells of 1 unit
  EXPECT_GT(compared, 18000u);   // of 20,000 pixels, the rest edges and the hole
  // The same formula on the same heights, but the DEM holds them as Float32 and gdaldem computes
  // in float with an approximate reciprocal square root: a grey at a rounding boundary may fall
  // either side, so one level of difference is allowed on 1 pixel in 100.
  EXPECT_LE(largest, 1);
  EXPECT_GE(matching, compared - compared / 100);
}

TEST(PreviewGdaldemCli, ShadingMatchesGdaldemMultidirectional) {
  if (!fs::exists(kGdaldem)) GTEST_SKIP() << kGdaldem << " is not installed";
  expect_shading_as_gdaldem(kProjected);
}

// Heights in metres on longitude/latitude: the preview's z factor is gdaldem's -s 111120.
TEST(PreviewGdaldemCli, OnLongitudeLatitudeAsGdaldemWithScale111120) {
  if (!fs::exists(kGdaldem)) GTEST_SKIP() << kGdaldem << " is not installed";
  expect_shading_as_gdaldem(kGeographic);
}

}  // namespace
