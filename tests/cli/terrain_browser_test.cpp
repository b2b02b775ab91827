// --terrain DIR loaded by a real client: CesiumJS in Debian's headless Chromium
// (tests/web/cesium_sample.mjs, through playwright-core) reads the pyramid of the sample from a
// static server on another origin, as docs/web_terrain.md says to serve it, and samples it with
// sampleTerrainMostDetailed. The heights it finds are the full TIN's, computed here from the
// run's PLY, within the finest level's error; it reached that level at every point; no request
// left localhost, no CORS preflight was needed and the page reported no error; its screenshot has
// the size asked and shows more than one colour; beyond the data, where tiles of different levels
// meet, it draws no step higher than the data's relief. With Cesium's default options (reading
// the tiles' metadata extension, as layer.json's metadataAvailability lets it) and with the tiles
// gzipped on the wire (Content-Encoding: gzip). Skips, saying why, without Node.js, the npm
// packages of tests/web or /usr/bin/chromium (cmake/setup_web_tools.sh installs them).
#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/json.hpp"
#include "support/files.hpp"
#include "support/tincdt_run.hpp"
#include "support/web_tools.hpp"
#include "terrain_support.hpp"

namespace tincdt::test::terrain {
namespace {

const std::string kSample = std::string(TINCDT_SOURCE_DIR) + "/data/sample.las";
const std::string kContours = std::string(TINCDT_SOURCE_DIR) + "/data/sample_contours.shp";
const char* const kChromium = "/usr/bin/chromium";
constexpr int kWidth = 640, kHeight = 400;

#define TINCDT_REQUIRE_BROWSER()                                                            \
  do {                                                                                      \
    TINCDT_REQUIRE_WEB_TOOL("cesium");                                                      \
    TINCDT_REQUIRE_WEB_TOOL("playwright-core");                                             \
    if (!std::filesystem::exists(kChromium))                                                \
      GTEST_SKIP() << kChromium << " not found (Debian's chromium package; install it and " \
                   << "the npm tools: cmake/setup_web_tools.sh)";                           \
  } while (false)

const json::Value& at(const json::Value& v, const char* key) {
  const json::Value* m = v.find(key);
  if (m == nullptr) throw std::runtime_error(std::string("no member ") + key);
  return *m;
}

// The strings of a JSON array, one a line.
std::string lines_of(const json::Value& list) {
  std::string out;
  for (const auto& s : list.items()) out += s.string() + "\n";
  return out;
}

struct Probe {
  double lon, lat, height;  // the full TIN's height there
};

// The height of the TIN MESH (vertices LON_LAT in longitude, latitude, metres) at LON, LAT: the
// plane of the triangle holding the point. Over a triangle a few metres wide, longitude and
// latitude are the TIN's projected coordinates up to an affine map, far below the tolerance.
std::optional<double> tin_height(const MeshFile& mesh,
                                 const std::vector<std::array<double, 3>>& lon_lat, double lon,
                                 double lat) {
  for (const auto& t : mesh.f) {
    const auto &a = lon_lat[t[0]], &b = lon_lat[t[1]], &c = lon_lat[t[2]];
    const double area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    const double wa = ((b[0] - lon) * (c[1] - lat) - (b[1] - lat) * (c[0] - lon)) / area;
    const double wb = ((c[0] - lon) * (a[1] - lat) - (c[1] - lat) * (a[0] - lon)) / area;
    const double wc = 1 - wa - wb;
    if (std::min({wa, wb, wc}) >= 0) return wa * a[2] + wb * b[2] + wc * c[2];
  }
  return std::nullopt;
}

// A 4 x 4 grid over the middle of the TIN's extent, with the TIN's height at each point.
std::vector<Probe> probes(const std::string& dir) {
  const MeshFile mesh = read_mesh(dir + "/full.ply");
  const auto lon_lat = lon_lat_metres(dir + "/full.ply", dir + "/full.prj");
  double west = INFINITY, south = INFINITY, east = -INFINITY, north = -INFINITY;
  for (const auto& p : lon_lat) {
    west = std::min(west, p[0]);
    east = std::max(east, p[0]);
    south = std::min(south, p[1]);
    north = std::max(north, p[1]);
  }
  std::vector<Probe> out;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      const double lon = west + (east - west) * (0.17 + 0.22 * i);
      const double lat = south + (north - south) * (0.13 + 0.24 * j);
      const auto h = tin_height(mesh, lon_lat, lon, lat);
      EXPECT_TRUE(h.has_value()) << lon << "," << lat;
      if (h) out.push_back({lon, lat, *h});
    }
  return out;
}

// The sample's ground and contours as a pyramid DIR/t, the full TIN beside it (DIR/full.ply),
// the surface beyond the data the default, the TIN's lowest; returns the finest level.
int build_pyramid(const std::string& dir) {
  const ShellRun r = run_tincdt(dir, "'" + kSample + "' --keep-class 2 --contours '" + kContours +
                                         "' -o full.ply --ply-ascii --terrain t");
  EXPECT_EQ(r.exit_code, 0) << r.messages;
  const json::Value layer = json::parse(slurp(dir + "/t/layer.json"));
  return static_cast<int>(at(layer, "maxzoom").number());
}

// tests/web/cesium_sample.mjs on DIR/t at PROBES with OPTIONS; its JSON answer.
json::Value sample_in_browser(const std::string& dir, const std::vector<Probe>& points,
                              const std::string& options) {
  std::string command = "node '" TINCDT_CESIUM_SAMPLE_SCRIPT "' --modules '" +
                        web_tools().string() + "' --terrain '" + dir + "/t' --chromium " +
                        kChromium + " " + options;
  char place[64];
  for (const auto& p : points) {
    std::snprintf(place, sizeof place, " %.9f,%.9f", p.lon, p.lat);
    command += place;
  }
  std::cout << command << "\n";
  const std::string out = dir + "/cesium.json";
  EXPECT_EQ(std::system((command + " > '" + out + "'").c_str()), 0) << command;
  return json::parse(slurp(out));
}

// Cesium's heights are the TIN's within the finest level's error, sampled at that level; it read
// the tiles' metadata; no CORS preflight was needed, nothing was fetched from elsewhere (no tile
// missing either) and the page raised no error.
void expect_heights_of_tin(const json::Value& answer, const std::vector<Probe>& points, int max) {
  const auto& heights = at(answer, "heights").items();
  const auto& levels = at(answer, "levels").items();
  ASSERT_EQ(heights.size(), points.size());
  ASSERT_EQ(levels.size(), points.size());
  double worst = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    SCOPED_TRACE(std::to_string(points[i].lon) + "," + std::to_string(points[i].lat));
    ASSERT_TRUE(heights[i].is(json::Value::Kind::number));
    EXPECT_EQ(levels[i].number(), max);
    const double d = std::fabs(heights[i].number() - points[i].height);
    EXPECT_LE(d, level_error(max))
        << "Cesium " << heights[i].number() << " m, TIN " << points[i].height << " m";
    worst = std::max(worst, d);
  }
  std::cout << "Cesium's heights against the TIN's at " << points.size()
            << " points: largest difference " << worst << " m (allowed " << level_error(max)
            << " m, level " << max << ")\n";
  EXPECT_GT(at(answer, "tiles").number(), 0);
  EXPECT_TRUE(at(answer, "metadata").boolean());
  // Cesium's tile requests are simple CORS requests: Access-Control-Allow-Origin is enough.
  EXPECT_EQ(at(answer, "preflights").number(), 0);
  EXPECT_TRUE(at(answer, "blocked").items().empty()) << lines_of(at(answer, "blocked"));
  EXPECT_TRUE(at(answer, "errors").items().empty()) << lines_of(at(answer, "errors"));
}

// The PNG at PATH is WIDTH x HEIGHT and not one flat colour: no colour covers half of it.
void expect_picture(const std::string& path) {
  GDALAllRegister();
  GDALDatasetUniquePtr png(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER));
  ASSERT_TRUE(png) << path;
  EXPECT_STREQ(png->GetDriver()->GetDescription(), "PNG");
  ASSERT_EQ(png->GetRasterXSize(), kWidth);
  ASSERT_EQ(png->GetRasterYSize(), kHeight);
  ASSERT_GE(png->GetRasterCount(), 3);
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(kWidth) * kHeight * 3);
  int bands[] = {1, 2, 3};
  ASSERT_EQ(png->RasterIO(GF_Read, 0, 0, kWidth, kHeight, rgb.data(), kWidth, kHeight, GDT_Byte, 3,
                          bands, 3, 3 * kWidth, 1, nullptr),
            CE_None);
  std::map<std::uint32_t, std::size_t> colours;
  for (std::size_t i = 0; i < rgb.size(); i += 3)
    ++colours[(std::uint32_t{rgb[i]} << 16) | (std::uint32_t{rgb[i + 1]} << 8) | rgb[i + 2]];
  std::size_t most = 0;
  for (const auto& [colour, n] : colours) most = std::max(most, n);
  std::cout << path << ": " << colours.size() << " colours, the commonest on " << most
            << " pixels\n";
  EXPECT_GE(colours.size(), 16u);
  EXPECT_LT(most, rgb.size() / 3 / 2);
}

// Cesium on the pyramid built in a fresh scratch folder, sample_in_browser's OPTIONS: its heights
// checked against the TIN's (expect_heights_of_tin); its answer.
json::Value sample_new_pyramid(const std::string& options) {
  const std::string dir = scratch_dir("terrain_browser");
  const int max = build_pyramid(dir);
  const auto points = probes(dir);
  const json::Value answer = sample_in_browser(dir, points, options);
  expect_heights_of_tin(answer, points, max);
  return answer;
}

TEST(TerrainBrowser, CesiumSamplesTheTinsHeightsAndDrawsIt) {
  TINCDT_REQUIRE_BROWSER();
  const std::string dir = scratch_dir("terrain_browser");
  const int max = build_pyramid(dir);
  const auto points = probes(dir);
  ASSERT_EQ(points.size(), 16u);
  const std::string png = dir + "/terrain.png";
  // Normals for the lighting; every other option is Cesium's default.
  const json::Value answer =
      sample_in_browser(dir, points,
                        "--options '{\"requestVertexNormals\":true}' --screenshot '" + png +
                            "' --size " + std::to_string(kWidth) + "x" + std::to_string(kHeight));
  expect_heights_of_tin(answer, points, max);
  EXPECT_EQ(at(answer, "gzipped").number(), 0);
  EXPECT_TRUE(at(answer, "rendered").boolean()) << "tiles still loading after 30 s";
  expect_picture(png);
  // Beyond the data the tiles ramp to the fill, the TIN's lowest: where a fine tile meets a
  // coarser one their ramps differ by less than the data's relief (with a fill of 0, by 1,000 m).
  double lowest = INFINITY, highest = -INFINITY;
  for (const auto& p : read_mesh(dir + "/full.ply").v) {
    lowest = std::min(lowest, p[2]);
    highest = std::max(highest, p[2]);
  }
  const json::Value& beyond = at(answer, "beyond");
  std::cout << "beyond the data: heights " << at(beyond, "low").number() << " to "
            << at(beyond, "high").number() << " m, largest step " << at(beyond, "step").number()
            << " m (the TIN: " << lowest << " to " << highest << " m)\n";
  EXPECT_GE(at(beyond, "low").number(), lowest - level_error(max));
  EXPECT_LE(at(beyond, "high").number(), highest + level_error(max));
  EXPECT_LT(at(beyond, "step").number(), highest - lowest);
}

// CesiumTerrainProvider.fromUrl(url) with no options: requestMetadata is on, and Cesium learns the
// tiles below each from its metadata (layer.json's metadataAvailability 1) down to the finest.
TEST(TerrainBrowser, CesiumsDefaultOptionsReadTheMetadata) {
  TINCDT_REQUIRE_BROWSER();
  sample_new_pyramid("");
}

TEST(TerrainBrowser, GzippedTilesSampleTheSame) {
  TINCDT_REQUIRE_BROWSER();
  const json::Value answer = sample_new_pyramid("--gzip");
  EXPECT_EQ(at(answer, "gzipped").number(), at(answer, "tiles").number());
}

}  // namespace
}  // namespace tincdt::test::terrain
