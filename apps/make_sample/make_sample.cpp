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
// The LAS writer is our own, from the ASPRS LAS 1.2 specification; it does not share code with
// src/io (which reads LAS), so the sample is an independent check of that reader.

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
#include <type_traits>
#include <utility>
#include <vector>

namespace {

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

// SplitMix64: tiny, well-mixed and fully specified, so the sample is the same everywhere.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }
  // Uniform in [0, 1).
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
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
  std::uint64_t state_;
};

// ---------------------------------------------------------------------------------------------
// Points
// ---------------------------------------------------------------------------------------------

struct LasPoint {
  std::int32_t x = 0, y = 0, z = 0;  // scaled integers, as stored
  std::uint16_t intensity = 0;
  std::uint8_t return_number = 1;
  std::uint8_t number_of_returns = 1;
  std::uint8_t classification = 2;
  std::int8_t scan_angle = 0;
  std::uint16_t point_source_id = 1;
  double gps_time = 0.0;
};

std::int32_t quantize(double value, double offset) {
  const double scaled = std::round((value - offset) / kScale);
  if (!(scaled >= -2147483648.0 && scaled <= 2147483647.0)) {
    throw std::runtime_error("coordinate out of LAS int32 range");
  }
  return static_cast<std::int32_t>(scaled);
}

LasPoint make_point(Rng& rng, double u, double v, double z, std::uint8_t cls, std::uint8_t ret,
                    std::uint8_t nret, int intensity_lo, int intensity_hi) {
  LasPoint p;
  p.x = quantize(kOriginX + u, kOffset[0]);
  p.y = quantize(kOriginY + v, kOffset[1]);
  p.z = quantize(z, kOffset[2]);
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
// LAS 1.2 writer (ASPRS LAS Specification 1.2, 2008): public header block (227 bytes), one
// GeoKeyDirectoryTag VLR, point data records of format 1 (28 bytes each). Little-endian.
// ---------------------------------------------------------------------------------------------

class ByteWriter {
 public:
  template <typename T>
  void put(T value) {
    static_assert(std::is_integral_v<T>);
    using U = std::make_unsigned_t<T>;
    const auto bits = static_cast<U>(value);
    for (std::size_t i = 0; i < sizeof(T); ++i) {
      bytes_.push_back(static_cast<char>((bits >> (8 * i)) & 0xFFu));
    }
  }
  void put_double(double value) {
    std::uint64_t bits = 0;
    static_assert(sizeof bits == sizeof value);
    std::memcpy(&bits, &value, sizeof bits);
    put(bits);
  }
  void put_chars(std::string_view text, std::size_t width) {  // NUL-padded, truncated to width
    for (std::size_t i = 0; i < width; ++i) bytes_.push_back(i < text.size() ? text[i] : '\0');
  }
  std::size_t size() const { return bytes_.size(); }
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

struct LasSummary {
  std::map<int, std::size_t> classes;
  std::array<double, 6> bounds{};  // min x, min y, min z, max x, max y, max z
};

LasSummary write_las(const fs::path& path, const std::vector<LasPoint>& pts) {
  // GeoKeyDirectoryTag: header {version 1, revision 1.0, key count} + sorted key entries
  // {KeyID, TIFFTagLocation (0 = value inline), Count, Value}.
  const std::vector<std::array<std::uint16_t, 4>> keys = {
      {1024, 0, 1, 1},                                  // GTModelTypeGeoKey = ModelTypeProjected
      {1025, 0, 1, 1},                                  // GTRasterTypeGeoKey = RasterPixelIsArea
      {3072, 0, 1, static_cast<std::uint16_t>(kEpsg)},  // ProjectedCSTypeGeoKey
      {3076, 0, 1, 9001},                               // ProjLinearUnitsGeoKey = metre
      {4099, 0, 1, 9001},                               // VerticalUnitsGeoKey = metre
  };
  ByteWriter geokeys;
  geokeys.put<std::uint16_t>(1);
  geokeys.put<std::uint16_t>(1);
  geokeys.put<std::uint16_t>(0);
  geokeys.put(static_cast<std::uint16_t>(keys.size()));
  for (const auto& key : keys) {
    for (const std::uint16_t field : key) geokeys.put(field);
  }

  constexpr std::uint16_t kHeaderSize = 227;
  constexpr std::uint16_t kVlrHeaderSize = 54;
  constexpr std::uint8_t kPointFormat = 1;
  constexpr std::uint16_t kPointRecordLength = 28;
  const auto offset_to_points =
      static_cast<std::uint32_t>(kHeaderSize + kVlrHeaderSize + geokeys.size());

  LasSummary summary;
  std::array<std::uint32_t, 5> by_return{};
  std::array<double, 3> lo{HUGE_VAL, HUGE_VAL, HUGE_VAL};
  std::array<double, 3> hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (const LasPoint& p : pts) {
    const std::array<std::int32_t, 3> xyz{p.x, p.y, p.z};
    for (std::size_t a = 0; a < 3; ++a) {
      const double value = xyz[a] * kScale + kOffset[a];  // exactly what a reader computes
      lo[a] = std::min(lo[a], value);
      hi[a] = std::max(hi[a], value);
    }
    ++by_return[p.return_number - 1u];
    ++summary.classes[p.classification];
  }
  summary.bounds = {lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]};

  ByteWriter w;
  // Public header block.
  w.put_chars("LASF", 4);                               // file signature
  w.put<std::uint16_t>(0);                              // file source ID
  w.put<std::uint16_t>(0);                              // global encoding: GPS week time
  for (int i = 0; i < 16; ++i) w.put<std::uint8_t>(0);  // project ID (GUID)
  w.put<std::uint8_t>(1);                               // version major
  w.put<std::uint8_t>(2);                               // version minor
  w.put_chars("OTHER", 32);                             // system identifier: synthetic data
  w.put_chars("tincdt_make_sample", 32);                // generating software
  w.put<std::uint16_t>(1);     // creation day of year (fixed: reproducible)
  w.put<std::uint16_t>(2025);  // creation year
  w.put(kHeaderSize);
  w.put(offset_to_points);
  w.put<std::uint32_t>(1);  // number of VLRs
  w.put(kPointFormat);
  w.put(kPointRecordLength);
  w.put(static_cast<std::uint32_t>(pts.size()));
  for (const std::uint32_t n : by_return) w.put(n);
  for (int a = 0; a < 3; ++a) w.put_double(kScale);
  for (const double o : kOffset) w.put_double(o);
  for (std::size_t a = 0; a < 3; ++a) {  // max X, min X, max Y, min Y, max Z, min Z
    w.put_double(hi[a]);
    w.put_double(lo[a]);
  }
  if (w.size() != kHeaderSize) throw std::logic_error("LAS header size mismatch");

  // Variable length record: LASF_Projection / 34735 (GeoKeyDirectoryTag).
  w.put<std::uint16_t>(0);  // reserved
  w.put_chars("LASF_Projection", 16);
  w.put<std::uint16_t>(34735);
  w.put(static_cast<std::uint16_t>(geokeys.size()));
  w.put_chars("GeoTIFF GeoKeyDirectoryTag", 32);
  for (const char c : geokeys.bytes()) w.put(static_cast<std::uint8_t>(c));
  if (w.size() != offset_to_points) throw std::logic_error("LAS VLR size mismatch");

  // Point data records, format 1.
  for (const LasPoint& p : pts) {
    w.put(p.x);
    w.put(p.y);
    w.put(p.z);
    w.put(p.intensity);
    // return number (bits 0-2), number of returns (3-5), scan direction (6), edge of line (7)
    w.put(static_cast<std::uint8_t>(p.return_number | (p.number_of_returns << 3)));
    w.put(p.classification);  // class in bits 0-4; synthetic/key-point/withheld flags clear
    w.put(p.scan_angle);
    w.put<std::uint8_t>(0);  // user data
    w.put(p.point_source_id);
    w.put_double(p.gps_time);
  }
  if (w.size() != offset_to_points + pts.size() * kPointRecordLength) {
    throw std::logic_error("LAS point record size mismatch");
  }

  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(w.bytes().data(), static_cast<std::streamsize>(w.size()));
  out.close();
  if (!out) throw std::runtime_error("cannot write " + path.string());
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
