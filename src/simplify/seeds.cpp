// Seeds for a greedy run, from the same run on a thinned subset of its points.
#include <algorithm>
#include <cstring>

#include "simplify/seeds.hpp"

namespace tincdt::simplify::detail {
namespace {

// Inputs this large start from seeds (below); smaller ones are cheap enough without.
constexpr std::size_t kSeedMinPoints = std::size_t{1} << 16;
// The coarse run sees about one point in 2^kThinningBits (kThinningBits of a hash per depth),
// stops at kSeedTolerance times the tolerance and hands on all its insertions.
constexpr int kThinningBits = 4;
constexpr double kSeedTolerance = 3;

// A hash of a point's x, y bits: which points the coarse run sees depends on nothing else.
std::uint64_t xy_hash(Point2 p) {
  const auto mix = [](std::uint64_t h) {
    h ^= h >> 31;
    h *= 0x7fb5d329728ea185ULL;
    h ^= h >> 27;
    h *= 0x81dadef4bc2dd44dULL;
    return h ^ (h >> 33);
  };
  std::uint64_t x, y;
  const double px = p.x + 0.0, py = p.y + 0.0;  // -0 as +0
  std::memcpy(&x, &px, sizeof x);
  std::memcpy(&y, &py, sizeof y);
  return mix(x ^ mix(y + 0x9e3779b97f4a7c15ULL));
}

// The early insertions of the greedy loop rescan nearly every point each (the first triangles
// hold millions): O(n log k) work for the first k insertions. The same greedy run on a thinned
// subset (the kept points and segments, and about one point in 2^kThinningBits, chosen by a
// hash of x, y; other bits of it at each depth) finds nearly the same first insertions at a
// fraction of that cost. It runs to kSeedTolerance times the tolerance (the greedy run's first
// third or so of its insertions, as the vertex count needed goes about as the inverse of the
// tolerance), and all its insertions start the full run, which then refines as before.
// (Recursively: a large subset is itself seeded.) Within 1.5% in vertex count either way on the
// benchmark grids (3 rather than 4: 4-6% faster, and no more vertices). Not with a vertex budget:
// there the greedy order alone decides which vertices are in.
std::vector<std::uint32_t> coarse_seeds(const PointSet& set, std::span<const std::uint32_t> kept,
                                        std::span<const constraints::Segment> segments,
                                        const SimplifyOptions& options, int depth) {
  const std::size_t n = set.size();
  if (n < kSeedMinPoints || options.max_vertices) return {};
  // The points that must be in (few next to n), sorted: merged with the scan below, so that no
  // array of n entries is needed (fresh pages cost more than their use here). Points that are
  // not in the set are left to the full run to report.
  std::vector<std::uint32_t> must;
  const auto in_set = [&](std::uint32_t i) { return set.find(i) < n; };
  for (std::uint32_t i : kept)
    if (in_set(i)) must.push_back(i);
  for (const constraints::Segment& s : segments)
    if (in_set(s.a) && in_set(s.b)) must.insert(must.end(), {s.a, s.b});
  std::sort(must.begin(), must.end());
  must.erase(std::unique(must.begin(), must.end()), must.end());
  std::vector<Point2> sub_xy;
  std::vector<double> sub_z;
  std::vector<std::uint32_t> point_of_sub;
  const std::size_t expected = must.size() + (n >> kThinningBits) + (n >> (kThinningBits + 3));
  sub_xy.reserve(expected);
  sub_z.reserve(expected);
  point_of_sub.reserve(expected);
  const std::uint64_t mask = (std::uint64_t{1} << kThinningBits) - 1;
  std::size_t next = 0;  // in must
  for (std::size_t j = 0; j < n; ++j) {
    const std::uint32_t i = set[j];
    const bool required = next < must.size() && must[next] == i;
    next += required;
    if (!required && ((xy_hash(set.xy[i]) >> (kThinningBits * depth)) & mask) != 0) continue;
    point_of_sub.push_back(i);
    sub_xy.push_back(set.xy[i]);
    sub_z.push_back(set.z[i]);
  }
  const auto sub_of = [&](std::uint32_t i) {
    return static_cast<std::uint32_t>(
        std::lower_bound(point_of_sub.begin(), point_of_sub.end(), i) - point_of_sub.begin());
  };
  std::vector<std::uint32_t> sub_kept;
  for (std::uint32_t i : kept)
    if (in_set(i)) sub_kept.push_back(sub_of(i));
  std::vector<constraints::Segment> sub_segments;
  for (const constraints::Segment& s : segments)
    if (in_set(s.a) && in_set(s.b)) sub_segments.push_back({sub_of(s.a), sub_of(s.b), s.source});
  SimplifyOptions coarse_options = options;
  coarse_options.max_error *= kSeedTolerance;
  const Unfinished coarse =
      run_greedy({sub_xy, sub_z, {}}, sub_kept, sub_segments, coarse_options, nullptr, depth + 1);
  std::vector<std::uint32_t> seeds;
  seeds.reserve(coarse.order.size());
  for (const std::uint32_t k : coarse.order) seeds.push_back(point_of_sub[k]);
  return seeds;
}

}  // namespace

// The greedy run on the points of `set`, from the seeds coarse_seeds() finds (depth: of coarse
// runs), in `arena` (empty: its own).
Unfinished run_greedy(const PointSet& set, std::span<const std::uint32_t> kept,
                      std::span<const constraints::Segment> segments,
                      const SimplifyOptions& options, const ProgressFn* progress, int depth,
                      std::span<std::uint32_t> arena) {
  const std::vector<std::uint32_t> seeds = coarse_seeds(set, kept, segments, options, depth);
  Unfinished u{std::make_unique<Simplifier>(set, options, arena), {}};
  u.run->start(kept, segments, seeds);
  u.run->assign_points();
  u.run->run(progress);
  u.order.assign(seeds.begin(), seeds.end());
  const std::vector<std::uint32_t> order = u.run->greedy_order();
  u.order.insert(u.order.end(), order.begin(), order.end());
  return u;
}

}  // namespace tincdt::simplify::detail
