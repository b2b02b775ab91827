#include "delaunay/half_triangulation.hpp"

#include <algorithm>
#include <numeric>
#include <vector>

#include "delaunay/parallel_delaunay.hpp"

namespace tincdt::delaunay {
namespace detail {

using namespace mesh;  // the half-edge vocabulary: kInfinite, ...

// Ghost (p[i+1], p[i], inf) lies on one side of edge p[i] p[i+1] and (p[i], p[i+1], inf) on the
// other; around each vertex the ghosts chain as around any hull.
void build_segment(Triangulation& tin, VertexId first, VertexId last, TriangleId slot) {
  assert(last >= first + 2);
  std::vector<VertexId> p(last - first);
  std::iota(p.begin(), p.end(), first);
  std::sort(p.begin(), p.end(),
            [&](VertexId u, VertexId v) { return xy_less(tin.point(u), tin.point(v)); });
  const auto m = static_cast<TriangleId>(p.size() - 1);
  const auto a = [&](TriangleId i) { return slot + i; };      // (p[i+1], p[i], inf)
  const auto b = [&](TriangleId i) { return slot + m + i; };  // (p[i], p[i+1], inf)
  for (TriangleId i = 0; i < m; ++i) {
    tin.set_corner(3 * a(i), p[i + 1]);
    tin.set_corner(3 * a(i) + 1, p[i]);
    tin.set_corner(3 * a(i) + 2, kInfinite);
    tin.set_corner(3 * b(i), p[i]);
    tin.set_corner(3 * b(i) + 1, p[i + 1]);
    tin.set_corner(3 * b(i) + 2, kInfinite);
    tin.link(3 * a(i), 3 * b(i));
  }
  // Ghost (u, v, inf): its v -> inf is the inf -> v of the ghost that starts at v.
  for (TriangleId i = 0; i < m; ++i) {
    tin.link(3 * a(i) + 1, 3 * (i > 0 ? a(i - 1) : b(0)) + 2);
    tin.link(3 * b(i) + 1, 3 * (i + 1 < m ? b(i + 1) : a(m - 1)) + 2);
  }
}

EdgeId find_ghost(const Triangulation& tin, TriangleId first, TriangleId last) {
  for (TriangleId t = first; t < last; ++t)
    for (EdgeId e = 3 * t; e < 3 * t + 3; ++e)
      if (tin.apex(e) == kInfinite) return e;
  throw internal_error("a half has no ghost");
}

}  // namespace detail

EdgeId triangulate_range(mesh::Triangulation& tin, VertexId first, VertexId last, TriangleId slot,
                         std::uint64_t* flips) {
  std::uint64_t count = 0;
  const EdgeId ghost =
      detail::triangulate_half(tin, first, last, slot, count, [](VertexId) { return true; });
  if (flips) *flips += count;
  return ghost;
}

}  // namespace tincdt::delaunay
