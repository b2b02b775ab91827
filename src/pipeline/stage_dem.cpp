// dem: --dem, the final TIN rasterized (products::rasterize) and written with the TIN's CRS in
// the raster format of the file's extension or --dem-format (.tif: a Cloud-Optimized GeoTIFF):
// Float32 cells, or Float64 with --dem-type Float64.
//
// The job's caller may fix the grid (Job::dem_grid) and have the cells filled from removed
// triangles too (Job::dem_extra_triangles, put back while the DEM is rasterized).
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "io/raster/dem_writer.hpp"
#include "pipeline/dem_grid.hpp"
#include "pipeline/stage.hpp"
#include "products/rasterize.hpp"
#include "products/short_number.hpp"

namespace tincdt::pipeline {
namespace {

bool wanted(const BuildOptions& o) {
  return !o.dem.path.empty();
}

// The machine's memory in bytes, 0 if unknown.
std::uint64_t physical_memory() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0
             ? static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page)
             : 0;
}

using products::short_number;

// The smallest DEM that is one: fewer cells than 2 x 2 is a resolution in the wrong unit (metres
// taken as degrees) or a typo, not a terrain model.
constexpr std::size_t kMinDemCells = 4;

// "metre" units, for a message: the CRS's unit, or what is known of it.
std::string unit_text(const std::string& crs_wkt) {
  const std::string unit = io::crs_unit_name(crs_wkt);
  if (!unit.empty()) return unit;
  return crs_wkt.empty() ? "units of the coordinates (no CRS)" : "units of the CRS";
}

// Refuses a grid of fewer than kMinDemCells cells, naming the resolution, the extent and the
// CRS's unit.
void check_enough_cells(const BuildOptions::Dem& o, const products::Grid& grid, const BBox& extent,
                        const std::string& crs_wkt) {
  if (grid.cells() >= kMinDemCells) return;
  const std::string unit = unit_text(crs_wkt);
  throw OutputError(o.path, "",
                    "a resolution of " + short_number(o.resolution) + " " + unit +
                        " over the extent " + short_number(extent.min_x) + " " +
                        short_number(extent.min_y) + " " + short_number(extent.max_x) + " " +
                        short_number(extent.max_y) + " (" +
                        short_number(extent.max_x - extent.min_x) + " x " +
                        short_number(extent.max_y - extent.min_y) + " " + unit + ") gives " +
                        count_text(grid.width) + " x " + count_text(grid.height) +
                        " cells; a DEM needs at least 2 x 2 (the resolution is in the CRS's unit)");
}

// The grid is held whole (GDAL writes it from there) with its overviews (a third more): refuse
// one that would not fit in the machine's memory rather than fail in the allocator or swap.
void check_fits_in_memory(const BuildOptions::Dem& o, const products::Grid& grid,
                          std::size_t cell_bytes) {
  const double bytes = static_cast<double>(grid.cells()) * static_cast<double>(cell_bytes) * 4 / 3;
  const std::uint64_t memory = physical_memory();
  if (memory == 0 || bytes <= static_cast<double>(memory)) return;
  constexpr double kGiB = 1024.0 * 1024 * 1024;
  throw OutputError(o.path, "",
                    "a DEM of " + count_text(grid.width) + " x " + count_text(grid.height) +
                        " cells of " + short_number(o.resolution) + " needs about " +
                        short_number(bytes / kGiB) + " GiB (" + count_text(cell_bytes) +
                        " bytes a cell, a third more for the overviews), more than this "
                        "machine's memory (" +
                        short_number(static_cast<double>(memory) / kGiB) +
                        " GiB): give a coarser resolution or a smaller extent");
}

// The grid over EXTENT, with the checks every DEM gets: a resolution fine enough for distinct
// cell centres and at most 2^31 - 1 columns and rows (grid_over), at least 2 x 2 cells.
products::Grid checked_grid(const BuildOptions::Dem& o, const BBox& extent,
                            const std::string& crs_wkt) {
  products::Grid grid;
  try {
    grid = products::grid_over(extent, o.resolution, o.target_aligned);
  } catch (const Error& e) {
    throw OutputError(o.path, "", e.detail());
  }
  check_enough_cells(o, grid, extent, crs_wkt);
  return grid;
}

template <class T>
void rasterize_and_write(Job& job, const products::Grid& grid, io::OutputFile& out) {
  const BuildOptions::Dem& o = job.options.dem;
  BuildReport::Dem& r = job.report.dem;
  auto t0 = std::chrono::steady_clock::now();
  std::vector<T> cells(grid.cells());
  // The extra triangles are back while the DEM rasterizes (the outputs after this stage see them
  // removed again).
  products::RasterizeStats stats;
  job.with_extra_triangles([&] {
    stats =
        products::rasterize<T>(job.tin(), grid, static_cast<T>(o.nodata_or_default()), cells,
                               {.threads = job.options.threads, .progress = job.stage_progress()});
  });
  r.cells_with_value = stats.cells_with_value;
  r.rasterize_s = seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  io::DemWriteOptions w;
  w.format = o.format;
  w.nodata = o.nodata_or_default();
  w.crs_wkt = job.crs_wkt;
  w.creation_options = o.creation_options;
  w.threads = job.options.threads;
  w.progress = job.stage_progress();
  std::vector<io::OutputFile*> siblings;
  r.driver = io::write_dem(out, grid, std::span<const T>(cells), w,
                           [&](const std::string& path) -> io::OutputFile& {
                             siblings.push_back(&job.add_output(path, "dem"));
                             return *siblings.back();
                           })
                 .driver;
  job.finish_output(out);
  for (io::OutputFile* s : siblings) job.finish_output(*s);
  r.write_s = seconds_since(t0);
}

void run(Job& job) {
  const BuildOptions::Dem& o = job.options.dem;
  products::Grid grid;
  if (job.dem_grid) {
    grid = *job.dem_grid;
  } else {
    grid = checked_grid(o, o.extent ? *o.extent : products::kept_extent(job.tin()), job.crs_wkt);
  }
  check_fits_in_memory(o, grid, o.float64() ? sizeof(double) : sizeof(float));
  BuildReport::Dem& r = job.report.dem;
  r.path = o.path;
  r.type = o.float64() ? "Float64" : "Float32";
  r.width = grid.width;
  r.height = grid.height;
  r.resolution = grid.resolution;
  r.min_x = grid.min_x;
  r.max_y = grid.max_y;
  io::OutputFile& out = job.add_output(o.path, "dem");
  if (o.float64())
    rasterize_and_write<double>(job, grid, out);
  else
    rasterize_and_write<float>(job, grid, out);
  job.info("DEM: " + count_text(grid.width) + " x " + count_text(grid.height) + " cells, " +
           count_text(r.cells_with_value) + " with a value");
}

}  // namespace

// Without --dem-extent the DEM covers the kept triangles, whose extent is the points' unless
// clip, erase or trim remove some. The grid over the points' extent is then the DEM's, and one
// too fine, too large or too coarse is refused before the Delaunay stage. When triangles may be
// removed only a grid too coarse there is sure to be one at the end; the rest waits for the TIN.
void check_dem_grid_early(const Job& job) {
  const BuildOptions::Dem& o = job.options.dem;
  if (o.path.empty() || job.dem_grid) return;
  BBox extent;
  if (o.extent) {
    extent = *o.extent;
  } else {
    for (const Point3& p : job.points) extent.add(p.x, p.y);
    if (!(extent.min_x <= extent.max_x)) return;  // no points: the Delaunay stage says so
  }
  const BuildOptions& options = job.options;
  if (!o.extent && (!options.clip.empty() || !options.erase.empty() || options.max_edge > 0)) {
    products::Grid largest;
    try {
      largest = products::grid_over(extent, o.resolution, o.target_aligned);
    } catch (const Error&) {
      return;
    }
    check_enough_cells(o, largest, extent, job.crs_wkt);
    return;
  }
  const products::Grid grid = checked_grid(o, extent, job.crs_wkt);
  check_fits_in_memory(o, grid, o.float64() ? sizeof(double) : sizeof(float));
}

namespace {

// The further files of the format (an ASCII grid's .prj) are planned with it, so that an
// existing one stops the job before any work.
void plan(const BuildOptions& o, FilePlan& files) {
  files.outputs.push_back({o.dem.path, "the DEM (--dem)"});
  std::string driver;
  try {
    driver = io::dem_driver_for(o.dem.path, o.dem.format, o.dem.float64());
  } catch (const Error&) {
    return;  // check_options() refused it already; the writer would again
  }
  for (const std::string& side : io::dem_side_files(o.dem.path, driver))
    files.outputs.push_back({side, "a file of the DEM (--dem)"});
}

// ---- options -----------------------------------------------------------------------------------

constexpr std::string_view kCellTypes[] = {"float32", "float64"};
constexpr bool kIsFloat64[] = {false, true};

// "XMIN YMIN XMAX YMAX", each checked a number.
BBox parse_extent(std::string_view text) {
  double v[4] = {0, 0, 0, 0};
  for (double& d : v) {
    const std::size_t space = text.find(' ');
    d = parse_number(text.substr(0, space)).value_or(0);
    text.remove_prefix(space == std::string_view::npos ? text.size() : space + 1);
  }
  BBox box;
  box.min_x = v[0];
  box.min_y = v[1];
  box.max_x = v[2];
  box.max_y = v[3];
  return box;
}

using Dem = BuildOptions::Dem;

std::string check_nodata(std::string_view v) {
  return lower(v) == "nan" ? std::string() : check_number(v);
}

void set_nodata(BuildOptions& o, std::string_view v) {
  o.dem.nodata = lower(v) == "nan" ? std::nan("") : *parse_number(v);
}

constexpr OptionSpec kOptions[] = {
    text_option("--dem", "FILE", option_groups::products, set_text<&BuildOptions::dem, &Dem::path>,
                "Rasterize the TIN: each cell centre gets its triangle's linear\n"
                "interpolation, nodata outside (needs --resolution); the format by\n"
                "extension: .tif Cloud-Optimized GeoTIFF, .asc, .img, .nc, ..."),
    text_option("--dem-format", "DRIVER", option_groups::products,
                set_text<&BuildOptions::dem, &Dem::format>,
                "The DEM's GDAL raster driver, as gdal_translate -of (COG, GTiff,\n"
                "AAIGrid, HFA, ...), over the extension's"),
    checked_option("--resolution", "R", option_groups::products, check_positive,
                   set_number<&BuildOptions::dem, &Dem::resolution>,
                   "DEM cell size, in the CRS's units"),
    {.flags = "--dem-extent",
     .value_name = "XMIN YMIN XMAX YMAX",
     .help = "DEM extent (default: the TIN's)",
     .group = option_groups::products,
     .arity = 4,
     .check = check_number,
     .set = [](BuildOptions& o, std::string_view v) { o.dem.extent = parse_extent(v); }},
    flag_option("--tap", option_groups::products,
                set_true<&BuildOptions::dem, &Dem::target_aligned>,
                "Snap the DEM extent out to multiples of the resolution (as gdalwarp -tap)"),
    with_default(checked_option("--dem-nodata", "V", option_groups::products, check_nodata,
                                set_nodata, "Value of the DEM cells outside the TIN (or nan)"),
                 "-9999",
                 [](const BuildOptions& o) { return number_text(o.dem.nodata_or_default()); }),
    // Shown from float64(): the choice's own shown finds no word while the option is not given.
    with_default(
        choice_option<kCellTypes, kIsFloat64, &BuildOptions::dem, &Dem::float64_cells>(
            "--dem-type", option_groups::products, "float32", "DEM cell type"),
        "float32",
        [](const BuildOptions& o) { return std::string(o.dem.float64() ? "float64" : "float32"); }),
    repeated_option("--dem-co", "NAME=VALUE", option_groups::products,
                    add_text<&BuildOptions::dem, &Dem::creation_options>,
                    "A creation option of the DEM's driver, checked against it; for COG\n"
                    "over the defaults (DEFLATE level 1, predictor, average overviews),\n"
                    "e.g. COMPRESS=ZSTD"),
};

}  // namespace

// The library calls that report progress under this stage, in order.
constexpr std::string_view kProgressPhases[] = {"dem", "write dem"};

constexpr StageProgress kDemProgress{"making the DEM", "", nullptr, kProgressPhases};
extern const Stage dem_stage{"dem", "dem", wanted, run, plan, "", kOptions, kDemProgress};

}  // namespace tincdt::pipeline
