// dem: --dem, the final TIN rasterized (products::rasterize) and written as a Cloud-Optimized
// GeoTIFF with the TIN's CRS: Float32 cells, or Float64 with --dem-type Float64.
//
// The job's caller may fix the grid (Job::dem_grid) and have the cells filled from removed
// triangles too (Job::dem_extra_triangles, put back while the DEM is rasterized).
#include <unistd.h>

#include <cmath>
#include <span>
#include <vector>

#include "core/error.hpp"
#include "io/raster/dem_writer.hpp"
#include "pipeline/stage.hpp"
#include "products/rasterize.hpp"

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

template <class T>
void rasterize_and_write(Job& job, const products::Grid& grid, io::OutputFile& out) {
  const BuildOptions::Dem& o = job.options.dem;
  BuildReport::Dem& r = job.report.dem;
  // The grid is held whole (GDAL writes it from there): refuse one larger than the machine
  // rather than fail in the allocator.
  const double bytes = static_cast<double>(grid.cells()) * sizeof(T);
  const std::uint64_t memory = physical_memory();
  if (memory > 0 && bytes > static_cast<double>(memory))
    throw OutputError(o.path, "",
                      "a DEM of " + std::to_string(grid.width) + " x " +
                          std::to_string(grid.height) + " cells needs " +
                          std::to_string(static_cast<std::uint64_t>(bytes / (1 << 30))) +
                          " GiB, more than this machine's memory (use a coarser --resolution "
                          "or a smaller --dem-extent)");
  auto t0 = std::chrono::steady_clock::now();
  std::vector<T> cells(grid.cells());
  // The extra triangles are back while the DEM rasterizes (the outputs after this stage see them
  // removed again).
  if (!job.dem_extra_triangles.empty()) job.wait_for_quality();  // it reads the removed flags
  mesh::Triangulation& tin = job.tin();
  struct PutBack {
    mesh::Triangulation& tin;
    const std::vector<TriangleId>& triangles;
    explicit PutBack(mesh::Triangulation& m, const std::vector<TriangleId>& t)
        : tin(m), triangles(t) {
      for (const TriangleId id : triangles) tin.set_removed(id, false);
    }
    ~PutBack() {
      for (const TriangleId id : triangles) tin.set_removed(id, true);
    }
    PutBack(const PutBack&) = delete;
    PutBack& operator=(const PutBack&) = delete;
  } put_back(tin, job.dem_extra_triangles);
  const products::RasterizeStats stats =
      products::rasterize<T>(tin, grid, static_cast<T>(o.nodata), cells,
                             {.threads = job.options.threads, .progress = job.stage_progress()});
  r.cells_with_value = stats.cells_with_value;
  r.rasterize_s = seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  io::DemWriteOptions w;
  w.nodata = o.nodata;
  w.crs_wkt = job.crs_wkt;
  w.creation_options = o.creation_options;
  w.threads = job.options.threads;
  w.progress = job.stage_progress();
  io::write_dem(out, grid, std::span<const T>(cells), w);
  job.finish_output(out);
  r.write_s = seconds_since(t0);
}

void run(Job& job) {
  const BuildOptions::Dem& o = job.options.dem;
  products::Grid grid;
  if (job.dem_grid) {
    grid = *job.dem_grid;
  } else {
    const BBox extent = o.extent ? *o.extent : products::kept_extent(job.tin());
    try {
      grid = products::grid_over(extent, o.resolution, o.target_aligned);
    } catch (const Error& e) {
      throw OutputError(o.path, "", e.detail());
    }
  }
  BuildReport::Dem& r = job.report.dem;
  r.path = o.path;
  r.type = o.float64 ? "Float64" : "Float32";
  r.width = grid.width;
  r.height = grid.height;
  r.resolution = grid.resolution;
  r.min_x = grid.min_x;
  r.max_y = grid.max_y;
  io::OutputFile& out = job.add_output(o.path, "dem");
  if (o.float64)
    rasterize_and_write<double>(job, grid, out);
  else
    rasterize_and_write<float>(job, grid, out);
  job.info("DEM: " + std::to_string(grid.width) + " x " + std::to_string(grid.height) + " cells, " +
           std::to_string(r.cells_with_value) + " with a value");
}

void plan(const BuildOptions& o, FilePlan& files) {
  files.outputs.push_back({o.dem.path, "the DEM (--dem)"});
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

constexpr OptionSpec kOptions[] = {
    text_option("--dem", "FILE.tif", option_groups::products,
                set_text<&BuildOptions::dem, &Dem::path>,
                "Rasterize the TIN to a Cloud-Optimized GeoTIFF: each cell centre gets\n"
                "its triangle's linear interpolation, nodata outside (needs --resolution)"),
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
    {.flags = "--dem-nodata",
     .value_name = "V",
     .help = "Value of the DEM cells outside the TIN (or nan)",
     .group = option_groups::products,
     .default_text = "-9999",
     .check =
         [](std::string_view v) { return lower(v) == "nan" ? std::string() : check_number(v); },
     .set =
         [](BuildOptions& o, std::string_view v) {
           o.dem.nodata = lower(v) == "nan" ? std::nan("") : *parse_number(v);
         },
     .shown = show_number<&BuildOptions::dem, &Dem::nodata>},
    choice_option<kCellTypes, kIsFloat64, &BuildOptions::dem, &Dem::float64>(
        "--dem-type", option_groups::products, "float32", "DEM cell type"),
    repeated_option("--dem-co", "NAME=VALUE", option_groups::products,
                    add_text<&BuildOptions::dem, &Dem::creation_options>,
                    "A GDAL COG creation option over the defaults (DEFLATE level 1,\n"
                    "predictor, average overviews), e.g. COMPRESS=ZSTD"),
};

}  // namespace

extern const Stage dem_stage{"dem", "dem", wanted, run, plan, "", kOptions};

}  // namespace tincdt::pipeline
