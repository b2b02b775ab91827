// The merge of two separable Delaunay triangulations (see parallel_delaunay.hpp): the common
// tangents, the facing hull chains, the zipper that fills the gap between them, the relinking of
// the old ghosts' neighbours, and the Lawson flips that make every new edge locally Delaunay.
#include <algorithm>
#include <cassert>
#include <cstdint>
#include <utility>
#include <vector>

#include "delaunay/half_triangulation.hpp"
#include "delaunay/parallel_delaunay.hpp"
#include "predicates/predicates.hpp"

namespace tincdt::delaunay {
namespace {
using namespace mesh;  // the half-edge vocabulary: next_edge, triangle_of, kInfinite, ...
using detail::internal_error;

// A hull edge is named by the finite half-edge g of its ghost (apex infinite): g runs v -> u for
// the hull edge u -> v, which has the hull's inside on its left (counter-clockwise order).
class Hull {
 public:
  explicit Hull(const Triangulation& tin) : tin_(tin) {}
  VertexId from(EdgeId g) const { return tin_.dest(g); }
  VertexId to(EdgeId g) const { return tin_.origin(g); }
  // The next hull edge counter-clockwise (starting where g ends) and the previous one.
  EdgeId next(EdgeId g) const { return prev_edge(tin_.twin(prev_edge(g))); }
  EdgeId prev(EdgeId g) const { return next_edge(tin_.twin(next_edge(g))); }
  Point2 at(VertexId v) const { return tin_.point(v); }
  int orient(VertexId a, VertexId b, VertexId c) const {
    return predicates::orient2d(tin_.point(a), tin_.point(b), tin_.point(c));
  }

 private:
  const Triangulation& tin_;
};

// The left hull edge leaving the lexicographically largest left vertex and the right one
// arriving at the smallest right vertex (where both tangent searches start), and the hull sizes.
struct HullEnds {
  EdgeId left_out = kNoId, right_in = kNoId;
  std::size_t left_size = 0, right_size = 0;
};

HullEnds find_hull_ends(const Triangulation& tin, const Hull& hull, EdgeId left_ghost,
                        EdgeId right_ghost) {
  assert(tin.apex(left_ghost) == kInfinite && tin.apex(right_ghost) == kInfinite);
  HullEnds ends;
  ends.left_out = left_ghost;
  for (EdgeId g = left_ghost;;) {
    if (xy_less(hull.at(hull.from(ends.left_out)), hull.at(hull.from(g)))) ends.left_out = g;
    ++ends.left_size;
    g = hull.next(g);
    if (g == left_ghost) break;
    if (ends.left_size > 2 * tin.vertex_count()) throw internal_error("left hull does not close");
  }
  ends.right_in = right_ghost;
  for (EdgeId g = right_ghost;;) {
    if (xy_less(hull.at(hull.to(g)), hull.at(hull.to(ends.right_in)))) ends.right_in = g;
    ++ends.right_size;
    g = hull.next(g);
    if (g == right_ghost) break;
    if (ends.right_size > 2 * tin.vertex_count()) throw internal_error("right hull does not close");
  }
  // The halves are separable: the largest left vertex is below the smallest right one.
  assert(xy_less(hull.at(hull.from(ends.left_out)), hull.at(hull.to(ends.right_in))));
  return ends;
}

// The lower tangent l0 -> r0 with the hull edges gl (leaving l0) and gr (arriving at r0), and the
// upper one lt -> rt with ga (arriving at lt) and gb (leaving rt).
struct Tangents {
  EdgeId gl, gr, ga, gb;
  VertexId l0, r0, lt, rt;
};

Tangents find_tangents(const Hull& hull, const HullEnds& ends) {
  const std::size_t step_limit = 2 * (ends.left_size + ends.right_size) + 8;
  Tangents t{};
  // Lower: every point on or left of it; when points are collinear with it, the two closest
  // ones (a hull edge of the union must not pass over a vertex).
  t.gl = ends.left_out;
  t.gr = ends.right_in;
  t.l0 = hull.from(t.gl);
  t.r0 = hull.to(t.gr);
  for (std::size_t steps = 0;; ++steps) {
    if (steps > step_limit) throw internal_error("lower tangent search does not end");
    const EdgeId cl = hull.prev(t.gl);  // arrives at l0 from its clockwise neighbour
    if (hull.orient(t.l0, t.r0, hull.from(cl)) < 0) {
      t.gl = cl;
      t.l0 = hull.from(t.gl);
      continue;
    }
    const EdgeId cr = hull.next(t.gr);  // leaves r0 to its counter-clockwise neighbour
    if (hull.orient(t.l0, t.r0, hull.to(cr)) < 0) {
      t.gr = cr;
      t.r0 = hull.to(t.gr);
      continue;
    }
    break;
  }
  // Upper (the union hull runs rt -> lt): every point on or right of it.
  t.ga = hull.prev(ends.left_out);
  t.gb = hull.next(ends.right_in);
  t.lt = hull.to(t.ga);
  t.rt = hull.from(t.gb);
  for (std::size_t steps = 0;; ++steps) {
    if (steps > step_limit) throw internal_error("upper tangent search does not end");
    const EdgeId cl = hull.next(t.ga);
    if (hull.orient(t.lt, t.rt, hull.to(cl)) > 0) {
      t.ga = cl;
      t.lt = hull.to(t.ga);
      continue;
    }
    const EdgeId cr = hull.prev(t.gb);
    if (hull.orient(t.lt, t.rt, hull.from(cr)) > 0) {
      t.gb = cr;
      t.rt = hull.from(t.gb);
      continue;
    }
    break;
  }
  return t;
}

// The facing chains: left l0 -> ... -> lt counter-clockwise, right r0 -> ... -> rt clockwise, as
// the ghost half-edges of their hull edges and their vertices (one more). When a tangent point is
// shared (l0 == lt) the chain is either empty or, if the other half sees the hull edge after it,
// the whole hull (the half lies inside the union's hull but for that vertex).
struct Chains {
  bool left_all = false, right_all = false;
  std::vector<EdgeId> left, right;
  std::vector<VertexId> lv, rv;
};

Chains facing_chains(const Hull& hull, const Tangents& t, const HullEnds& ends) {
  Chains c;
  if (t.l0 == t.lt) {
    const VertexId s = hull.to(t.gl);
    c.left_all = hull.orient(t.l0, s, t.r0) < 0 || hull.orient(t.l0, s, t.rt) < 0;
  }
  if (t.r0 == t.rt) {
    const VertexId s = hull.from(t.gr);
    c.right_all = hull.orient(s, t.r0, t.l0) < 0 || hull.orient(s, t.r0, t.lt) < 0;
  }
  c.lv = {t.l0};
  c.rv = {t.r0};
  if (t.l0 != t.lt || c.left_all) {
    for (EdgeId g = t.gl;; g = hull.next(g)) {
      c.left.push_back(g);
      c.lv.push_back(hull.to(g));
      if (g == t.ga) break;
      if (c.left.size() > ends.left_size) throw internal_error("left chain does not reach lt");
    }
  }
  if (t.r0 != t.rt || c.right_all) {
    for (EdgeId g = t.gr;; g = hull.prev(g)) {
      c.right.push_back(g);
      c.rv.push_back(hull.from(g));
      if (g == t.gb) break;
      if (c.right.size() > ends.right_size) throw internal_error("right chain does not reach rt");
    }
  }
  if (c.lv.back() != t.lt || c.rv.back() != t.rt)
    throw internal_error("chains end off the tangents");
  return c;
}

// What the chain ghosts link to outside, read before their slots are reused: the twins of the
// chain half-edges and the ghost edges around the tangent points (kNoId for a whole-hull chain).
struct Outside {
  std::vector<EdgeId> left, right;
  EdgeId into_l0, out_of_lt, out_of_r0, into_rt;
};

Outside read_outside(const Triangulation& tin, const Tangents& t, const Chains& c) {
  Outside o;
  o.left.resize(c.left.size());
  o.right.resize(c.right.size());
  for (std::size_t i = 0; i < c.left.size(); ++i) o.left[i] = tin.twin(c.left[i]);
  for (std::size_t j = 0; j < c.right.size(); ++j) o.right[j] = tin.twin(c.right[j]);
  o.into_l0 = c.left_all ? kNoId : tin.twin(next_edge(t.gl));     // inf -> l0
  o.out_of_lt = c.left_all ? kNoId : tin.twin(prev_edge(t.ga));   // lt -> inf
  o.out_of_r0 = c.right_all ? kNoId : tin.twin(prev_edge(t.gr));  // r0 -> inf
  o.into_rt = c.right_all ? kNoId : tin.twin(next_edge(t.gb));    // inf -> rt
  return o;
}

void set_triangle(Triangulation& tin, TriangleId t, VertexId x, VertexId y, VertexId z) {
  tin.set_corner(3 * t, x);
  tin.set_corner(3 * t + 1, y);
  tin.set_corner(3 * t + 2, z);
}

// The zipper: from base l -> r (first the new hull edge l0 -> r0, whose outside is ghost LOW),
// adds (l, r, next right) or (l, r, next left), whichever stays inside the gap; when both do, the
// one whose circumcircle is empty of the other candidate. Takes the chain ghosts' slots in
// POOL's order, records each replaced chain ghost half-edge in REPLACED and links the last base to
// ghost UP. Returns the new half-edges, to be checked for local Delaunay.
std::vector<EdgeId> zip(Triangulation& tin, const Hull& hull, const Chains& c,
                        const std::vector<TriangleId>& pool, TriangleId low, TriangleId up,
                        std::vector<std::pair<EdgeId, EdgeId>>& replaced) {
  const std::vector<VertexId>&lv = c.lv, &rv = c.rv;
  const std::size_t a = c.left.size(), b = c.right.size();
  std::vector<EdgeId> fresh;
  fresh.reserve(3 * (a + b));
  EdgeId base_twin = 3 * low;  // r -> l
  std::size_t i = 0, j = 0, k = 0;
  while (i < a || j < b) {
    const VertexId l = lv[i], r = rv[j];
    bool can_l = false, can_r = false;
    if (i < a) {
      const VertexId l1 = lv[i + 1];
      can_l = hull.orient(l, r, l1) > 0 &&
              (j == b || hull.orient(r, rv[j + 1], l1) > 0 || hull.orient(l, r, rv[j + 1]) <= 0);
    }
    if (j < b) {
      const VertexId r1 = rv[j + 1];
      can_r = hull.orient(l, r, r1) > 0 &&
              (i == a || hull.orient(l, lv[i + 1], r1) < 0 || hull.orient(l, r, lv[i + 1]) <= 0);
    }
    if (can_l && can_r)
      can_r = predicates::incircle_perturbed(hull.at(l), hull.at(r), hull.at(rv[j + 1]),
                                             hull.at(lv[i + 1])) < 0;
    if (!can_l && !can_r) throw internal_error("no triangle fits the gap");
    assert(k < a + b);  // one triangle per chain edge: the chain ghosts' slots suffice
    const TriangleId t = pool[k++];
    const EdgeId e = 3 * t;
    if (can_r) {
      set_triangle(tin, t, l, r, rv[j + 1]);
      replaced.emplace_back(c.right[j], e + 1);  // r -> r1
      tin.link(e, base_twin);
      base_twin = e + 2;  // r1 -> l
      ++j;
    } else {
      set_triangle(tin, t, l, r, lv[i + 1]);
      replaced.emplace_back(c.left[i], e + 2);  // l1 -> l
      tin.link(e, base_twin);
      base_twin = e + 1;  // r -> l1
      ++i;
    }
    fresh.insert(fresh.end(), {e, e + 1, e + 2});
  }
  assert(k == a + b);
  tin.link(3 * up, base_twin);
  return fresh;
}

// The chain edges take the ghosts' outer twins, and the new ghosts LOW and UP join the hull's
// ghost cycle. A chain ghost's outer twin may itself be a chain ghost (a collinear half covered
// on both sides): REPLACED maps those to the replacing triangle's edge.
void relink(Triangulation& tin, const Chains& c, const Outside& o, TriangleId low, TriangleId up,
            std::vector<std::pair<EdgeId, EdgeId>>& replaced) {
  std::sort(replaced.begin(), replaced.end());
  const auto renamed = [&](EdgeId old) {
    const auto it =
        std::lower_bound(replaced.begin(), replaced.end(), std::make_pair(old, EdgeId{0}));
    return it != replaced.end() && it->first == old ? it->second : old;
  };
  for (std::size_t q = 0; q < c.left.size(); ++q) tin.link(renamed(c.left[q]), renamed(o.left[q]));
  for (std::size_t q = 0; q < c.right.size(); ++q)
    tin.link(renamed(c.right[q]), renamed(o.right[q]));
  tin.link(3 * low + 1, c.left_all ? 3 * up + 2 : o.into_l0);     // l0 -> inf
  tin.link(3 * low + 2, c.right_all ? 3 * up + 1 : o.out_of_r0);  // inf -> r0
  if (!c.left_all) tin.link(3 * up + 2, o.out_of_lt);             // inf -> lt
  if (!c.right_all) tin.link(3 * up + 1, o.into_rt);              // rt -> inf
}

// Lawson flips from the half-edges FRESH until every edge is locally Delaunay; returns the flips.
std::uint64_t flip_to_delaunay(Triangulation& tin, std::vector<EdgeId>& fresh) {
  std::uint64_t flips = 0;
  while (!fresh.empty()) {
    const EdgeId e = fresh.back();
    fresh.pop_back();
    const EdgeId f = tin.twin(e);
    assert(tin.twin(f) == e);
    const VertexId pa = tin.origin(e), pb = tin.dest(e), pc = tin.apex(e), pd = tin.apex(f);
    if (pa == kInfinite || pb == kInfinite || pc == kInfinite || pd == kInfinite) continue;
    if (predicates::incircle_perturbed(tin.point(pa), tin.point(pb), tin.point(pc), tin.point(pd)) <
        0)
      continue;
    tin.flip(e);
    ++flips;
    fresh.insert(fresh.end(), {next_edge(e), prev_edge(e), next_edge(f), prev_edge(f)});
  }
  return flips;
}

}  // namespace

std::uint64_t merge_triangulations(Triangulation& tin, EdgeId left_ghost, EdgeId right_ghost,
                                   TriangleId spare0, TriangleId spare1) {
  const Hull hull(tin);
  const HullEnds ends = find_hull_ends(tin, hull, left_ghost, right_ghost);
  const Tangents tangents = find_tangents(hull, ends);
  const Chains chains = facing_chains(hull, tangents, ends);
  const Outside outside = read_outside(tin, tangents, chains);

  // The chain ghosts' slots, then the two spares, take the new triangles and ghosts.
  const std::size_t a = chains.left.size(), b = chains.right.size();
  std::vector<TriangleId> pool;
  pool.reserve(a + b + 2);
  for (EdgeId g : chains.left) pool.push_back(triangle_of(g));
  for (EdgeId g : chains.right) pool.push_back(triangle_of(g));
  pool.push_back(spare0);
  pool.push_back(spare1);
  const TriangleId low = pool[a + b], up = pool[a + b + 1];
  set_triangle(tin, low, tangents.r0, tangents.l0, kInfinite);  // outside new hull edge l0 -> r0
  set_triangle(tin, up, tangents.lt, tangents.rt, kInfinite);   // outside new hull edge rt -> lt

  std::vector<std::pair<EdgeId, EdgeId>> replaced;  // old ghost half-edge -> new half-edge
  replaced.reserve(a + b);
  std::vector<EdgeId> fresh = zip(tin, hull, chains, pool, low, up, replaced);
  relink(tin, chains, outside, low, up, replaced);
  return flip_to_delaunay(tin, fresh);
}

}  // namespace tincdt::delaunay
