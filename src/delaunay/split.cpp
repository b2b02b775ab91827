#include "delaunay/split.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <limits>

#include "core/parallel.hpp"
#include "delaunay/half_triangulation.hpp"
#include "predicates/predicates.hpp"

namespace tincdt::delaunay::detail {
namespace {

// About one point in 4096, drawn by a hash of its coordinates.
std::vector<Point2> draw_sample(const std::vector<Point3>& input, bool concurrent) {
  const std::size_t n = input.size();
  const std::uint64_t sample_mask = std::bit_floor(std::max<std::size_t>(n / 4096, 1)) - 1;
  std::vector<Point2> part[2];
  // Multiply-xor: enough spread for a sample, and a third of point_hash()'s cost.
  const auto bits = [](double v) { return std::bit_cast<std::uint64_t>(v + 0.0); };
  const auto draw = [&](std::size_t begin, std::size_t end, std::vector<Point2>& to) {
    to.reserve(2 * (end - begin) / (sample_mask + 1) + 16);
    for (std::size_t i = begin; i < end; ++i) {
      const Point3& p = input[i];
      const std::uint64_t h = bits(p.x) * 0x9e3779b97f4a7c15ULL ^ bits(p.y) * 0xc2b2ae3d27d4eb4fULL;
      if (((h >> 40) & sample_mask) == 0) to.push_back({p.x, p.y});
    }
  };
  run_two(
      concurrent, [&] { draw(0, n / 2, part[0]); }, [&] { draw(n / 2, n, part[1]); });
  std::vector<Point2> sample = std::move(part[0]);
  sample.insert(sample.end(), part[1].begin(), part[1].end());
  return sample;
}

}  // namespace

// When the sample says it costs little balance, the split falls between two x values rather than
// inside a run of equal x (a lattice column): each half's hull then has that whole run as its
// facing side, instead of a long slanted edge over a fan of thin triangles that the merge would
// flip away.
std::optional<LeftOfPivot> choose_pivot(const std::vector<Point3>& input, bool concurrent) {
  std::vector<Point2> sample = draw_sample(input, concurrent);
  if (sample.empty()) return std::nullopt;
  std::sort(sample.begin(), sample.end(), xy_less);
  const std::size_t samples = sample.size();
  Point2 pivot = sample[samples / 2];
  const auto x_less = [](Point2 a, Point2 b) { return a.x < b.x; };
  const auto lo = std::lower_bound(sample.begin(), sample.end(), pivot, x_less);
  const auto hi = std::upper_bound(sample.begin(), sample.end(), pivot, x_less);
  const auto off_middle = [&](auto it) {
    const auto k = static_cast<std::size_t>(it - sample.begin());
    return k > samples / 2 ? k - samples / 2 : samples / 2 - k;
  };
  const std::size_t tolerance = samples / 20;  // 5 %
  constexpr double inf = std::numeric_limits<double>::infinity();
  if (off_middle(lo) <= off_middle(hi) && off_middle(lo) <= tolerance) {
    pivot.y = -inf;  // left: x < pivot.x
  } else if (off_middle(hi) <= tolerance) {
    pivot.y = inf;  // left: x <= pivot.x
  }
  return LeftOfPivot{pivot};
}

bool can_split(const std::vector<Point3>& input, LeftOfPivot is_left) {
  const std::size_t n = input.size();
  std::size_t first[2] = {n, n}, second[2] = {n, n};
  for (std::size_t i = 0; i < n && (second[0] == n || second[1] == n); ++i) {
    const Point3& p = input[i];
    const int side = is_left(p) ? 0 : 1;
    if (first[side] == n) {
      first[side] = i;
    } else if (second[side] == n && (input[first[side]].x != p.x || input[first[side]].y != p.y)) {
      second[side] = i;
    }
  }
  if (second[0] == n || second[1] == n) return false;
  const Point2 a{input[first[0]].x, input[first[0]].y};
  const Point2 b{input[second[0]].x, input[second[0]].y};
  bool off_line = false;
  for (std::size_t i = 0; i < n && !off_line; ++i)
    off_line = predicates::orient2d(a, b, {input[i].x, input[i].y}) != 0;
  return off_line;
}

}  // namespace tincdt::delaunay::detail
