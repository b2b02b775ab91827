// Contour and breakline reader (any OGR vector source): polylines become vertices and segments.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace tincdt::io {

struct LineReadOptions {
  std::string layer;      // wins over a ":LAYER" in the path; empty = the source's only layer
  std::string z_field;    // take z from this attribute instead of the geometry
  bool z_from_m = false;  // take z from the geometry's M values
};

// The feature a segment came from, for logs, stats and diagnostics.
struct LineFeature {
  std::uint32_t file;  // index of the path in the order read_lines was called
  std::int64_t fid;    // OGR feature id
  double z;            // the feature's level when z came from an attribute, else NaN
};

// A repeated vertex that was collapsed, i.e. a zero-length segment that was skipped.
struct LineSkip {
  Point3 at;           // the collapsed vertex, with its own z (the vertex kept has the run's first)
  std::uint32_t file;  // index into LineData::files
  std::int64_t fid;    // OGR feature id
};

// A feature that gave no segment, and why.
struct LineDrop {
  std::uint32_t file;  // index into LineData::files
  std::int64_t fid;    // OGR feature id
  std::string reason;  // "no geometry", "empty geometry", "Point geometry: ...", "degenerate: ..."
  Point3 at;           // when has_at: the first vertex of the first degenerate line (z from the z
                       // source) or of the first unused geometry (its own Z, 0 when 2D)
  bool has_at;         // false for no geometry, an empty geometry, only empty parts
};

struct LineData {
  std::vector<Point3> vertices;
  struct Segment {
    std::uint32_t a;  // indices into vertices
    std::uint32_t b;
    std::uint32_t feature;  // index into features
  };
  std::vector<Segment> segments;
  std::vector<LineFeature> features;
  std::vector<std::string> files;  // path (and ":layer" when one was named) per file index
  // For diagnostics: one entry per repeated vertex collapsed (LineReadStats::repeated_vertices)
  // and one per feature dropped (LineReadStats::empty_features), in reading order.
  std::vector<LineSkip> skipped;
  std::vector<LineDrop> dropped;
};

struct LineReadStats {
  std::uint64_t features = 0;              // features in the layer, used or not
  std::uint64_t vertices = 0;              // vertices appended
  std::uint64_t segments = 0;              // segments appended
  std::uint64_t repeated_vertices = 0;     // consecutive repeats (same x, y) collapsed
  std::uint64_t zero_length_segments = 0;  // skipped; each is one collapsed repeat, so equal
                                           // to repeated_vertices
  std::uint64_t degenerate_parts = 0;      // lines / rings with < 2 distinct vertices, skipped
                                           // (a feature left without segments by them is also
                                           // one of empty_features)
  std::uint64_t closed_parts = 0;          // rings and closed lines: last segment ends at first
  std::uint64_t empty_features = 0;        // no geometry, no line geometry (points) or no
                                           // usable segment
  std::string crs_wkt;                     // WKT2 (WKT1 if OSR cannot); empty when none
  std::string layer;                       // the layer read
  // Things the caller should log (GDAL warnings, curves approximated by line strings); each
  // names the file.
  std::vector<std::string> warnings;
};

// Appends the LineStrings, MultiLineStrings and Polygon / MultiPolygon rings of PATH (spec may
// be "FILE" or "FILE:LAYER"; options.layer wins when set), with their Z/M/ZM variants and
// GeometryCollections of them; curved geometries are approximated by line strings (and said so
// in `warnings`); points are skipped and counted in empty_features. Each collapsed vertex is
// recorded in out.skipped and each feature without segments in out.dropped with the reason.
// PATH is split at its last ':'
// only when the whole does not exist and the part before the ':' does. Without a layer name the
// source must have exactly one layer. Z comes from options.z_field, else options.z_from_m, else
// the geometry's Z. Consecutive vertices with the same x, y are collapsed (the first z is kept).
// Closed rings stay closed: the last segment ends at the ring's first vertex index. Throws
// InputError naming the file, layer and feature for a 2D geometry with no z source, a missing or
// NULL z field, missing M values, a non-finite coordinate, an unreadable source; `out` is then
// left as it was.
LineReadStats read_lines(const std::string& path, const LineReadOptions& options, LineData& out);

// The file part of a vector source spec, split as read_lines() splits it: SPEC itself, or the
// part before its last ':' when SPEC does not exist and that part does.
std::string vector_source_file(const std::string& spec);

}  // namespace tincdt::io
