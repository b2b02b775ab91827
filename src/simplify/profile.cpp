#include "simplify/profile.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <utility>

namespace tincdt::simplify {
namespace {

// Douglas–Peucker over N points: DISTANCE(first, last, i) is how far point i is from the chord
// of its span. The first and last points and those FORCED are kept; then each span's farthest
// point beyond TOLERANCE, until none is. Ties go to the first point, so the result is a rule of
// the input alone.
template <class Distance>
std::vector<std::size_t> douglas_peucker(std::size_t n, double tolerance,
                                         std::span<const std::uint8_t> forced, Distance distance) {
  std::vector<bool> keep(n, false);
  if (n == 0) return {};
  keep.front() = keep.back() = true;
  for (std::size_t i = 0; i < forced.size() && i < n; ++i)
    if (forced[i]) keep[i] = true;
  std::vector<std::pair<std::size_t, std::size_t>> spans;
  for (std::size_t i = 0, start = 0; i < n; ++i)
    if (keep[i] && i > start) {
      spans.push_back({start, i});
      start = i;
    }
  while (!spans.empty()) {
    const auto [first, last] = spans.back();
    spans.pop_back();
    double worst = tolerance;
    std::size_t worst_at = first;
    for (std::size_t i = first + 1; i < last; ++i) {
      const double e = distance(first, last, i);
      if (e > worst) {
        worst = e;
        worst_at = i;
      }
    }
    if (worst_at == first) continue;
    keep[worst_at] = true;
    spans.push_back({worst_at, last});
    spans.push_back({first, worst_at});
  }
  std::vector<std::size_t> kept;
  for (std::size_t i = 0; i < n; ++i)
    if (keep[i]) kept.push_back(i);
  return kept;
}

// How far P is from the chord A-B: horizontally, or vertically at its projection.
double chord_distance(const Point3& a, const Point3& b, const Point3& p) {
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double length2 = dx * dx + dy * dy;
  double t = length2 > 0 ? ((p.x - a.x) * dx + (p.y - a.y) * dy) / length2 : 0;
  t = std::clamp(t, 0.0, 1.0);
  const double hx = a.x + t * dx - p.x, hy = a.y + t * dy - p.y;
  const double vertical = std::fabs(a.z + t * (b.z - a.z) - p.z);
  return std::max(std::sqrt(hx * hx + hy * hy), vertical);
}

}  // namespace

std::vector<std::size_t> simplify_profile(std::span<const double> at,
                                          std::span<const double> height, double tolerance,
                                          std::span<const std::uint8_t> forced) {
  assert(at.size() == height.size());
  return douglas_peucker(
      at.size(), tolerance, forced, [&](std::size_t first, std::size_t last, std::size_t i) {
        assert(at[first] < at[last]);
        const double slope = (height[last] - height[first]) / (at[last] - at[first]);
        return std::fabs(height[i] - (height[first] + slope * (at[i] - at[first])));
      });
}

std::vector<std::size_t> simplify_polyline(std::span<const Point3> points, double tolerance,
                                           std::span<const std::uint8_t> keep) {
  return douglas_peucker(points.size(), tolerance, keep,
                         [&](std::size_t first, std::size_t last, std::size_t i) {
                           return chord_distance(points[first], points[last], points[i]);
                         });
}

}  // namespace tincdt::simplify
