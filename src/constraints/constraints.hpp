// The constraint stage (paper steps B-D): every segment becomes an edge of the TIN by edge
// swapping only, then the constrained Delaunay property is restored around it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/progress.hpp"
#include "core/types.hpp"
#include "mesh/triangulation.hpp"

namespace tincdt::constraints {

// How the triangles around a new constraint are improved after it is in. Only `delaunay` gives a
// triangulation defined by the points and segments alone; `aspect` and `none` also depend on the
// order in which the segments come (never on the input order of the points or the threads).
enum class Restore {
  delaunay,  // Lawson flips with the exact in-circle test, ties broken by the symbolic
             // perturbation (predicates::incircle_perturbed): the result is the unique CDT
  aspect,    // the paper's criterion (eq. 1): flip when it lowers max(circumradius / inradius)
  none,      // keep the triangles the swapping left
};

enum class OnCrossing { split, error };

// A segment between two vertices; `source` is the caller's id of the feature it came from.
// A piece of an earlier call given again names the input segment it is part of (Piece::whole_a,
// whole_b), so that its crossings with the new segments are computed from that whole segment as
// the earlier ones were; kNoId: the segment is whole.
struct Segment {
  VertexId a;
  VertexId b;
  std::uint32_t source;
  VertexId whole_a = kNoId;
  VertexId whole_b = kNoId;
};

struct ConstraintOptions {
  Restore restore = Restore::delaunay;
  OnCrossing on_crossing = OnCrossing::split;
};

// A Steiner vertex made where two constraints cross.
struct Crossing {
  VertexId vertex;
  std::uint32_t source_a;  // the segment being inserted
  std::uint32_t source_b;  // the constraint it crossed
  double z_a;              // z interpolated along each of them; the vertex gets their mean
  double z_b;
};

// One constrained edge of the result and the input segment it is part of (source, and the
// segment's ends, whole_a -> whole_b). Overlapping constraints give one piece per source on the
// same edge.
struct Piece {
  VertexId a;
  VertexId b;
  std::uint32_t source;
  VertexId whole_a = kNoId;
  VertexId whole_b = kNoId;
};

struct ConstraintResult {
  std::uint64_t segments = 0;           // segments inserted
  std::uint64_t segments_skipped = 0;   // zero length (both ends merged into one vertex)
  std::uint64_t split_at_vertices = 0;  // times a segment ran through (or, crossing, a hair
                                        // from) an existing vertex
  std::uint64_t flips_insertion = 0;
  std::uint64_t flips_restoration = 0;
  std::vector<Crossing> crossings;
  double max_z_disagreement = 0;
  std::vector<Piece> pieces;
};

// Thrown with OnCrossing::error.
class CrossingError : public GeometryError {
 public:
  CrossingError(std::uint32_t source_a, std::uint32_t source_b, Point2 at);
  std::uint32_t source_a;
  std::uint32_t source_b;
  Point2 at;
};

// Inserts every segment into `tin`, which must be a Delaunay (or constrained Delaunay)
// triangulation holding their vertices. Termination does not rest on an iteration cap: each
// segment's crossed edges are swapped in Sloan's order, which always finds a convex quadrilateral.
ConstraintResult insert_constraints(mesh::Triangulation& tin, const std::vector<Segment>& segments,
                                    const ConstraintOptions& options = {},
                                    const ProgressFn* progress = nullptr);

// Empty if every segment with distinct ends is covered: the pieces of its source are constrained
// edges of `tin` that join its two ends. Otherwise the first problem found. (With
// Triangulation::validate(), which checks that every other edge is locally Delaunay, this is
// the whole constrained Delaunay check.)
std::string check_segments(const mesh::Triangulation& tin, const std::vector<Segment>& segments,
                           const std::vector<Piece>& pieces);

}  // namespace tincdt::constraints
