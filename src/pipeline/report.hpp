// What a job did: counts, CRS, outputs and timings, and the --stats document made from them.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/types.hpp"
#include "terrain/quality.hpp"

namespace tincdt::pipeline {

struct BuildReport {
  struct Input {
    std::string path;
    // "points", "contours", "hard_lines", "soft_lines", "clip", "erase", "replace"
    std::string kind = "points";
    std::string format;  // "xyz", "las 1.2 pdrf 3", ... (points); the layer name (vectors)
    std::string crs;     // label, "" when the file has none
    std::uint64_t points_read = 0;
    std::uint64_t points_kept = 0;
    std::uint64_t bytes_read = 0;  // of the point file (a COPC file read by box: the part read)
    // Vector sources.
    std::uint64_t features_read = 0;
    std::uint64_t features_used = 0;  // with a usable line or ring (in a tile job: near the tile)
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
  struct Simplify {
    bool ran = false;
    std::uint64_t points = 0;    // vertices of the full TIN: the merged points and line vertices
    std::uint64_t vertices = 0;  // of the simplified TIN
    double max_error = 0;        // achieved, over all of `points`
    double rmse = 0;
    bool stopped_at_max_vertices = false;
  } simplify;
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
  // Seconds per stage, as the stage loop measured them (stages.cpp). Several stages may add to
  // one key: flats, replace, trim, clip and erase all count as "terrain", every output as
  // "write". A key without a field of its own (a later stage's) goes to `more`.
  struct Timings {
    double read = 0, delaunay = 0, constraints = 0, surface = 0, terrain = 0, validate = 0,
           quality = 0, write = 0, total = 0;
    std::vector<std::pair<std::string, double>> more;
    void add(std::string_view key, double seconds);
  } timings_s;
  // Every stage that ran, in order, with its own time.
  struct StageTime {
    std::string name;
    double seconds = 0;
  };
  std::vector<StageTime> stages;
  // Figures of a caller's own (e.g. how far it read), as "figures": {NAME: VALUE}.
  std::vector<std::pair<std::string, double>> figures;
  std::uint64_t peak_rss_bytes = 0;
  std::string crs;  // label, e.g. "EPSG:2949", or "" when unknown
  std::string crs_wkt;
  std::string output;
  std::string output_format;  // "obj", "ply", "geojson"
  std::uint64_t output_bytes = 0;
  // Every file written but the stats document itself, in the order the stages made them. (The
  // stats document also names the constraint lines and the diagnostics on their own, as
  // "constraints_out" and "diagnostics".)
  struct Output {
    std::string path;
    std::string kind;  // "tin", "prj", "constraint_lines", "diagnostics", ...
    std::uint64_t bytes = 0;
    // The CRS the file is in, as a label ("EPSG:4326"): the TIN's, or the target CRS of a
    // reprojected one; "" when it has none (no CRS known, or a file without coordinates).
    std::string crs;
  };
  std::vector<Output> outputs;
  // The path of the output of KIND, "" when none was written.
  std::string output_of(std::string_view kind) const;
  // Products (each also in `outputs` with its size, and in `stages` with its time).
  struct Dem {
    std::string path;    // "" when not asked for
    std::string driver;  // GDAL's name of the format ("COG", "AAIGrid")
    std::string type;    // "Float32", "Float64"
    std::uint32_t width = 0, height = 0;
    double resolution = 0;
    double min_x = 0, max_y = 0;  // top-left corner
    std::uint64_t cells_with_value = 0;
    double rasterize_s = 0, write_s = 0;
  } dem;
  struct ContourLines {
    std::string path;    // "" when not asked for
    std::string driver;  // GDAL's name of the format
    std::uint64_t levels = 0, lines = 0, closed = 0, points = 0;
    double length = 0;  // total, in the CRS's units
    double trace_s = 0, write_s = 0;
  } contour_lines;
  Point3 offset{0, 0, 0};     // subtracted from the written coordinates
  std::vector<Input> inputs;  // point files first, then vector sources in the order read

  std::string to_json() const;  // the --stats document
};

}  // namespace tincdt::pipeline
