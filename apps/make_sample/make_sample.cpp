// tincdt_make_sample: writes the project's sample inputs into a folder.
//
//   OUTDIR/sample.las                     LAS 1.2, point format 1, EPSG:32632 as GeoTIFF keys
//   OUTDIR/sample_contours.{shp,shx,dbf,prj}  3D contour lines (ELEV) of the same terrain
//
// Everything is synthetic and deterministic: a smooth analytic terrain (a slope, a hill, a hollow
// and a gentle undulation), ground points sampled from it with a little noise, a few dozen
// "trees" whose crowns are unclassified points above the ground, and a handful of exact-xy
// duplicates as left by overlapping flight lines. The contours come from GDALContourGenerate run
// on an in-memory raster of the same terrain. Same binary, same bytes: the RNG is our own
// SplitMix64, and the DBF header date is fixed.
//
// The LAS writer is the project's synthetic-LAS writer (tests/support/las_writer.hpp, from the
// ASPRS LAS 1.2 specification), shared with the tests and benchmarks; it does not share code
// with src/io (which reads LAS), so the sample is an independent check of that reader.

#include <gdal.h>
#include <gdal_alg.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <numbers>
#include <set>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "support/las_writer.hpp"
#include "support/splitmix.hpp"

namespace {

namespace las = tincdt::test::las;

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------
// Scene definition
// ---------------------------------------------------------------------------------------------

constexpr int kEpsg = 32632;           // WGS 84 / UTM zone 32N
constexpr double kOriginX = 600200.0;  // south-west corner of the scene
constexpr double kOriginY = 5190300.0;
constexpr double kWidth = 160.0;   // metres, east-west
constexpr double kHeight = 120.0;  // metres, north-south
constexpr double kScale = 0.01;    // LAS scale, all three axes
constexpr std::array<double, 3> kOffset = {600000.0, 5190000.0, 0.0};
constexpr int kGroundPoints = 3000;  // random ground points (plus the 4 corners)
constexpr int kTrees = 36;
constexpr int kCrownPointsPerTree = 28;      // class 1, return 1 of 2
constexpr int kUnderCrownPointsPerTree = 4;  // class 2, return 2 of 2
constexpr int kDuplicates = 4;               // exact-xy copies of ground points, flight line 2
constexpr double kContourInterval = 2.0;     // metres
constexpr double kRasterResolution = 1.0;    // metres, for the contour raster
constexpr double kContourInset = 1.0;        // contours stay this far inside the point hull
constexpr std::uint64_t kSeed = 20250101;

// Bare-earth elevation at local coordinates (u, v) in metres from the south-west corner.
double terrain(double u, double v) {
  auto bump = [](double du, double dv, double sigma) {
    return std::exp(-(du * du + dv * dv) / (2.0 * sigma * sigma));
  };
  return 1480.0 + 0.06 * u + 0.04 * v             // regional slope up to the north-east
         + 16.0 * bump(u - 62.0, v - 68.0, 28.0)  // a rounded hill
         - 5.0 * bump(u - 125.0, v - 35.0, 18.0)  // a hollow
         + 1.2 * std::sin(u / 23.0) * std::cos(v / 17.0);
}

// SplitMix64, so the sample is the same everywhere.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : bits_{seed} {}
  std::uint64_t next() { return bits_.next(); }
  // Uniform in [0, 1).
  double uniform() { return bits_.unit(); }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  int uniform_int(int lo, int hi) {  // inclusive
    return lo + static_cast<int>(next() % static_cast<std::uint64_t>(hi - lo + 1));
  }
  // Standard normal by Box-Muller (one value per call; simple beats fast here).
  double normal(double sigma) {
    const double u1 = 1.0 - uniform();  // (0, 1]
    const double u2 = uniform();
    return sigma * std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
  }

 private:
  tincdt::test::SplitMix64 bits_;
};

// ---------------------------------------------------------------------------------------------
// Points
// ---------------------------------------------------------------------------------------------

using LasPoint = las::Record;  // x, y, z as stored: scaled integers

LasPoint make_point(Rng& rng, double u, double v, double z, std::uint8_t cls, std::uint8_t ret,
                    std::uint8_t nret, int intensity_lo, int intensity_hi) {
  LasPoint p;
  p.x = las::quantize(kOriginX + u, kScale, kOffset[0]);
  p.y = las::quantize(kOriginY + v, kScale, kOffset[1]);
  p.z = las::quantize(z, kScale, kOffset[2]);
  p.point_source_id = 1;  // flight line 1
  p.intensity = static_cast<std::uint16_t>(rng.uniform_int(intensity_lo, intensity_hi));
  p.return_number = ret;
  p.number_of_returns = nret;
  p.classification = cls;
  p.scan_angle = static_cast<std::int8_t>(std::lround((u / kWidth - 0.5) * 30.0));
  return p;
}

std::vector<LasPoint> make_points() {
  Rng rng(kSeed);
  std::vector<LasPoint> pts;
  constexpr double kNoise = 0.03;  // metres of vertical noise on ground returns

  // Ground: the four corners (so the hull is the whole scene), then uniform random points.
  for (const auto& [u, v] : std::array<std::array<double, 2>, 4>{
           {{0.0, 0.0}, {kWidth, 0.0}, {kWidth, kHeight}, {0.0, kHeight}}}) {
    pts.push_back(make_point(rng, u, v, terrain(u, v), 2, 1, 1, 200, 600));
  }
  for (int i = 0; i < kGroundPoints; ++i) {
    const double u = rng.uniform(0.0, kWidth);
    const double v = rng.uniform(0.0, kHeight);
    pts.push_back(make_point(rng, u, v, terrain(u, v) + rng.normal(kNoise), 2, 1, 1, 200, 600));
  }

  // Trees: crown returns above the ground (class 1, first of two), ground below them (last of two).
  for (int t = 0; t < kTrees; ++t) {
    const double cu = rng.uniform(6.0, kWidth - 6.0);
    const double cv = rng.uniform(6.0, kHeight - 6.0);
    const double radius = rng.uniform(2.0, 4.0);
    const double height = rng.uniform(6.0, 18.0);
    auto in_disk = [&](double& u, double& v) {
      const double r = radius * std::sqrt(rng.uniform());
      const double a = 2.0 * std::numbers::pi * rng.uniform();
      u = cu + r * std::cos(a);
      v = cv + r * std::sin(a);
      return r;
    };
    for (int k = 0; k < kCrownPointsPerTree; ++k) {
      double u = 0.0, v = 0.0;
      const double r = in_disk(u, v);
      const double above = height * (1.0 - 0.6 * (r / radius) * (r / radius)) + rng.normal(0.3);
      pts.push_back(make_point(rng, u, v, terrain(u, v) + above, 1, 1, 2, 40, 300));
    }
    for (int k = 0; k < kUnderCrownPointsPerTree; ++k) {
      double u = 0.0, v = 0.0;
      in_disk(u, v);
      pts.push_back(make_point(rng, u, v, terrain(u, v) + rng.normal(kNoise), 2, 2, 2, 100, 400));
    }
  }

  // Random points may share a 1 cm cell by chance; nudge such a point 1 cm east so that the only
  // exact-xy duplicates are the deliberate ones below.
  std::set<std::pair<std::int32_t, std::int32_t>> used;
  for (LasPoint& p : pts) {
    while (!used.emplace(p.x, p.y).second) ++p.x;
  }

  // Overlap: a few ground points seen again from flight line 2, same x/y, slightly other z.
  std::set<int> picked;
  while (static_cast<int>(picked.size()) < kDuplicates) {
    const int index = rng.uniform_int(4, kGroundPoints + 3);  // a random ground point
    if (!picked.insert(index).second) continue;
    LasPoint p = pts[static_cast<std::size_t>(index)];
    p.z += static_cast<std::int32_t>(rng.uniform_int(1, 6));  // +1..6 cm
    p.point_source_id = 2;
    p.intensity = static_cast<std::uint16_t>(rng.uniform_int(200, 600));
    pts.push_back(p);
  }

  // Along-track order, as an aircraft flying north records them; GPS time follows that order.
  std::sort(pts.begin(), pts.end(), [](const LasPoint& a, const LasPoint& b) {
    if (a.y != b.y) return a.y < b.y;
    if (a.x != b.x) return a.x < b.x;
    if (a.z != b.z) return a.z < b.z;
    return a.point_source_id < b.point_source_id;
  });
  for (std::size_t i = 0; i < pts.size(); ++i) {
    pts[i].gps_time = 305000.0 + static_cast<double>(i) * 2.5e-4;
  }
  return pts;
}

// ---------------------------------------------------------------------------------------------
// LAS 1.2, point format 1, with one GeoKeyDirectoryTag record
// ---------------------------------------------------------------------------------------------

struct LasSummary {
  std::map<int, std::size_t> classes;
  std::array<double, 6> bounds{};  // min x, min y, min z, max x, max y, max z
};

LasSummary write_las(const fs::path& path, const std::vector<LasPoint>& pts) {
  las::Header header;
  header.point_format = 1;
  header.software = "tincdt_make_sample";
  header.scale = {kScale, kScale, kScale};
  header.offset = kOffset;
  header.geokeys = {
      {1024, 0, 1, 1},                                  // GTModelTypeGeoKey = ModelTypeProjected
      {1025, 0, 1, 1},                                  // GTRasterTypeGeoKey = RasterPixelIsArea
      {3072, 0, 1, static_cast<std::uint16_t>(kEpsg)},  // ProjectedCSTypeGeoKey
      {3076, 0, 1, 9001},                               // ProjLinearUnitsGeoKey = metre
      {4099, 0, 1, 9001},                               // VerticalUnitsGeoKey = metre
  };
  const std::string bytes = las::file(header, pts);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) throw std::runtime_error("cannot write " + path.string());

  const las::Header h = las::summarize(header, pts);
  LasSummary summary;
  for (const LasPoint& p : pts) ++summary.classes[p.classification];
  summary.bounds = {h.min[0], h.min[1], h.min[2], h.max[0], h.max[1], h.max[2]};
  return summary;
}

// ---------------------------------------------------------------------------------------------
// Contours: an in-memory raster of the terrain, GDALContourGenerate into a 3D shapefile layer.
// ---------------------------------------------------------------------------------------------

struct ContourSummary {
  long features = 0;
  double min_level = 0.0, max_level = 0.0;
};

[[noreturn]] void gdal_fail(const std::string& what) {
  throw std::runtime_error(what + ": " + CPLGetLastErrorMsg());
}

ContourSummary write_contours(const fs::path& shp) {
  // The raster covers the scene less kContourInset on every side, so that every contour vertex
  // lies strictly inside the hull of the LAS points (GDAL's contours reach the raster's edge).
  const double width = kWidth - 2.0 * kContourInset;
  const double height = kHeight - 2.0 * kContourInset;
  const int nx = static_cast<int>(std::lround(width / kRasterResolution));
  const int ny = static_cast<int>(std::lround(height / kRasterResolution));
  GDALDriverH mem = GDALGetDriverByName("MEM");
  GDALDriverH shape = GDALGetDriverByName("ESRI Shapefile");
  if (mem == nullptr || shape == nullptr) gdal_fail("GDAL drivers MEM / ESRI Shapefile missing");

  GDALDatasetH raster = GDALCreate(mem, "", nx, ny, 1, GDT_Float64, nullptr);
  if (raster == nullptr) gdal_fail("cannot create the in-memory raster");
  // North-up, row 0 at the top; each pixel holds the terrain at its centre.
  double transform[6] = {
      kOriginX + kContourInset, kRasterResolution, 0.0, kOriginY + kContourInset + height, 0.0,
      -kRasterResolution};
  GDALSetGeoTransform(raster, transform);
  std::vector<double> cells(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny));
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const double u = kContourInset + (i + 0.5) * kRasterResolution;
      const double v = kContourInset + height - (j + 0.5) * kRasterResolution;
      cells[static_cast<std::size_t>(j) * static_cast<std::size_t>(nx) +
            static_cast<std::size_t>(i)] = terrain(u, v);
    }
  }
  GDALRasterBandH band = GDALGetRasterBand(raster, 1);
  if (GDALRasterIO(band, GF_Write, 0, 0, nx, ny, cells.data(), nx, ny, GDT_Float64, 0, 0) !=
      CE_None) {
    gdal_fail("cannot fill the in-memory raster");
  }

  // Replace any previous shapefile (and its sidecars) as a whole.
  for (const char* ext : {".shp", ".shx", ".dbf", ".prj", ".cpg", ".qix"}) {
    fs::path sidecar = shp;
    sidecar.replace_extension(ext);
    std::error_code ec;
    fs::remove(sidecar, ec);
  }
  GDALDatasetH vector = GDALCreate(shape, shp.c_str(), 0, 0, 0, GDT_Unknown, nullptr);
  if (vector == nullptr) gdal_fail("cannot create " + shp.string());

  OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
  if (OSRImportFromEPSG(srs, kEpsg) != OGRERR_NONE) gdal_fail("cannot build EPSG:32632");
  OSRSetAxisMappingStrategy(srs, OAMS_TRADITIONAL_GIS_ORDER);
  const char* layer_options[] = {"DBF_DATE_LAST_UPDATE=2025-01-01", nullptr};
  OGRLayerH layer =
      GDALDatasetCreateLayer(vector, shp.stem().c_str(), srs, wkbLineString25D,
                             const_cast<char**>(layer_options));  // GDAL's C API is not const
  OSRRelease(srs);
  if (layer == nullptr) gdal_fail("cannot create the contour layer");

  OGRFieldDefnH id_field = OGR_Fld_Create("ID", OFTInteger);
  OGR_Fld_SetWidth(id_field, 8);
  OGRFieldDefnH elev_field = OGR_Fld_Create("ELEV", OFTReal);
  OGR_Fld_SetWidth(elev_field, 12);
  OGR_Fld_SetPrecision(elev_field, 3);
  const bool fields_ok = OGR_L_CreateField(layer, id_field, TRUE) == OGRERR_NONE &&
                         OGR_L_CreateField(layer, elev_field, TRUE) == OGRERR_NONE;
  OGR_Fld_Destroy(id_field);
  OGR_Fld_Destroy(elev_field);
  if (!fields_ok) gdal_fail("cannot create the ID / ELEV fields");

  // A 3D layer makes GDAL give every vertex Z = the contour level.
  if (GDALContourGenerate(band, kContourInterval, 0.0, 0, nullptr, FALSE, 0.0, layer, 0, 1,
                          GDALDummyProgress, nullptr) != CE_None) {
    gdal_fail("GDALContourGenerate failed");
  }

  ContourSummary summary;
  summary.min_level = HUGE_VAL;
  summary.max_level = -HUGE_VAL;
  OGR_L_ResetReading(layer);
  while (OGRFeatureH feature = OGR_L_GetNextFeature(layer)) {
    const double level = OGR_F_GetFieldAsDouble(feature, 1);
    summary.min_level = std::min(summary.min_level, level);
    summary.max_level = std::max(summary.max_level, level);
    ++summary.features;
    OGR_F_Destroy(feature);
  }
  GDALClose(vector);
  GDALClose(raster);
  return summary;
}

int run(const fs::path& outdir) {
  if (!fs::is_directory(outdir)) {
    std::cerr << "tincdt_make_sample: " << outdir.string() << ": not a directory\n";
    return 1;
  }
  const std::vector<LasPoint> pts = make_points();
  const fs::path las = outdir / "sample.las";
  const LasSummary ls = write_las(las, pts);
  std::printf("wrote %s: %zu points (", las.string().c_str(), pts.size());
  const char* sep = "";
  for (const auto& [cls, n] : ls.classes) {
    std::printf("%sclass %d: %zu", sep, cls, n);
    sep = ", ";
  }
  std::printf("), EPSG:%d\n  x %.2f..%.2f  y %.2f..%.2f  z %.2f..%.2f\n", kEpsg, ls.bounds[0],
              ls.bounds[3], ls.bounds[1], ls.bounds[4], ls.bounds[2], ls.bounds[5]);

  const fs::path shp = outdir / "sample_contours.shp";
  const ContourSummary cs = write_contours(shp);
  std::printf("wrote %s: %ld contour lines, ELEV %.0f..%.0f every %.0f m, EPSG:%d\n",
              shp.string().c_str(), cs.features, cs.min_level, cs.max_level, kContourInterval,
              kEpsg);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string_view usage =
      "usage: tincdt_make_sample OUTDIR\n"
      "Writes OUTDIR/sample.las and OUTDIR/sample_contours.{shp,shx,dbf,prj}, the synthetic\n"
      "sample inputs of tincdt (deterministic: the same bytes on every run).\n";
  if (argc == 2 && (std::string_view(argv[1]) == "-h" || std::string_view(argv[1]) == "--help")) {
    std::cout << usage;
    return 0;
  }
  if (argc != 2) {
    std::cerr << usage;
    return 2;
  }
  GDALAllRegister();
  int rc = 1;
  try {
    rc = run(argv[1]);
  } catch (const std::exception& e) {
    std::cerr << "tincdt_make_sample: " << e.what() << '\n';
    rc = 1;
  }
  GDALDestroyDriverManager();
  OSRCleanup();
  return rc;
}
