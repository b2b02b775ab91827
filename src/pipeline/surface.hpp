// Internal to the pipeline (build.cpp): where each constraint came from, and the surface-feature
// stage that drapes soft lines and polygon rings on the TIN of points and hard lines and makes
// them constrained edges.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "constraints/constraints.hpp"
#include "core/progress.hpp"
#include "io/vector/polygon_reader.hpp"
#include "mesh/triangulation.hpp"
#include "terrain/polygons.hpp"

namespace tincdt::pipeline::detail {

enum class SourceKind : std::uint8_t { contour, hard_line, soft_line, clip, erase, replace };

// "contours", "hard_lines", "soft_lines", "clip", "erase", "replace".
const char* kind_name(SourceKind kind);

// Constraint source ids (constraints::Segment::source, Piece::source) -> the input feature.
class SourceTable {
 public:
  std::uint32_t add_file(std::string name);
  // A feature of file `file` (an add_file() index); returns its source id, counting from 0.
  // `draped`: its vertices took their z from the TIN (soft lines, 2D rings, replace rings).
  std::uint32_t add(std::uint32_t file, std::int64_t fid, SourceKind kind, bool draped);

  std::size_t size() const { return entries_.size(); }
  const std::vector<std::string>& files() const { return files_; }
  std::uint32_t file_index(std::uint32_t source) const { return entries_[source].file; }
  const std::string& file(std::uint32_t source) const { return files_[entries_[source].file]; }
  std::int64_t fid(std::uint32_t source) const { return entries_[source].fid; }
  SourceKind kind(std::uint32_t source) const { return entries_[source].kind; }
  bool draped(std::uint32_t source) const { return entries_[source].draped; }
  bool known(std::uint32_t source) const { return source < entries_.size(); }
  // "FILE feature FID", or "a line" for an unknown id.
  std::string describe(std::uint32_t source) const;

 private:
  struct Entry {
    std::uint32_t file;
    std::int64_t fid;
    SourceKind kind;
    bool draped;
  };
  std::vector<std::string> files_;
  std::vector<Entry> entries_;
};

// The features of one kind read from the vector sources, and the source id of the first one
// (feature i has source id first_source + i).
struct SurfaceInput {
  SourceKind kind;
  io::ShapeData data;
  std::uint32_t first_source = 0;
};

// Whether the features of this kind take their z from the TIN: soft lines and replace rings
// always, clip and erase rings when they are 2D.
bool is_draped(SourceKind kind, const io::ShapeFeature& feature);

struct SurfaceResult {
  constraints::ConstraintResult constraints;  // the second insertion; its pieces are all pieces
  std::uint64_t vertices = 0;                 // surface-feature vertices given
  std::uint64_t draped = 0;                   // of these, z from the TIN
  std::uint64_t reused = 0;                   // of these, on an existing vertex
  std::uint64_t soft_line_vertices = 0;       // draped soft-line vertices
  std::uint64_t segments = 0;                 // surface-feature segments given
  std::uint64_t crossings_with_hard_z = 0;    // crossing vertices given the hard line's z
  std::uint64_t rings_cut = 0;                // clip and erase rings cut to the TIN's hull
  std::uint64_t rings_outside = 0;            // clip and erase rings wholly outside it: left out
  std::vector<constraints::Segment> given;    // the surface-feature segments inserted
};

// What a job over part of the data (a tile) tells the surface stage; empty: the whole data.
struct SurfaceScope {
  // The whole data's convex hull (counter-clockwise, without collinear vertices, from its least
  // point: terrain::strict_hull()), which clip and erase rings are cut to instead of the TIN's.
  std::vector<Point2> hull;
  // Whether the TIN's triangle T (of points and hard lines) is the whole job's: a height draped
  // from any other one is NaN, which the job must then not keep. Draped vertices beyond the
  // TIN but inside the hull are NaN too instead of an error.
  std::function<bool(const mesh::Triangulation& tin, TriangleId t)> settled;
  bool partial() const { return !hull.empty(); }
};

// The surface-feature stage on the constrained TIN of points and hard lines:
//  0. cuts clip and erase rings to the TIN's convex hull (z along the ring for 3D rings), and
//     leaves out those wholly outside it; a polygon ring that encloses no area, and clip
//     polygons that all lie outside the TIN, are InputErrors naming the feature / file;
//  1. drapes every vertex of a draped feature on the TIN as it is (linear interpolation), all
//     before any is inserted, so each takes its z from the TIN without the surface features;
//     a vertex outside the TIN (soft lines, replace rings) is an InputError naming the feature;
//  2. inserts the vertices (mesh::PointInserter); one on an existing vertex reuses it;
//  3. inserts the hard pieces again (they are edges already: only their sources are recorded,
//     so that crossings find them) and then every surface-feature segment, splitting crossings,
//     each made from the two whole segments (a hard piece names its whole segment);
//  4. gives a crossing vertex of a draped and a not-draped constraint the not-draped one's z
//     (a soft line is draped on a hard line, never the other way round).
SurfaceResult insert_surface_features(mesh::Triangulation& tin,
                                      const std::vector<const SurfaceInput*>& inputs,
                                      const SourceTable& sources,
                                      const std::vector<constraints::Piece>& hard_pieces,
                                      constraints::Restore restore, const ProgressFn* progress,
                                      const SurfaceScope& scope = {});

// The features as terrain polygons (rings in x, y; z = the feature's z).
std::vector<terrain::Polygon> polygons_of(const io::ShapeData& data);

// 1 for every vertex on a piece of a contour (the on_contour flags of terrain/flats.hpp).
std::vector<std::uint8_t> contour_flags(const mesh::Triangulation& tin,
                                        const std::vector<constraints::Piece>& pieces,
                                        const SourceTable& sources);

}  // namespace tincdt::pipeline::detail
