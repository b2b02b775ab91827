// The public entry points: the whole simplification is the regions' runs when they apply (see
// regions.cpp), then the run on all points, seeded by them, which adopts the triangles it
// shares with them (see adopt.cpp); else one greedy run, from seeds (see seeds.cpp).
#include "simplify/simplify.hpp"

#include <memory>
#include <string_view>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "predicates/predicates.hpp"
#include "simplify/regions.hpp"
#include "simplify/seeds.hpp"
#include "simplify/simplifier.hpp"

namespace tincdt::simplify {
namespace {

using detail::kMaxPoints;
using detail::kRegionProgress;
using detail::PointSet;
using detail::Simplifier;
using mesh::kInfinite;
using mesh::next_edge;
using mesh::triangle_of;

// The regions' runs when they apply, then the run on all points, seeded by them, which adopts
// the triangles it shares with them.
SimplifyResult simplify_all(const PointSet& set, std::span<const std::uint32_t> kept,
                            std::span<const constraints::Segment> segments,
                            const SimplifyOptions& options, const ProgressFn* progress) {
  if (set.size() > kMaxPoints)  // before any work, and before ids are narrowed to 32 bits
    throw GeometryError("simplify: too many points for 32-bit ids");
  detail::Regions regions = detail::run_regions(set, kept, segments, options, progress);
  if (regions.runs.empty())
    return detail::run_greedy(set, kept, segments, options, progress, 0).run->finish();
  ProgressFn rest;
  if (progress && *progress)
    rest = [progress](std::string_view stage, double fraction) {
      return (*progress)(stage, kRegionProgress + (1 - kRegionProgress) * fraction);
    };
  const std::unique_ptr<std::uint32_t[]> arena = std::move(regions.arena);
  Simplifier s(set, options, {arena.get(), regions.arena_size});
  s.start(kept, segments, regions.seeds);
  std::uint32_t ran = 0;
  {
    std::vector<Simplifier::Part> parts;
    for (std::size_t r = 0; r < regions.runs.size(); ++r) {
      parts.push_back({regions.runs[r].run.get(), regions.members[r]});
      ran += parts.back().run != nullptr;
    }
    s.adopt(parts);
  }
  regions = {};  // their memory, before the run needs more
  s.run(progress ? &rest : nullptr);
  SimplifyResult out = s.finish();
  out.report.regions = ran;
  return out;
}

}  // namespace

SimplifyResult simplify(std::span<const Point2> xy, std::span<const double> z,
                        std::span<const std::uint32_t> kept,
                        std::span<const constraints::Segment> segments,
                        const SimplifyOptions& options, const ProgressFn* progress) {
  std::vector<std::uint32_t> all = hull_corners(xy);
  all.insert(all.end(), kept.begin(), kept.end());
  return simplify_all({xy, z, {}}, all, segments, options, progress);
}

SimplifyResult simplify_tin(const mesh::Triangulation& full, const SimplifyOptions& options,
                            const ProgressFn* progress) {
  std::vector<std::uint32_t> kept;
  std::vector<constraints::Segment> segments;
  full.for_each_constrained_edge([&](EdgeId e) {
    segments.push_back({full.origin(e), full.dest(e), 0});
  });
  // Strict hull corners, around the ring of ghosts (not a pass over every triangle, which reads
  // 400 MB on a 16M-point TIN): ghost (u, v, inf) lies outside hull edge v -> u, and the ghost
  // across its edge v -> inf lies outside the hull edge w -> v before it.
  const std::size_t slots = full.triangle_slots();
  TriangleId first = 0;
  while (first < slots && !full.is_ghost(first)) ++first;
  TriangleId t = first;
  for (std::size_t steps = 0; first < slots; ++steps) {
    if (steps == slots) throw InternalError("simplify: the ghosts are not one ring");
    const auto tri = full.triangle(t);
    int k = 0;
    while (k < 3 && tri[k] != kInfinite) ++k;
    const VertexId u = tri[(k + 1) % 3], v = tri[(k + 2) % 3];
    const EdgeId inf_v = full.twin(3 * t + static_cast<EdgeId>((k + 2) % 3));
    const VertexId w = full.dest(next_edge(inf_v));
    if (predicates::orient2d(full.point(w), full.point(v), full.point(u)) != 0) kept.push_back(v);
    t = triangle_of(inf_v);
    if (t == first) break;
  }
  return simplify_all({full.points(), full.heights(), {}}, kept, segments, options, progress);
}

}  // namespace tincdt::simplify
