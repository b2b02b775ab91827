// The whole job as one library call: read -> merge -> triangulate -> constrain -> write.
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
#include "io/line_reader.hpp"
#include "io/point_reader.hpp"
#include "io/tin_writer.hpp"

namespace tincdt::pipeline {

// One field per job setting, grouped by stage. Later stages (contours / breaklines from OGR
// sources, restoration mode, clipping) add their own fields next to the stage they configure.
struct BuildOptions {
  // ---- input ---------------------------------------------------------------------------
  std::vector<std::string> inputs;  // point files (LAS, XYZ, "-")
  io::PointFilter filter;
  std::string assign_crs_wkt;  // --a-srs: the inputs' CRS, replacing any in the files

  // Contours and breaklines (any OGR source, "FILE" or "FILE:LAYER"): their vertices join the
  // Delaunay stage, their segments become constrained edges. Lines alone make a valid job.
  std::vector<std::string> contours;
  std::vector<std::string> breaklines;
  io::LineReadOptions lines;  // --layer, --z-field, --z-from-m, for every line source

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
};

struct BuildReport {
  struct Input {
    std::string path;
    std::string format;  // "xyz", "las 1.2 pdrf 3", ...
    std::string crs;     // label, "" when the file has none
    std::uint64_t points_read = 0;
    std::uint64_t points_kept = 0;
  };

  std::uint64_t points_read = 0;
  std::uint64_t points_kept = 0;
  std::uint64_t duplicates_merged = 0;
  std::uint64_t vertices = 0;
  std::uint64_t triangles = 0;
  std::uint64_t constraints = 0;  // constrained edges in the TIN
  std::uint64_t steiner_vertices = 0;
  // Constraint stage.
  std::uint64_t line_features = 0;
  std::uint64_t line_vertices = 0;
  std::uint64_t constraint_segments = 0;        // input segments
  std::uint64_t zero_length_segments = 0;       // skipped (repeated vertices, merged ends)
  std::uint64_t constraint_segments_split = 0;  // at a vertex lying on them
  std::uint64_t crossings = 0;
  double max_z_disagreement = 0;  // between two crossing constraints, at their crossing
  struct Flips {
    std::uint64_t insertion = 0, restoration = 0;
  } flips;
  struct Timings {
    double read = 0, delaunay = 0, constraints = 0, validate = 0, write = 0, total = 0;
  } timings_s;
  std::uint64_t peak_rss_bytes = 0;
  std::string crs;  // label, e.g. "EPSG:2949", or "" when unknown
  std::string crs_wkt;
  std::string output;
  std::string output_format;  // "obj", "ply", "geojson"
  std::uint64_t output_bytes = 0;
  Point3 offset{0, 0, 0};  // subtracted from the written coordinates
  std::vector<Input> inputs;

  std::string to_json() const;  // the --stats document
};

// Runs the job; throws tincdt::Error (InputError, OutputError, GeometryError, Cancelled).
// The output (and the stats file) are checked before anything is read, so a long job does not
// fail at its end because of an existing or unwritable output. On failure nothing is written.
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
