#include "pipeline/surface.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <limits>
#include <string>
#include <utility>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "mesh/point_insertion.hpp"
#include "terrain/hull_cut.hpp"
#include "terrain/interpolate.hpp"

namespace tincdt::pipeline::detail {

const char* kind_name(SourceKind kind) {
  // In the order of SourceKind's values.
  static constexpr const char* kNames[] = {"contours", "hard_lines", "soft_lines",
                                           "clip",     "erase",      "replace"};
  return kNames[static_cast<int>(kind)];
}

std::uint32_t SourceTable::add_file(std::string name) {
  files_.push_back(std::move(name));
  return static_cast<std::uint32_t>(files_.size() - 1);
}

std::uint32_t SourceTable::add(std::uint32_t file, std::int64_t fid, SourceKind kind, bool draped) {
  if (entries_.size() >= std::numeric_limits<std::uint32_t>::max() - 1)
    throw InputError(files_[file], "", "more than 2^32 - 2 vector features");
  entries_.push_back({file, fid, kind, draped});
  return static_cast<std::uint32_t>(entries_.size() - 1);
}

std::string SourceTable::describe(std::uint32_t source) const {
  if (!known(source)) return "a line";
  return file(source) + " feature " + signed_count_text(fid(source));
}

bool is_draped(SourceKind kind, const io::ShapeFeature& feature) {
  if (kind == SourceKind::soft_line || kind == SourceKind::replace) return true;
  return feature.parts.empty() || feature.parts.front().points.empty() ||
         std::isnan(feature.parts.front().points.front().z);
}

namespace {

using terrain::cut_to_hull;
using terrain::inside_or_on;
using terrain::interior_point;
using terrain::strict_hull;
using terrain::zero_area;

std::string where(std::int64_t fid) {
  return "feature " + signed_count_text(fid);
}

bool is_polygon(SourceKind kind) {
  return kind == SourceKind::clip || kind == SourceKind::erase || kind == SourceKind::replace;
}

// The parts each feature inserts, in order (one entry per feature of every input): its own, or
// for clip and erase polygons their rings cut to the hull, kept in `cut_parts`. A ring without
// area is refused, naming it.
std::vector<const std::vector<io::ShapePart>*> parts_to_insert(
    const mesh::Triangulation& tin, const std::vector<const SurfaceInput*>& inputs,
    const SourceTable& sources, const SurfaceScope& scope,
    std::deque<std::vector<io::ShapePart>>& cut_parts, SurfaceResult& result) {
  std::vector<const std::vector<io::ShapePart>*> parts_of;
  std::vector<Point2> hull;
  Point2 inside{0, 0};
  bool clip_given = false, clip_inside = false;
  for (const SurfaceInput* input : inputs) {
    const bool cut = input->kind == SourceKind::clip || input->kind == SourceKind::erase;
    if (cut && hull.empty()) {
      hull = scope.partial() ? scope.hull : strict_hull(tin);
      if (hull.size() >= 3) inside = interior_point(hull);
    }
    for (std::size_t i = 0; i < input->data.features.size(); ++i) {
      const io::ShapeFeature& f = input->data.features[i];
      const auto source = static_cast<std::uint32_t>(input->first_source + i);
      for (std::size_t r = 0; r < f.parts.size() && is_polygon(input->kind); ++r) {
        if (f.parts[r].points.size() >= 3 && !zero_area(f.parts[r].points)) continue;
        throw InputError(
            sources.file(source), where(f.fid),
            "ring " + count_text(r) + " encloses no area (its vertices lie on one line)");
      }
      if (!cut || hull.size() < 3) {
        parts_of.push_back(&f.parts);
        continue;
      }
      std::vector<io::ShapePart>& mine = cut_parts.emplace_back();
      for (const io::ShapePart& part : f.parts) {
        const bool whole =
            std::all_of(part.points.begin(), part.points.end(), [&](const Point3& p) {
              return inside_or_on(hull, {p.x, p.y});
            });
        if (whole) {
          mine.push_back(part);
          continue;
        }
        io::ShapePart piece{cut_to_hull(part.points, hull, inside), true};
        if (piece.points.empty()) {
          ++result.rings_outside;
        } else {
          ++result.rings_cut;
          mine.push_back(std::move(piece));
        }
      }
      if (input->kind == SourceKind::clip) {
        clip_given = true;
        clip_inside = clip_inside || !mine.empty();
      }
      parts_of.push_back(&mine);
    }
  }
  if (clip_given && !clip_inside) {
    const SurfaceInput* clip = *std::find_if(
        inputs.begin(), inputs.end(), [](const auto* in) { return in->kind == SourceKind::clip; });
    throw InputError(sources.file(clip->first_source), "",
                     "the clip polygons lie wholly outside the TIN of the points and hard "
                     "lines: nothing would be left (are they in another place or CRS?)");
  }
  return parts_of;
}

// The z of every vertex of every part, in order: draped ones from the TIN as it is, before
// anything is inserted.
std::vector<double> part_heights(const mesh::Triangulation& tin,
                                 const std::vector<const SurfaceInput*>& inputs,
                                 const SourceTable& sources, const SurfaceScope& scope,
                                 const std::vector<const std::vector<io::ShapePart>*>& parts_of,
                                 SurfaceResult& result) {
  std::vector<double> z;
  terrain::SurfaceSampler sampler(tin);
  std::size_t feature = 0;
  for (const SurfaceInput* input : inputs) {
    for (std::size_t i = 0; i < input->data.features.size(); ++i) {
      const io::ShapeFeature& f = input->data.features[i];
      const auto source = static_cast<std::uint32_t>(input->first_source + i);
      const bool draped = sources.draped(source);
      for (const io::ShapePart& part : *parts_of[feature++]) {
        for (const Point3& p : part.points) {
          ++result.vertices;
          if (!draped) {
            z.push_back(p.z);
            continue;
          }
          double h = sampler.z_at({p.x, p.y});
          if (scope.settled && !std::isnan(h) && !scope.settled(tin, sampler.last_triangle()))
            h = std::numeric_limits<double>::quiet_NaN();
          // Outside the whole data's hull there is no TIN; elsewhere a job over part of the data
          // may lack it.
          if (std::isnan(h) && (!scope.partial() || !inside_or_on(scope.hull, {p.x, p.y}))) {
            char at[80];
            std::snprintf(at, sizeof at, "(%.3f, %.3f)", p.x, p.y);
            const char* what = input->kind == SourceKind::soft_line ? "a soft line"
                               : input->kind == SourceKind::replace ? "a replace polygon"
                                                                    : "a 2D polygon ring";
            throw InputError(sources.file(source), where(f.fid),
                             std::string("vertex ") + at + " lies outside the TIN: " + what +
                                 " must lie on the TIN of the points and hard lines, which "
                                 "covers only their convex hull (cut the feature to the data)");
          }
          z.push_back(h);
          ++result.draped;
          if (input->kind == SourceKind::soft_line) ++result.soft_line_vertices;
        }
      }
    }
  }
  return z;
}

// Inserts the vertices of every part (one on an existing vertex reuses it) and appends the
// parts' segments to `segments`.
void insert_part_vertices(mesh::Triangulation& tin, const std::vector<const SurfaceInput*>& inputs,
                          const std::vector<const std::vector<io::ShapePart>*>& parts_of,
                          const std::vector<double>& z, std::vector<constraints::Segment>& segments,
                          SurfaceResult& result) {
  if (!tin.has_vertex_index()) tin.build_vertex_index();
  mesh::PointInserter inserter(tin);
  std::size_t k = 0, feature = 0;
  std::vector<VertexId> ids;
  for (const SurfaceInput* input : inputs) {
    for (std::size_t i = 0; i < input->data.features.size(); ++i) {
      const auto source = static_cast<std::uint32_t>(input->first_source + i);
      for (const io::ShapePart& part : *parts_of[feature++]) {
        ids.clear();
        for (const Point3& p : part.points) {
          const Point2 xy{p.x, p.y};
          const mesh::Location at = inserter.locate(xy);
          if (at.kind == mesh::Location::on_vertex) {
            ids.push_back(tin.origin(at.edge));
            ++result.reused;
          } else {
            const VertexId v = tin.add_vertex(xy, z[k]);
            inserter.insert(v, at);
            ids.push_back(v);
          }
          ++k;
        }
        for (std::size_t j = 0; j + 1 < ids.size(); ++j)
          segments.push_back({ids[j], ids[j + 1], source});
        if (part.closed && ids.size() > 2) segments.push_back({ids.back(), ids.front(), source});
      }
    }
  }
  tin.recount();
}

}  // namespace

SurfaceResult insert_surface_features(mesh::Triangulation& tin,
                                      const std::vector<const SurfaceInput*>& inputs,
                                      const SourceTable& sources,
                                      const std::vector<constraints::Piece>& hard_pieces,
                                      constraints::Restore restore, const ProgressFn* progress,
                                      const SurfaceScope& scope) {
  SurfaceResult result;
  std::deque<std::vector<io::ShapePart>> cut_parts;
  const auto parts_of = parts_to_insert(tin, inputs, sources, scope, cut_parts, result);
  const std::vector<double> z = part_heights(tin, inputs, sources, scope, parts_of, result);

  std::vector<constraints::Segment> segments;
  segments.reserve(hard_pieces.size() + result.vertices);
  for (const constraints::Piece& p : hard_pieces)
    segments.push_back({p.a, p.b, p.source, p.whole_a, p.whole_b});
  insert_part_vertices(tin, inputs, parts_of, z, segments, result);
  result.segments = segments.size() - hard_pieces.size();

  constraints::ConstraintOptions options;
  options.restore = restore;
  options.on_crossing = constraints::OnCrossing::split;  // crossing hard lines is what they do
  result.constraints = constraints::insert_constraints(tin, segments, options, progress);
  result.given.assign(segments.begin() + static_cast<std::ptrdiff_t>(hard_pieces.size()),
                      segments.end());

  // A draped constraint crossing one with its own z takes that z there.
  for (const constraints::Crossing& x : result.constraints.crossings) {
    if (!sources.known(x.source_a) || !sources.known(x.source_b)) continue;
    const bool draped_a = sources.draped(x.source_a), draped_b = sources.draped(x.source_b);
    if (draped_a == draped_b) continue;
    tin.set_z(x.vertex, draped_a ? x.z_b : x.z_a);
    ++result.crossings_with_hard_z;
  }
  return result;
}

std::vector<terrain::Polygon> polygons_of(const io::ShapeData& data) {
  std::vector<terrain::Polygon> polygons;
  polygons.reserve(data.features.size());
  for (const io::ShapeFeature& f : data.features) {
    terrain::Polygon polygon;
    polygon.z = f.z;
    for (const io::ShapePart& part : f.parts) {
      std::vector<Point2> ring;
      ring.reserve(part.points.size());
      for (const Point3& p : part.points) ring.push_back({p.x, p.y});
      polygon.rings.push_back(std::move(ring));
    }
    polygons.push_back(std::move(polygon));
  }
  return polygons;
}

std::vector<std::uint8_t> contour_flags(const mesh::Triangulation& tin,
                                        const std::vector<constraints::Piece>& pieces,
                                        const SourceTable& sources) {
  std::vector<std::uint8_t> on(tin.vertex_count(), 0);
  for (const constraints::Piece& p : pieces) {
    if (!sources.known(p.source) || sources.kind(p.source) != SourceKind::contour) continue;
    on[p.a] = 1;
    on[p.b] = 1;
  }
  return on;
}

}  // namespace tincdt::pipeline::detail
