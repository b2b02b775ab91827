// Strict convex hull corners: the corners simplify() keeps so that its TIN covers every point.
#include <algorithm>
#include <numeric>

#include "predicates/predicates.hpp"
#include "simplify/simplify.hpp"

namespace tincdt::simplify {
namespace {

using predicates::orient2d;

}  // namespace

std::vector<std::uint32_t> hull_corners(std::span<const Point2> xy) {
  return hull_corners(xy, {});
}

std::vector<std::uint32_t> hull_corners(std::span<const Point2> xy,
                                        std::span<const std::uint32_t> ids) {
  const std::size_t n = ids.empty() ? xy.size() : ids.size();
  if (n == 0) return {};
  const auto id = [&](std::size_t j) {
    return ids.empty() ? static_cast<std::uint32_t>(j) : ids[j];
  };

  // Akl-Toussaint: the extreme points in 8 directions, counter-clockwise from the leftmost,
  // bound a region F (strictly left of each of their edges) that holds no hull corner: a point
  // strictly left of every edge of a closed chain of input points lies in their hull, and is
  // none of them. Which points are extreme may be decided inexactly (x + y rounds); F only
  // depends on them being input points.
  // Directions counter-clockwise from the left: -x, -x-y, -y, x-y, x, x+y, y, y-x.
  std::uint32_t ext[8];
  std::fill_n(ext, 8, id(0));
  double best[8];
  const auto keys = [](Point2 p, double(&k)[8]) {
    k[0] = -p.x, k[1] = -p.x - p.y, k[2] = -p.y, k[3] = p.x - p.y;
    k[4] = p.x, k[5] = p.x + p.y, k[6] = p.y, k[7] = p.y - p.x;
  };
  keys(xy[id(0)], best);
  for (std::size_t j = 1; j < n; ++j) {
    const std::uint32_t i = id(j);
    double k[8];
    keys(xy[i], k);
    for (int d = 0; d < 8; ++d) {
      if (k[d] > best[d]) {
        best[d] = k[d];
        ext[d] = i;
      }
    }
  }
  // The box of the points, for the fast test below: from the axis extremes.
  const double min_x = xy[ext[0]].x, max_x = xy[ext[4]].x;
  const double min_y = xy[ext[2]].y, max_y = xy[ext[6]].y;
  // Repeated extremes (one point extreme in several directions) would give edges of length 0.
  std::uint32_t chain[8];
  int m = 0;
  for (int d = 0; d < 8; ++d)
    if (m == 0 || xy[ext[d]] != xy[chain[m - 1]]) chain[m++] = ext[d];
  while (m > 1 && xy[chain[m - 1]] == xy[chain[0]]) --m;
  const auto in_f = [&](Point2 p) {
    if (m < 3) return false;
    for (int d = 0; d < m; ++d)
      if (orient2d(xy[chain[d]], xy[chain[(d + 1) % m]], p) <= 0) return false;
    return true;
  };
  // Most points are far inside: a box checked to lie in F (convex, so its corners suffice)
  // settles them with four comparisons.
  double box[4] = {0, -1, 0, -1};  // lo_x, hi_x, lo_y, hi_y; empty
  for (double margin : {1.0 / 1024, 1.0 / 16, 1.0 / 4}) {
    const double lx = min_x + (max_x - min_x) * margin, hx = max_x - (max_x - min_x) * margin;
    const double ly = min_y + (max_y - min_y) * margin, hy = max_y - (max_y - min_y) * margin;
    if (in_f({lx, ly}) && in_f({hx, ly}) && in_f({hx, hy}) && in_f({lx, hy})) {
      box[0] = lx, box[1] = hx, box[2] = ly, box[3] = hy;
      break;
    }
  }
  std::vector<std::uint32_t> rest;
  for (std::size_t j = 0; j < n; ++j) {
    const std::uint32_t i = id(j);
    const Point2 p = xy[i];
    if (p.x > box[0] && p.x < box[1] && p.y > box[2] && p.y < box[3]) continue;
    if (!in_f(p)) rest.push_back(i);
  }

  // Andrew's monotone chain on the rest, dropping collinear points.
  std::sort(rest.begin(), rest.end(),
            [&](std::uint32_t a, std::uint32_t b) { return xy_less(xy[a], xy[b]); });
  rest.erase(std::unique(rest.begin(), rest.end(),
                         [&](std::uint32_t a, std::uint32_t b) { return xy[a] == xy[b]; }),
             rest.end());
  if (rest.size() < 3) return rest;
  std::vector<std::uint32_t> hull;
  hull.reserve(2 * rest.size());
  const auto add = [&](std::uint32_t i, std::size_t floor) {
    while (hull.size() >= floor + 2 &&
           orient2d(xy[hull[hull.size() - 2]], xy[hull.back()], xy[i]) <= 0)
      hull.pop_back();
    hull.push_back(i);
  };
  for (std::uint32_t i : rest) add(i, 0);  // lower chain, left to right
  const std::size_t lower = hull.size() - 1;
  for (auto it = rest.rbegin() + 1; it != rest.rend(); ++it) add(*it, lower);  // upper
  hull.pop_back();  // the first point again
  return hull;
}

}  // namespace tincdt::simplify
