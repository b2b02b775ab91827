// The constrained edges of a TIN as a GeoJSON FeatureCollection of 3D LineStrings, one per edge,
// each with the input feature it came from (`--constraints-out FILE`). Same file conventions as
// the TIN's GeoJSON (tin_writer.hpp): the CRS member the way GDAL writes it, the offset as a
// foreign member, and a temporary renamed over the target only when complete.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "io/mesh/tin_writer.hpp"
#include "mesh/triangulation.hpp"

namespace tincdt::io {

// One constrained edge a -> b of the TIN (real vertices), from input feature `feature`.
struct ConstraintEdge {
  VertexId a;
  VertexId b;
  std::uint32_t feature;  // index into the `features` passed alongside
};

// The input feature a constrained edge came from.
struct ConstraintFeatureInfo {
  std::string file;  // the input path (and ":layer"), as the user should see it
  std::int64_t fid;  // the OGR feature id
};

// Writes every edge, in order, as a Feature with a LineString [[x, y, z], [x, y, z]] (vertex a,
// then b) and the properties
//   source_file (string), source_fid (integer), z_start, z_end (the heights of a and b as in the
//   TIN: true elevations, before any offset).
// Honours options.offset, options.overwrite and options.crs_wkt; options.format and
// options.ply_ascii are ignored. Throws OutputError, before creating anything, for an edge with
// a vertex that is not in the TIN or a feature index out of range; and for anything write_tin()
// would refuse (existing output without overwrite, unwritable folder, non-finite coordinate).
// A failed call leaves no file behind.
// Returns vertices = distinct vertices of the edges, triangles = 0, bytes = the file's size.
TinWriteStats write_constraint_lines(const std::string& path, const mesh::Triangulation& tin,
                                     const std::vector<ConstraintEdge>& edges,
                                     const std::vector<ConstraintFeatureInfo>& features,
                                     const TinWriteOptions& options);
// The same into OUT (one file of an OutputSet), not committed; options.overwrite is OUT's.
TinWriteStats write_constraint_lines(OutputFile& out, const mesh::Triangulation& tin,
                                     const std::vector<ConstraintEdge>& edges,
                                     const std::vector<ConstraintFeatureInfo>& features,
                                     const TinWriteOptions& options);

}  // namespace tincdt::io
