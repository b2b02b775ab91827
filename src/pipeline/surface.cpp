#include "pipeline/surface.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>

#include "core/error.hpp"
#include "mesh/point_insertion.hpp"
#include "terrain/interpolate.hpp"

namespace tincdt::pipeline::detail {

const char* kind_name(SourceKind kind) {
  switch (kind) {
    case SourceKind::contour:
      return "contours";
    case SourceKind::hard_line:
      return "hard_lines";
    case SourceKind::soft_line:
      return "soft_lines";
    case SourceKind::clip:
      return "clip";
    case SourceKind::erase:
      return "erase";
    case SourceKind::replace:
      return "replace";
  }
  return "?";
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
  return file(source) + " feature " + std::to_string(fid(source));
}

bool is_draped(SourceKind kind, const io::ShapeFeature& feature) {
  if (kind == SourceKind::soft_line || kind == SourceKind::replace) return true;
  return feature.parts.empty() || feature.parts.front().points.empty() ||
         std::isnan(feature.parts.front().points.front().z);
}

namespace {

std::string where(std::int64_t fid) {
  return "feature " + std::to_string(fid);
}

}  // namespace

SurfaceResult insert_surface_features(mesh::Triangulation& tin,
                                      const std::vector<const SurfaceInput*>& inputs,
                                      const SourceTable& sources,
                                      const std::vector<constraints::Piece>& hard_pieces,
                                      constraints::Restore restore, const ProgressFn* progress) {
  SurfaceResult result;

  // 1. Heights: draped ones from the TIN as it is, before anything is inserted.
  std::vector<double> z;  // per vertex of every part of every feature, in order
  {
    terrain::SurfaceSampler sampler(tin);
    for (const SurfaceInput* input : inputs) {
      for (std::size_t i = 0; i < input->data.features.size(); ++i) {
        const io::ShapeFeature& f = input->data.features[i];
        const auto source = static_cast<std::uint32_t>(input->first_source + i);
        const bool draped = sources.draped(source);
        for (const io::ShapePart& part : f.parts) {
          for (const Point3& p : part.points) {
            ++result.vertices;
            if (!draped) {
              z.push_back(p.z);
              continue;
            }
            const double h = sampler.z_at({p.x, p.y});
            if (std::isnan(h)) {
              char at[80];
              std::snprintf(at, sizeof at, "(%.3f, %.3f)", p.x, p.y);
              throw InputError(
                  sources.file(source), where(f.fid),
                  std::string("vertex ") + at + " lies outside the TIN: a " +
                      (input->kind == SourceKind::soft_line ? "soft line" : "2D polygon ring") +
                      " is draped on the TIN of the points and hard lines, which "
                      "covers only their convex hull (cut the feature to the data)");
            }
            z.push_back(h);
            ++result.draped;
            if (input->kind == SourceKind::soft_line) ++result.soft_line_vertices;
          }
        }
      }
    }
  }

  // 2. Vertices, 3. segments.
  if (!tin.has_vertex_index()) tin.build_vertex_index();
  mesh::PointInserter inserter(tin);
  std::vector<constraints::Segment> segments;
  segments.reserve(hard_pieces.size() + result.vertices);
  for (const constraints::Piece& p : hard_pieces) segments.push_back({p.a, p.b, p.source});
  std::size_t k = 0;
  std::vector<VertexId> ids;
  for (const SurfaceInput* input : inputs) {
    for (std::size_t i = 0; i < input->data.features.size(); ++i) {
      const auto source = static_cast<std::uint32_t>(input->first_source + i);
      for (const io::ShapePart& part : input->data.features[i].parts) {
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
  result.segments = segments.size() - hard_pieces.size();

  constraints::ConstraintOptions options;
  options.restore = restore;
  options.on_crossing = constraints::OnCrossing::split;  // crossing hard lines is what they do
  result.constraints = constraints::insert_constraints(tin, segments, options, progress);
  result.given.assign(segments.begin() + static_cast<std::ptrdiff_t>(hard_pieces.size()),
                      segments.end());

  // 4. A draped constraint crossing one with its own z takes that z there.
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
