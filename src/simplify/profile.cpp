#include "simplify/profile.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <utility>

namespace tincdt::simplify {

std::vector<std::size_t> simplify_profile(std::span<const double> at,
                                          std::span<const double> height, double tolerance) {
  assert(at.size() == height.size());
  const std::size_t n = at.size();
  if (n <= 2) {
    std::vector<std::size_t> all(n);
    for (std::size_t i = 0; i < n; ++i) all[i] = i;
    return all;
  }
  std::vector<bool> keep(n, false);
  keep.front() = keep.back() = true;
  std::vector<std::pair<std::size_t, std::size_t>> spans{{0, n - 1}};
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
