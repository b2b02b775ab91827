// The whole job as one library call: read -> merge -> triangulate -> constrain -> drape and
// insert the surface features -> fix flats -> replace -> trim -> clip -> erase -> write.
// apps/tincdt only turns command-line options into BuildOptions and reports the result.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "constraints/constraints.hpp"
#include "core/progress.hpp"
#include "core/types.hpp"
#include "delaunay/delaunay.hpp"
#include "io/mesh/tin_writer.hpp"
#include "io/points/point_reader.hpp"
#include "io/vector/line_reader.hpp"
#include "terrain/quality.hpp"

namespace tincdt::pipeline {

// One field per job setting, grouped by stage. Later stages (contours / breaklines from OGR
// sources, restoration mode, clipping) add their own fields next to the stage they configure.
struct BuildOptions {
  // ---- input ---------------------------------------------------------------------------
  std::vector<std::string> inputs;  // point files (LAS, XYZ, "-")
  io::PointFilter filter;
  std::string assign_crs_wkt;  // --a-srs: the inputs' CRS, replacing any in the files

  // Contours and hard lines (any OGR source, "FILE" or "FILE:LAYER"): their vertices join the
  // Delaunay stage, their segments become constrained edges. Lines alone make a valid job.
  // Contour vertices are the ones --fix-flats looks at; breaklines (--breaklines, --hard-lines)
  // are otherwise the same.
  std::vector<std::string> contours;
  std::vector<std::string> breaklines;
  io::LineReadOptions lines;  // --layer, --z-field, --z-from-m, for every vector source

  // ---- surface features (any OGR source, "FILE" or "FILE:LAYER"; lines.layer applies) -------
  // Inserted after the TIN of points and hard lines is built and constrained. Their 2D vertices
  // are draped: z from that TIN (linear interpolation); a vertex outside it is an InputError
  // naming the feature. Then their segments become constrained edges; where one crosses a hard
  // line or contour, the new vertex takes the hard line's z.
  std::vector<std::string> soft_lines;  // lines, always draped (a z of their own is ignored)
  std::vector<std::string> clip;        // polygons: triangles outside all of them are removed
  std::vector<std::string> erase;       // polygons: triangles inside any of them are removed
  std::vector<std::string> replace;     // polygons: vertices on or inside get the polygon's z
                                        // (lines.z_field, else lines.z_from_m, else 3D z)
  // Clip and erase rings with a z of their own (3D geometry) keep it; 2D rings are draped.

  // ---- TIN boundary and quality, applied in this order -----------------------------------
  //   fix flats -> replace -> trim (max_edge) -> clip -> erase
  // Flats are fixed on the whole TIN before any z is replaced (a replace polygon makes flat
  // triangles on purpose) and before any triangle is removed (fix_flat_triangles needs the
  // whole TIN). Trimming works inward from the convex hull only, before clip and erase open
  // new boundaries. Where clip and erase overlap, erase wins; vertices of a replace polygon
  // inside an erase polygon are replaced, but their triangles are removed.
  bool fix_flats = false;  // --fix-flats: needs contours (their vertices define the flats)
  double max_edge = 0;     // --max-edge LENGTH: > 0 trims boundary triangles; 0 = no trimming

  // ---- Delaunay stage --------------------------------------------------------------------
  delaunay::DuplicatePolicy on_duplicate = delaunay::DuplicatePolicy::mean;
  bool validate = false;  // run Triangulation::validate() before writing (slow)

  // ---- constraint stage ------------------------------------------------------------------
  constraints::ConstraintOptions constraint;  // --restore, --on-crossing

  // ---- output --------------------------------------------------------------------------
  std::string output;
  io::TinWriteOptions write;  // format, ply_ascii, overwrite, offset, target CRS
                              // (write.crs_wkt is filled by build() from the inputs)
  bool offset_auto = false;   // write.offset = data's min corner rounded down to 1000
  std::string stats_path;     // --stats FILE.json, empty = none; honours write.overwrite
  // --constraints-out FILE.geojson: every constrained edge of the written TIN with its source
  // feature (as the TIN: write.offset, write.target_crs_wkt, overwrite, temporary + rename).
  std::string constraints_out;
  // --diagnostics FILE.gpkg: crossings, skipped segments and dropped features as GIS layers.
  std::string diagnostics;
};

struct BuildReport {
  struct Input {
    std::string path;
    // "points", "contours", "hard_lines", "soft_lines", "clip", "erase", "replace"
    std::string kind = "points";
    std::string format;  // "xyz", "las 1.2 pdrf 3", ... (points); the layer name (vectors)
    std::string crs;     // label, "" when the file has none
    std::uint64_t points_read = 0;
    std::uint64_t points_kept = 0;
    // Vector sources.
    std::uint64_t features_read = 0;
    std::uint64_t features_used = 0;     // with at least one usable line or ring
    std::uint64_t features_dropped = 0;  // no geometry, points only, degenerate
    std::uint64_t vertices = 0;
    std::uint64_t segments = 0;
    std::uint64_t skipped_segments = 0;  // zero-length (repeated vertices collapsed)
  };
  struct Flats {
    bool fixed = false;    // --fix-flats ran
    bool counted = false;  // counted (with contours, for --fix-flats or --stats); else all 0
    std::uint64_t before = 0, after_swaps = 0, after = 0, swaps = 0, vertices_added = 0;
    std::uint64_t vertices_interpolated = 0, vertices_extrapolated = 0;
    std::uint64_t left_no_level = 0, left_unplaced = 0;
    std::uint64_t non_delaunay_edges = 0;  // left by the swaps, on purpose (see terrain/flats.hpp)
  };

  std::uint64_t points_read = 0;
  std::uint64_t points_kept = 0;
  std::uint64_t duplicates_merged = 0;
  std::uint64_t vertices = 0;     // written: with removed triangles, only those of kept ones
  std::uint64_t triangles = 0;    // written (kept) triangles
  std::uint64_t constraints = 0;  // constrained edges of the written TIN
  std::uint64_t steiner_vertices = 0;
  // Constraint stage.
  std::uint64_t line_features = 0;
  std::uint64_t line_vertices = 0;
  std::uint64_t constraint_segments = 0;        // input segments
  std::uint64_t zero_length_segments = 0;       // skipped (repeated vertices, merged ends)
  std::uint64_t constraint_segments_split = 0;  // at a vertex lying on them
  std::uint64_t crossings = 0;
  double max_z_disagreement = 0;  // between two crossing hard lines / contours, at their crossing
  // Surface features and the terrain stage.
  std::uint64_t surface_features = 0;    // soft lines, clip, erase and replace features used
  std::uint64_t soft_line_vertices = 0;  // soft-line vertices inserted (draped)
  std::uint64_t draped_vertices = 0;     // all draped vertices (soft lines, 2D rings)
  std::uint64_t reused_vertices = 0;     // surface-feature vertices on an existing vertex
  Flats flats;
  std::uint64_t replaced_vertices = 0;
  std::uint64_t trimmed_triangles = 0;
  std::uint64_t clipped_triangles = 0;
  std::uint64_t erased_triangles = 0;
  // Measured on the written TIN when stats are written (BuildOptions::stats_path).
  bool quality_measured = false;
  terrain::QualityReport quality;
  struct Flips {
    std::uint64_t insertion = 0, restoration = 0;
  } flips;
  struct Timings {
    double read = 0, delaunay = 0, constraints = 0, surface = 0, terrain = 0, validate = 0,
           write = 0, total = 0;
  } timings_s;
  std::uint64_t peak_rss_bytes = 0;
  std::string crs;  // label, e.g. "EPSG:2949", or "" when unknown
  std::string crs_wkt;
  std::string output;
  std::string output_format;  // "obj", "ply", "geojson"
  std::uint64_t output_bytes = 0;
  std::string constraints_out;  // written files, "" when not asked for
  std::string diagnostics;
  Point3 offset{0, 0, 0};     // subtracted from the written coordinates
  std::vector<Input> inputs;  // point files first, then vector sources in the order read

  std::string to_json() const;  // the --stats document
};

// Runs the job; throws tincdt::Error (InputError, OutputError, GeometryError, Cancelled).
// The outputs (TIN, stats, constraint lines, diagnostics) are checked before anything is read,
// so a long job does not fail at its end because of an existing or unwritable output. On
// failure nothing is written: outputs already written by this run are removed again.
// Log lines go through `log` (may be empty) so the library stays free of spdlog.
enum LogLevel : int { log_debug = 0, log_info = 1, log_warn = 2 };
using LogFn = std::function<void(int level /*0 debug,1 info,2 warn*/, const std::string&)>;
BuildReport build(const BuildOptions& options, const ProgressFn* progress = nullptr,
                  const LogFn& log = {});

// Writes report.to_json() to PATH through a temporary file renamed at the end.
void write_stats(const BuildReport& report, const std::string& path, bool overwrite);

// Peak resident set size of this process (VmHWM), 0 if unknown.
std::uint64_t peak_rss_bytes();

// The project version, "X.Y.Z" (from the CMake project).
std::string_view version();

// "obj", "ply" or "geojson".
std::string_view format_name(io::TinFormat format);

}  // namespace tincdt::pipeline
