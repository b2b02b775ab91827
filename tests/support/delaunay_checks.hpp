// Independent references for Delaunay tests: the hull size by monotone chain and the empty-circle
// property by brute force; whether an input takes the two-thread path; and a hard input.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <tuple>
#include <vector>

#include "delaunay/parallel_delaunay.hpp"
#include "mesh/triangulation.hpp"
#include "predicates/predicates.hpp"

namespace tincdt::test {

// Number of convex hull vertices, collinear ones on the hull included (monotone chain).
inline std::size_t hull_vertex_count(std::vector<Point2> p) {
  std::sort(p.begin(), p.end(),
            [](Point2 a, Point2 b) { return std::tie(a.x, a.y) < std::tie(b.x, b.y); });
  p.erase(std::unique(p.begin(), p.end()), p.end());
  std::vector<Point2> h;
  auto build = [&](auto first, auto last) {
    const std::size_t base = h.size();
    for (auto it = first; it != last; ++it) {
      while (h.size() >= base + 2 && predicates::orient2d(h[h.size() - 2], h.back(), *it) < 0)
        h.pop_back();
      h.push_back(*it);
    }
    h.pop_back();
  };
  build(p.begin(), p.end());
  build(p.rbegin(), p.rend());
  return h.size();
}

// No vertex strictly inside any kept triangle's circumcircle.
inline bool globally_delaunay(const mesh::Triangulation& tin) {
  bool ok = true;
  tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& t) {
    for (VertexId v = 0; v < tin.vertex_count() && ok; ++v)
      if (predicates::incircle(tin.point(t[0]), tin.point(t[1]), tin.point(t[2]), tin.point(v)) > 0)
        ok = false;
  });
  return ok;
}

// Whether triangulate() splits POINTS in two for two threads, rather than falling back to one.
inline bool takes_parallel_path(std::vector<Point3> points) {
  BBox box;
  for (const Point3& p : points) box.add(p.x, p.y);
  delaunay::DelaunayResult result;
  return delaunay::triangulate_in_two(points, box, {}, nullptr, result);
}

// A K x K unit lattice at UTM magnitude, row by row, each coordinate moved by one ulp up, down or
// not at all (drawn from RNG): nearly cocircular everywhere.
inline std::vector<Point2> one_ulp_lattice(int k, std::mt19937_64& rng) {
  std::vector<Point2> pts;
  for (int j = 0; j < k; ++j)
    for (int i = 0; i < k; ++i) {
      double x = 500000.0 + i, y = 4000000.0 + j;
      const int dx = static_cast<int>(rng() % 3) - 1, dy = static_cast<int>(rng() % 3) - 1;
      if (dx) x = std::nextafter(x, dx > 0 ? 1e300 : -1e300);
      if (dy) y = std::nextafter(y, dy > 0 ? 1e300 : -1e300);
      pts.push_back({x, y});
    }
  return pts;
}

}  // namespace tincdt::test
