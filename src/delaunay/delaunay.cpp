#include "delaunay/delaunay.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "core/memory.hpp"
#include "core/number_text.hpp"
#include "delaunay/parallel_delaunay.hpp"
#include "delaunay/spatial_order.hpp"
#include "mesh/point_insertion.hpp"
#include "predicates/predicates.hpp"

namespace tincdt::delaunay {

using mesh::Triangulation;

DelaunayResult triangulate(std::vector<Point3>&& points, const DelaunayOptions& options,
                           const ProgressFn* progress) {
  std::vector<Point3> input = std::move(points);
  const std::size_t n = input.size();
  if (n >= mesh::kInfinite) throw GeometryError("too many points for 32-bit vertex ids");

  BBox box;
  for (std::size_t i = 0; i < n; ++i) {
    Point3& p = input[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw GeometryError("point " + count_text(i) + " has a non-finite coordinate");
    // -0.0 becomes 0.0 (x + 0.0 changes nothing else): one point, one key, one text.
    p.x += 0.0;
    p.y += 0.0;
    p.z += 0.0;
    box.add(p.x, p.y);
  }

  DelaunayResult result;
  // Whether to split depends on the point count alone, never on the threads: one thread or two
  // give the same bits.
  if (n >= options.parallel_min_points && triangulate_in_two(input, box, options, progress, result))
    return result;

  Triangulation& tin = result.tin;
  {
    // Vertices in insertion order, equal x, y merged.
    const std::vector<std::uint32_t> order = insertion_order(input, box, options.threads);
    if (options.keep_point_map) result.vertex_of_point.assign(n, kNoId);
    tin.reserve_vertices(n);
    MergedZ merged{};
    for (std::uint32_t i : order) {
      const Point3& p = input[i];
      const std::size_t nv = tin.vertex_count();
      if (nv > 0 && tin.point(static_cast<VertexId>(nv - 1)) == Point2{p.x, p.y}) {
        const auto v = static_cast<VertexId>(nv - 1);
        if (options.keep_duplicates)
          record_duplicate(result.duplicates, v, merged.z, p.z, merged.count + 1);
        merged.add(p.z, i, options.on_duplicate);
        tin.set_z(v, merged.z);
        ++result.duplicates_merged;
      } else {
        tin.add_vertex({p.x, p.y}, p.z);
        merged = MergedZ::start(p.z, i);
      }
      if (options.keep_point_map)
        result.vertex_of_point[i] = static_cast<VertexId>(tin.vertex_count() - 1);
    }
  }
  release(input);  // before the triangles take its space

  const auto nv = static_cast<VertexId>(tin.vertex_count());
  if (nv < 3)
    throw GeometryError("fewer than 3 distinct points (" + count_text(nv) +
                        "): nothing to triangulate");
  // The first triangle: vertices 0, 1 and the first one not collinear with them.
  VertexId third = 2;
  int turn = 0;
  for (; third < nv; ++third) {
    turn = predicates::orient2d(tin.point(0), tin.point(1), tin.point(third));
    if (turn != 0) break;
  }
  if (third == nv) throw GeometryError("all points are collinear: no triangle can be formed");

  tin.reserve_triangles(2 * static_cast<std::size_t>(nv));
  mesh::PointInserter inserter(tin);
  if (turn > 0) {
    inserter.start(0, 1, third);
  } else {
    inserter.start(1, 0, third);
  }
  Progress report(progress, "delaunay", nv);
  for (VertexId v = 2; v < nv; ++v) {
    if (v == third) continue;
    inserter.insert(v);
    report.tick(v);
  }
  report.finish();
  result.flips = inserter.flips();
  tin.recount();
  return result;
}

}  // namespace tincdt::delaunay
