// The settings of a job: one field per setting, grouped in the order of the stages they
// configure (stages.cpp). apps/tincdt binds its command line to these fields directly;
// check_options() holds every rule that involves more than one of them.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "constraints/constraints.hpp"
#include "core/types.hpp"
#include "delaunay/delaunay.hpp"
#include "io/mesh/tin_writer.hpp"
#include "io/points/point_reader.hpp"
#include "io/vector/line_reader.hpp"

namespace tincdt::pipeline {

struct BuildOptions {
  // ---- every stage ------------------------------------------------------------------------
  // Threads for the parallel work (reading XYZ, Delaunay, quality); 0 = every core.
  unsigned threads = 0;

  // ---- read: points ----------------------------------------------------------------------
  std::vector<std::string> inputs;  // point files (LAS, XYZ, "-" = XYZ from standard input)
  io::PointFilter filter;           // --keep-class, --drop-class, --first-only, --last-only
  // --a-srs: the CRS of the inputs that have none, as the user gave it (EPSG:n, WKT, PROJ
  // string, a .prj file). --override-srs: the CRS of every input, replacing the files' own.
  std::string assign_srs;
  std::string override_srs;
  // --t-srs: the CRS of the TIN and every output, as the user gave it; every input is transformed
  // into it as it is read, so that the TIN is Delaunay in the CRS it is delivered in. "" = the
  // first input's CRS. A geographic one (degrees) only with allow_geographic (--allow-geographic).
  std::string target_srs;
  bool allow_geographic = false;

  // ---- read: contours and hard lines (any OGR source, "FILE" or "FILE:LAYER") ------------
  // Their vertices join the Delaunay stage, their segments become constrained edges. Lines
  // alone make a valid job. Contour vertices are the ones --fix-flats looks at; breaklines
  // (--breaklines, --hard-lines) are otherwise the same.
  std::vector<std::string> contours;
  std::vector<std::string> breaklines;
  io::LineReadOptions lines;  // --layer, --z-field, --z-from-m, for every vector source

  // ---- read: surface features (any OGR source; lines.layer applies) -----------------------
  // Inserted after the TIN of points and hard lines is built and constrained. Their 2D vertices
  // are draped: z from that TIN (linear interpolation). Then their segments become constrained
  // edges; where one crosses a hard line or contour, the new vertex takes the hard line's z.
  // Clip and erase rings with a z of their own (3D geometry) keep it; 2D rings are draped.
  std::vector<std::string> soft_lines;  // lines, always draped (a z of their own is ignored)
  std::vector<std::string> clip;        // polygons: triangles outside all of them are removed
  std::vector<std::string> erase;       // polygons: triangles inside any of them are removed
  std::vector<std::string> replace;     // polygons: vertices on or inside get the polygon's z
                                        // (lines.z_field, else lines.z_from_m, else 3D z)

  // ---- delaunay ----------------------------------------------------------------------------
  delaunay::DuplicatePolicy on_duplicate = delaunay::DuplicatePolicy::mean;

  // ---- constraints --------------------------------------------------------------------------
  constraints::ConstraintOptions constraint;  // --restore, --on-crossing

  // ---- simplify, after the surface features ------------------------------------------------
  // --max-error Z (>= 0): the smallest TIN greedy insertion finds within Z (z units, vertically)
  // of every vertex of the full one; every constrained edge stays, and the result is
  // constrained Delaunay whatever --restore says. --max-vertices N: stop at N vertices (0 = no
  // limit); alone, it simplifies with a tolerance of 0.
  std::optional<double> max_error;
  std::size_t max_vertices = 0;

  // ---- terrain, applied in this order: fix flats -> replace -> trim -> clip -> erase ------
  // Flats are fixed on the whole TIN before any z is replaced (a replace polygon makes flat
  // triangles on purpose) and before any triangle is removed (fix_flat_triangles needs the
  // whole TIN). Trimming works inward from the convex hull only, before clip and erase open
  // new boundaries. Where clip and erase overlap, erase wins; vertices of a replace polygon
  // inside an erase polygon are replaced, but their triangles are removed.
  bool fix_flats = false;  // --fix-flats: needs contours (their vertices define the flats)
  double max_edge = 0;     // --max-edge LENGTH: > 0 trims boundary triangles; 0 = no trimming

  // ---- validate -----------------------------------------------------------------------------
  bool validate = false;  // check the TIN's topology and Delaunay property before writing

  // ---- write: the TIN and the other outputs -------------------------------------------------
  std::string output;  // -o
  struct Write {
    std::optional<io::TinFormat> format;  // -f; default: from the output's extension
    bool ply_ascii = false;               // --ply-ascii
    bool overwrite = false;               // --overwrite: for every output
    Point3 offset{0, 0, 0};               // --offset X,Y,Z: subtracted from written coordinates
    bool offset_auto = false;             // --offset auto: the data's min corner, rounded down
                                          // to 1000
    bool gpkg_tin = false;                // --gpkg-tin: GeoPackage TIN Z instead of POLYGON Z
  } write;
  std::string stats_path;  // --stats FILE.json
  // --constraints-out FILE.geojson: every constrained edge of the written TIN with its source
  // feature (in the TIN's coordinates, offset).
  std::string constraints_out;
  // --diagnostics FILE.gpkg: crossings, skipped segments and dropped features as GIS layers.
  std::string diagnostics;

  // ---- products, each made from the final TIN (after every stage that edits it) ---------
  struct Dem {
    std::string path;             // --dem FILE: .tif a Cloud-Optimized GeoTIFF; "" = none
    std::string format;           // --dem-format: GDAL raster driver; "" = by the extension
    double resolution = 0;        // --resolution: cell size (> 0), in the CRS's units
    std::optional<BBox> extent;   // --dem-extent; default: the kept triangles' extent
    bool target_aligned = false;  // --tap: extent snapped out to multiples of the resolution
    // --dem-nodata; kDefaultNodata when not given
    std::optional<double> nodata;
    static constexpr double kDefaultNodata = -9999;
    double nodata_or_default() const { return nodata.value_or(kDefaultNodata); }
    // --dem-type: Float64 cells when true; Float32 when false or not given
    std::optional<bool> float64_cells;
    bool float64() const { return float64_cells.value_or(false); }
    std::vector<std::string> creation_options;  // --dem-co NAME=VALUE: the driver's options
  } dem;
  struct Preview {
    std::string path;  // --preview FILE.png: a hillshade with the edges drawn; "" = none
    // --preview-size: pixels on the longer side; kDefaultSize when not given
    std::optional<std::uint32_t> size;
    static constexpr std::uint32_t kDefaultSize = 1024;
    std::uint32_t size_or_default() const { return size.value_or(kDefaultSize); }
  } preview;
  struct ContourLines {
    std::string path;            // --contour-lines FILE (any OGR vector format); "" = none
    std::string format;          // GDAL driver name; "" = from the extension
    double interval = 0;         // --interval (> 0)
    std::optional<double> base;  // --base: levels are base + k * interval; 0 when not given
    double base_or_default() const { return base.value_or(0); }
    std::vector<double> levels;  // --levels: fixed levels instead of an interval
    // --contour-field: the level's attribute (none in DXF, DGN); kDefaultField when not given
    std::optional<std::string> field;
    static constexpr const char* kDefaultField = "elev";
    std::string field_or_default() const { return field.value_or(kDefaultField); }
  } contour_lines;
  struct Terrain {
    std::string path;  // --terrain DIR: a quantized-mesh pyramid; "" = none
    // --terrain-levels 0-MAX (a pyramid starts at level 0); default: from the point spacing
    std::optional<int> max_level;
    // --terrain-fill-height: the surface beyond the data, metres; default the TIN's lowest
    std::optional<double> fill_height;
    // --terrain-max-tiles: a larger pyramid is refused; kDefaultMaxTiles when not given
    std::optional<std::uint64_t> max_tiles;
    static constexpr std::uint64_t kDefaultMaxTiles = 2'000'000;
    std::uint64_t max_tiles_or_default() const { return max_tiles.value_or(kDefaultMaxTiles); }
  } terrain;
};

// What check_options() found, resolved for the job.
struct CheckedOptions {
  io::TinFormat format = io::TinFormat::ply;  // of the TIN: -f, else from the extension
  std::string assign_crs_wkt;                 // --a-srs as WKT, "" when not given
  std::string override_crs_wkt;               // --override-srs as WKT, "" when not given
  std::string target_crs_wkt;                 // --t-srs as WKT, "" when not given
  std::vector<std::string> warnings;          // settings that have no effect, and why
};

// Every rule that involves more than one option, or a value no single option can check: some
// input, the output format, the extensions of --constraints-out and --diagnostics, --fix-flats
// with contours, exclusive options, readable --a-srs / --t-srs, a geographic --t-srs only with
// --allow-geographic, no offset for LandXML and GeoPackage, each product's settings only with
// the product and the ones it needs.
// Throws UsageError naming the option. Cheap (no input is read); build() runs it first, and a
// command line runs it before anything else to tell a usage error from a failed job.
CheckedOptions check_options(const BuildOptions& options);

}  // namespace tincdt::pipeline
