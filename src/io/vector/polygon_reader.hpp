// Polygon and draped-line reader (any OGR vector source) for the area and draped surface
// features: --clip, --erase and --replace polygons, and --soft-lines. Unlike the contour reader
// (line_reader.hpp) it keeps parts apart (a polygon's rings, a line's vertices in order) and
// needs no elevation for 2D geometries: those are draped on the TIN by the pipeline.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "io/vector/line_reader.hpp"

namespace tincdt::io {

struct ShapeReadOptions {
  std::string layer;  // wins over a ":LAYER" in the path; empty = the source's only layer
  // false (clip, erase, soft lines): no z source is needed or read; the points keep the
  // geometry's Z when it has one and get NaN when it is 2D. true (replace polygons): every
  // feature needs one z, from z_field, else from the M values, else from the geometry's Z, and
  // the values of one feature must all be equal.
  bool feature_z = false;
  std::string z_field;    // feature_z: the attribute holding the feature's z
  bool z_from_m = false;  // feature_z: the z is the geometry's (single) M value
};

// One ring of a polygon, or one line: consecutive points differ in x or y; a ring's closing
// point is not repeated (the last point joins the first).
struct ShapePart {
  std::vector<Point3> points;  // z: the geometry's Z, NaN when 2D
  bool closed = false;         // a ring, or a line that ends where it starts
};

struct ShapeFeature {
  std::uint32_t file = 0;                               // index into ShapeData::files
  std::int64_t fid = 0;                                 // OGR feature id
  double z = std::numeric_limits<double>::quiet_NaN();  // feature_z: its z; otherwise NaN
  std::vector<ShapePart> parts;  // polygons: every ring (outer ones and holes) in file order
};

struct ShapeData {
  std::vector<ShapeFeature> features;  // only features with at least one usable part
  std::vector<std::string> files;      // path (and ":layer" when one was named) per file index
  // For diagnostics, as in LineData: collapsed repeated vertices and features that gave nothing.
  std::vector<LineSkip> skipped;
  std::vector<LineDrop> dropped;
};

struct ShapeReadStats {
  std::uint64_t features = 0;           // features in the layer, used or not
  std::uint64_t parts = 0;              // rings or lines appended
  std::uint64_t vertices = 0;           // points appended
  std::uint64_t segments = 0;           // segments those parts make
  std::uint64_t repeated_vertices = 0;  // consecutive repeats (same x, y) collapsed
  std::uint64_t degenerate_parts = 0;   // rings with < 3, lines with < 2 distinct points: skipped
  std::uint64_t empty_features = 0;     // features without a usable part (ShapeData::dropped)
  std::string crs_wkt;                  // WKT2 (WKT1 if OSR cannot); empty when none
  std::string layer;                    // the layer read
  std::vector<std::string> warnings;    // GDAL warnings, curves approximated; each names the file
};

// Appends the Polygon / MultiPolygon features of PATH ("FILE" or "FILE:LAYER", split as the
// contour reader does), with their Z/M variants, GeometryCollections of them and curved polygons
// (approximated by line strings, and said so in `warnings`). Each feature keeps all its rings;
// lines and points are not polygons: such a feature is dropped with the reason. Throws
// InputError naming the file, layer and feature for a non-finite coordinate, an unreadable
// source, and with feature_z for a feature without one z (2D without --z-field, NULL or
// non-numeric field, missing M values, vertices at different heights); `out` is then left as it
// was.
ShapeReadStats read_polygons(const std::string& path, const ShapeReadOptions& options,
                             ShapeData& out);

// The same for lines: LineStrings, MultiLineStrings and polygon rings (closed) are parts.
ShapeReadStats read_shape_lines(const std::string& path, const ShapeReadOptions& options,
                                ShapeData& out);

}  // namespace tincdt::io
