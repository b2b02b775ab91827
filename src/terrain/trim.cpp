#include "terrain/trim.hpp"

#include <array>
#include <cassert>
#include <cmath>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "terrain/interpolate.hpp"
#include "terrain/regions.hpp"

namespace tincdt::terrain {

bool has_long_edge(const mesh::Triangulation& tin, TriangleId t, double max_edge,
                   const TrimOptions& options) {
  const double limit2 = max_edge * max_edge;  // compare squared lengths: no sqrt per edge
  const auto c = tin.triangle(t);
  for (int i = 0; i < 3; ++i) {
    if (!options.constrained_edges_count && tin.is_constrained(3 * t + static_cast<EdgeId>(i)))
      continue;
    const Point2 p = tin.point(c[i]), q = tin.point(c[(i + 1) % 3]);
    const double dx = p.x - q.x, dy = p.y - q.y;
    if (dx * dx + dy * dy > limit2) return true;
  }
  return false;
}

std::uint64_t trim_long_edges(mesh::Triangulation& tin, double max_edge,
                              const TrimOptions& options) {
  if (!(max_edge > 0))
    throw Error("max edge length must be positive, not " + number_text(max_edge));
  if (std::isinf(max_edge)) return 0;
  const auto neighbour = [&](TriangleId t, int i) {
    return mesh::triangle_of(tin.twin(3 * t + static_cast<EdgeId>(i)));
  };

  // Seed with the kept triangles on the boundary; afterwards only the neighbours of removed
  // triangles can become boundary triangles, so the work is proportional to what is removed
  // plus the boundary, never a rescan of the whole TIN.
  std::vector<TriangleId> queue;
  const auto slots = static_cast<TriangleId>(tin.triangle_slots());
  for (TriangleId t = 0; t < slots; ++t) {
    if (!tin.is_kept(t)) continue;
    for (int i = 0; i < 3; ++i)
      if (!tin.is_kept(neighbour(t, i))) {
        queue.push_back(t);
        break;
      }
  }

  std::uint64_t removed = 0;
  while (!queue.empty()) {
    const TriangleId t = queue.back();
    queue.pop_back();
    // A triangle may be queued once per removed neighbour: the kept check makes repeats free.
    if (!tin.is_kept(t) || !has_long_edge(tin, t, max_edge, options)) continue;
    tin.set_removed(t, true);
    ++removed;
    for (int i = 0; i < 3; ++i) {
      const TriangleId n = neighbour(t, i);
      if (tin.is_kept(n)) queue.push_back(n);
    }
  }
  return removed;
}

std::vector<std::uint8_t> trim_and_fence(mesh::Triangulation& tin, double max_edge) {
  trim_long_edges(tin, max_edge);
  const auto slots = static_cast<TriangleId>(tin.triangle_slots());
  std::vector<std::uint8_t> trimmed(slots, 0);
  for (TriangleId t = 0; t < slots; ++t) trimmed[t] = !tin.is_ghost(t) && tin.is_removed(t);
  fence_trimmed(tin, trimmed);
  return trimmed;
}

void fence_trimmed(mesh::Triangulation& tin, const std::vector<std::uint8_t>& trimmed) {
  const auto slots = static_cast<TriangleId>(tin.triangle_slots());
  assert(trimmed.size() == slots);
  for (TriangleId t = 0; t < slots; ++t) {
    if (!trimmed[t]) continue;
    for (EdgeId e = 3 * t; e < 3 * t + 3; ++e) {
      const TriangleId n = mesh::triangle_of(tin.twin(e));
      if (tin.is_ghost(n) || trimmed[n]) continue;
      tin.set_constrained(e, true);
      tin.set_constrained(tin.twin(e), true);
    }
  }
}

std::vector<std::uint8_t> mark_trimmed_areas(const mesh::Triangulation& full,
                                             const std::vector<std::uint8_t>& trimmed,
                                             const mesh::Triangulation& simplified) {
  std::vector<std::uint8_t> marked(simplified.triangle_slots(), 0);
  SurfaceSampler sampler(full);
  simplified.for_each_triangle([&](TriangleId t, const std::array<VertexId, 3>& c) {
    const Point2 a = simplified.point(c[0]), b = simplified.point(c[1]), d = simplified.point(c[2]);
    const TriangleId in = sampler.locate({(a.x + b.x + d.x) / 3, (a.y + b.y + d.y) / 3});
    marked[t] = in != kNoId && in < trimmed.size() && trimmed[in];
  });
  return marked;
}

std::uint64_t remove_marked_regions(mesh::Triangulation& tin,
                                    const std::vector<std::uint8_t>& marked) {
  std::uint64_t removed = 0;
  const auto all = [](TriangleId) { return true; };
  for_each_region(tin, all, [&](std::span<const TriangleId> members) {
    const TriangleId largest =
        largest_triangle(tin, members, static_cast<TriangleId>(marked.size()));
    if (largest == kNoId || !marked[largest]) return;
    for (const TriangleId t : members) {
      if (!tin.is_kept(t)) continue;
      tin.set_removed(t, true);
      ++removed;
    }
  });
  return removed;
}

}  // namespace tincdt::terrain
