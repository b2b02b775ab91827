// Vector sources through the whole job: byte 0 picks what the rest, a GeoJSON document read by
// the OGR readers from GDAL's /vsimem/, is given as (contours, hard lines, soft lines, clip,
// erase, replace polygons, or two of these), the restoration, the crossing rule and a few
// options; pipeline::build() then runs the constraint, surface and terrain stages on a small
// grid of points spread over the middle of the features' extent (so that they stick out of its
// hull) and validates the TIN. A finding is a crash, a sanitizer report or an internal error
// (a TIN that fails validation is one).
//
// To see a finding with the tool: TINCDT_FUZZ_KEEP=DIR vector_fuzz_replay FILE keeps the points
// and the document in DIR and prints the equivalent tincdt command.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "core/coordinates.hpp"
#include "core/error.hpp"
#include "fuzz/fuzz_support.hpp"
#include "io/gdal_support.hpp"
#include "pipeline/build.hpp"

namespace {

namespace fs = std::filesystem;
using namespace tincdt;

const char* const kVector = "/vsimem/vector_fuzz.geojson";

const char* keep_dir() {
  return std::getenv("TINCDT_FUZZ_KEEP");
}

// A scratch folder for the points and the outputs, removed at exit (unless kept).
const fs::path& scratch() {
  static const fs::path dir = [] {
    if (keep_dir() != nullptr) {
      fs::create_directories(keep_dir());
      return fs::path(keep_dir());
    }
    const fs::path base =
        fs::is_directory("/dev/shm") ? fs::path("/dev/shm") : fs::temp_directory_path();
    fs::path d = base / ("tincdt_vector_fuzz_" + std::to_string(::getpid()));
    fs::create_directories(d);
    std::atexit([] {
      std::error_code ec;
      fs::remove_all(scratch(), ec);
    });
    return d;
  }();
  return dir;
}

// The tincdt command that runs the same job (for TINCDT_FUZZ_KEEP).
std::string command_of(const pipeline::BuildOptions& o, const std::string& document) {
  std::string c = "tincdt";
  for (const std::string& in : o.inputs) c += " " + in;
  const std::pair<const std::vector<std::string>*, const char*> lists[] = {
      {&o.contours, "--contours"}, {&o.breaklines, "--hard-lines"}, {&o.soft_lines, "--soft-lines"},
      {&o.clip, "--clip"},         {&o.erase, "--erase"},           {&o.replace, "--replace"}};
  for (const auto& [list, flag] : lists)
    if (!list->empty()) c += std::string(" ") + flag + " " + document;
  const char* const restore[] = {"delaunay", "aspect", "none"};
  c += std::string(" --restore ") + restore[static_cast<int>(o.constraint.restore)];
  if (o.constraint.on_crossing == constraints::OnCrossing::error) c += " --on-crossing error";
  if (o.fix_flats) c += " --fix-flats";
  if (o.max_edge > 0) c += " --max-edge " + std::to_string(o.max_edge);
  return c + " --validate --overwrite -o " + o.output;
}

// The features' extent, from every layer GDAL sees in the document; false when there is none.
bool extent_of(double& x0, double& y0, double& x1, double& y1) {
  io::detail::register_gdal_drivers();
  const io::detail::GdalQuiet quiet;
  const io::detail::GdalDataset ds(GDALDataset::Open(kVector, GDAL_OF_VECTOR | GDAL_OF_READONLY));
  if (!ds) return false;
  bool any = false;
  for (OGRLayer* layer : ds->GetLayers()) {
    OGREnvelope e;
    if (layer->GetExtent(&e, TRUE) != OGRERR_NONE) continue;
    if (!any) {
      x0 = e.MinX, y0 = e.MinY, x1 = e.MaxX, y1 = e.MaxY;
      any = true;
    } else {
      x0 = std::min(x0, e.MinX), y0 = std::min(y0, e.MinY);
      x1 = std::max(x1, e.MaxX), y1 = std::max(y1, e.MaxY);
    }
  }
  const double limit = 1e14;  // points must stay readable: the grid is clamped well inside
  if (!any || !std::isfinite(x0 + y0 + x1 + y1)) return false;
  x0 = std::clamp(x0, -limit, limit), x1 = std::clamp(x1, -limit, limit);
  y0 = std::clamp(y0, -limit, limit), y1 = std::clamp(y1, -limit, limit);
  return true;
}

// A jittered 7 x 7 grid over the middle 70% of the extent, on a tilted, bumpy surface.
std::string grid_points(double x0, double y0, double x1, double y1) {
  double w = x1 - x0, h = y1 - y0;
  if (!(w > 0)) w = 2, x0 -= 1;
  if (!(h > 0)) h = 2, y0 -= 1;
  std::string text;
  char line[128];
  std::uint32_t state = 2463534242u;
  constexpr int n = 6;
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= n; ++j) {
      state ^= state << 13, state ^= state >> 17, state ^= state << 5;
      const double jx = (i > 0 && i < n) ? (state % 1000) / 1000.0 - 0.5 : 0;
      const double jy = (j > 0 && j < n) ? ((state >> 10) % 1000) / 1000.0 - 0.5 : 0;
      const double u = 0.15 + 0.7 * (i + 0.3 * jx) / n, v = 0.15 + 0.7 * (j + 0.3 * jy) / n;
      const double z = 100 + 20 * u - 10 * v + 3 * std::sin(7 * u) * std::cos(5 * v);
      std::snprintf(line, sizeof line, "%.17g %.17g %.17g\n", x0 + u * w, y0 + v * h, z);
      text += line;
    }
  }
  return text;
}

void write_file(const fs::path& path, const std::string& text) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr || std::fwrite(text.data(), 1, text.size(), f) != text.size()) std::abort();
  std::fclose(f);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::uint8_t mode = data[0];
  VSILFILE* mem = VSIFileFromMemBuffer(kVector, const_cast<GByte*>(data + 1), size - 1, FALSE);
  if (mem == nullptr) std::abort();
  VSIFCloseL(mem);

  pipeline::BuildOptions o;
  const std::string vector = kVector;
  switch (mode & 7) {
    case 0:
      o.contours = {vector};
      break;
    case 1:
      o.breaklines = {vector};
      break;
    case 2:
      o.soft_lines = {vector};
      break;
    case 3:
      o.clip = {vector};
      break;
    case 4:
      o.erase = {vector};
      break;
    case 5:
      o.replace = {vector};
      break;
    case 6:
      o.contours = {vector}, o.clip = {vector};
      break;
    default:
      o.breaklines = {vector}, o.erase = {vector};
      break;
  }
  const int restore = (mode >> 3) & 3;
  o.constraint.restore = restore == 1   ? constraints::Restore::aspect
                         : restore == 2 ? constraints::Restore::none
                                        : constraints::Restore::delaunay;
  o.constraint.on_crossing =
      (mode & 0x20) != 0 ? constraints::OnCrossing::error : constraints::OnCrossing::split;
  const bool lines_alone = (mode & 0x40) != 0 && (!o.contours.empty() || !o.breaklines.empty());
  double x0 = 0, y0 = 0, x1 = 100, y1 = 100;
  extent_of(x0, y0, x1, y1);
  if (!lines_alone) {
    const fs::path points = scratch() / "points.xyz";
    write_file(points, grid_points(x0, y0, x1, y1));
    o.inputs = {points.string()};
  }
  if ((mode & 0x80) != 0) {
    if (!o.contours.empty()) {
      o.fix_flats = true;
    } else {
      o.max_edge = std::max(x1 - x0, y1 - y0) / 5;
    }
  }
  o.output = (scratch() / "tin.ply").string();
  o.write.overwrite = true;
  o.validate = true;
  if (keep_dir() != nullptr) {
    const fs::path document = scratch() / "vector.geojson";
    write_file(document, std::string(reinterpret_cast<const char*>(data + 1), size - 1));
    std::fprintf(stderr, "%s\n", command_of(o, document.string()).c_str());
  }
  try {
    pipeline::build(o);
  } catch (const Error& e) {
    fuzz::check_not_internal(e);
  }
  VSIUnlink(kVector);
  return 0;
}
