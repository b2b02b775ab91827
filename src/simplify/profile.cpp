#include "simplify/profile.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <utility>

namespace tincdt::simplify {

std::vector<std::size_t> simplify_profile(std::span<const double> at,
                                          std::span<const double> height, double tolerance,
                                          std::span<const std::uint8_t> forced) {
  assert(at.size() == height.size());
  const std::size_t n = at.size();
  if (n <= 2) {
    std::vector<std::size_t> all(n);
    for (std::size_t i = 0; i < n; ++i) all[i] = i;
    return all;
  }
  std::vector<bool> keep(n, false);
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
    assert(at[first] < at[last]);
    const double slope = (height[last] - height[first]) / (at[last] - at[first]);
    double worst = tolerance;
    std::size_t worst_at = first;
    for (std::size_t i = first + 1; i < last; ++i) {
      const double e = std::fabs(height[i] - (height[first] + slope * (at[i] - at[first])));
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

}  // namespace tincdt::simplify

namespace tincdt::simplify {
namespace {

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

std::vector<std::size_t> simplify_polyline(std::span<const Point3> points, double tolerance,
                                           std::span<const std::uint8_t> keep) {
  const std::size_t n = points.size();
  std::vector<bool> kept(n, false);
  if (n == 0) return {};
  kept.front() = kept.back() = true;
  for (std::size_t i = 0; i < keep.size() && i < n; ++i)
    if (keep[i]) kept[i] = true;
  std::vector<std::pair<std::size_t, std::size_t>> spans;
  for (std::size_t i = 0, start = 0; i < n; ++i)
    if (kept[i] && i > start) {
      spans.push_back({start, i});
      start = i;
    }
  while (!spans.empty()) {
    const auto [first, last] = spans.back();
    spans.pop_back();
    double worst = tolerance;
    std::size_t worst_at = first;
    for (std::size_t i = first + 1; i < last; ++i) {
      const double e = chord_distance(points[first], points[last], points[i]);
      if (e > worst) {
        worst = e;
        worst_at = i;
      }
    }
    if (worst_at == first) continue;
    kept[worst_at] = true;
    spans.push_back({worst_at, last});
    spans.push_back({first, worst_at});
  }
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < n; ++i)
    if (kept[i]) out.push_back(i);
  return out;
}

}  // namespace tincdt::simplify
