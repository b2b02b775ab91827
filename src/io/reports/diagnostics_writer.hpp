// `--diagnostics FILE.gpkg`: what the build did to the input, as GeoPackage layers a user opens in
// a GIS instead of reading logs.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "io/output_file.hpp"
#include "io/vector/line_reader.hpp"

namespace tincdt::io {

struct Diagnostics {
  // Two constraint lines crossed; the crossing point became a vertex of both.
  struct Crossing {
    Point3 at;  // the inserted vertex (z: the mean of z_a and z_b)
    std::string file_a;
    std::int64_t fid_a;
    std::string file_b;
    std::int64_t fid_b;
    double z_a;  // z interpolated along line a at the crossing
    double z_b;  // z interpolated along line b
  };
  // Input points with the same x, y merged into one vertex.
  struct Duplicate {
    Point3 at;             // the vertex kept
    std::uint32_t points;  // how many input points it stands for
    double z_min;
    double z_max;
  };
  // A zero-length segment (a repeated vertex) skipped in a line.
  struct SkippedSegment {
    Point3 at;
    std::string file;
    std::int64_t fid;
  };
  // An input feature that contributed nothing.
  struct DroppedFeature {
    std::string file;
    std::int64_t fid;
    std::string reason;
    Point3 at;    // meaningful only when has_at
    bool has_at;  // false: no location known (no geometry, empty geometry)
  };
  std::vector<Crossing> crossings;
  std::vector<Duplicate> duplicates;
  std::vector<SkippedSegment> skipped_segments;
  std::vector<DroppedFeature> dropped_features;
};

// Writes a GeoPackage with four layers of 3D points, each created even when empty (so the schema
// is there to see) and each in the CRS CRS_WKT (empty: none):
//   crossings          file_a, fid_a, file_b, fid_b, z_a, z_b, z_diff = |z_a - z_b|
//   merged_duplicates  points, z_min, z_max
//   skipped_segments   source_file, source_fid
//   dropped_features   source_file, source_fid, reason; geometry NULL when no location is known
// ("fid" is the GeoPackage's own feature id column, hence "source_fid" for the input's.)
// Features keep the order of the vectors; the GeoPackage fids count from 1 in each layer. The
// layers have no spatial index (it would take most of the time); add one if ever needed with
//   ogrinfo FILE.gpkg -sql "SELECT CreateSpatialIndex('crossings', 'geom')"
// The file is built beside PATH under a hidden temporary name ending in .gpkg and renamed over
// PATH only when complete. Throws OutputError when PATH exists and !overwrite (before writing
// anything), when the folder is not writable, for a non-finite location (naming the layer and
// the entry) or an unreadable CRS, and when GDAL fails; a failed call leaves no file behind.
void write_diagnostics(const std::string& path, const Diagnostics& d, const std::string& crs_wkt,
                       bool overwrite);
// The same into OUT (one file of an OutputSet), not committed.
void write_diagnostics(OutputFile& out, const Diagnostics& d, const std::string& crs_wkt);

// Appends what the line reader skipped and dropped (LineData::skipped, LineData::dropped) to D,
// with the file names of LINES.
void add_line_diagnostics(const LineData& lines, Diagnostics& d);

}  // namespace tincdt::io
