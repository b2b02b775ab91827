#include "mesh/triangulation.hpp"

#include <atomic>
#include <cassert>
#include <cmath>

#include "core/memory.hpp"
#include "core/number_text.hpp"
#include "core/parallel.hpp"
#include "mesh/geometry.hpp"
#include "predicates/predicates.hpp"

namespace tincdt::mesh {

VertexId Triangulation::add_vertex(Point2 p, double z) {
  xy_.push_back(p);
  z_.push_back(z);
  if (!vertex_edge_.empty()) vertex_edge_.push_back(kNoId);
  return static_cast<VertexId>(xy_.size() - 1);
}

void Triangulation::reserve_vertices(std::size_t n) {
  xy_.reserve(n);
  z_.reserve(n);
  advise_huge_pages(xy_);
  advise_huge_pages(z_);
}

TriangleId Triangulation::add_triangle(VertexId a, VertexId b, VertexId c) {
  const auto t = static_cast<TriangleId>(triangle_slots());
  corner_.insert(corner_.end(), {a, b, c});
  twin_.insert(twin_.end(), {kNoId, kNoId, kNoId});
  if (!constrained_.empty()) constrained_.insert(constrained_.end(), {0, 0, 0});
  if (!removed_.empty()) removed_.push_back(0);
  if (a < kInfinite && b < kInfinite && c < kInfinite) ++real_triangles_;
  return t;
}

void Triangulation::add_empty_triangles(std::size_t count) {
  const std::size_t slots = triangle_slots() + count;
  corner_.resize(3 * slots, kNoId);
  twin_.resize(3 * slots, kNoId);
  if (!constrained_.empty()) constrained_.resize(3 * slots, 0);
  if (!removed_.empty()) removed_.resize(slots, 0);
}

void Triangulation::set_corners(TriangleId t, VertexId a, VertexId b, VertexId c) {
  corner_[3 * t] = a;
  corner_[3 * t + 1] = b;
  corner_[3 * t + 2] = c;
}

void Triangulation::reserve_triangles(std::size_t n) {
  corner_.reserve(3 * n);
  twin_.reserve(3 * n);
  advise_huge_pages(corner_);
  advise_huge_pages(twin_);
}

void Triangulation::truncate_triangles(std::size_t slots) {
  assert(slots <= triangle_slots());
#ifndef NDEBUG
  for (std::size_t e = 3 * slots; e < twin_.size(); ++e) assert(twin_[e] == kNoId);
#endif
  corner_.resize(3 * slots);
  twin_.resize(3 * slots);
  if (!constrained_.empty()) constrained_.resize(3 * slots);
  if (!removed_.empty()) removed_.resize(slots);
}

void Triangulation::set_removed(TriangleId t, bool on) {
  if (removed_.empty()) {
    if (!on) return;
    removed_.assign(triangle_slots(), 0);
  }
  if (removed_[t] == static_cast<std::uint8_t>(on)) return;
  removed_[t] = on;
  if (!is_ghost(t)) real_triangles_ += on ? -1 : 1;
}

void Triangulation::set_constrained(EdgeId e, bool on) {
  if (constrained_.empty()) {
    if (!on) return;
    constrained_.assign(corner_.size(), 0);
  }
  constrained_[e] = on;
  constrained_[twin_[e]] = on;
}

void Triangulation::flip(EdgeId e) {
  const EdgeId f = twin_[e];
  const EdgeId e1 = next_edge(e), e2 = prev_edge(e);  // b -> c, c -> a
  const EdgeId f1 = next_edge(f), f2 = prev_edge(f);  // a -> d, d -> b
  const VertexId a = corner_[e], b = corner_[e1], c = corner_[e2], d = corner_[f2];
  const EdgeId t_bc = twin_[e1], t_ca = twin_[e2], t_ad = twin_[f1], t_db = twin_[f2];
  // Debug builds: an unconstrained edge of two linked triangles whose quadrilateral is strictly
  // convex (a and b strictly on opposite sides of c-d), ghosts aside.
  assert(twin_[f] == e && corner_[f] == b && corner_[f1] == a && !is_constrained(e));
  assert(a == kInfinite || b == kInfinite || c == kInfinite || d == kInfinite ||
         predicates::orient2d(xy_[c], xy_[d], xy_[a]) *
                 predicates::orient2d(xy_[c], xy_[d], xy_[b]) <
             0);

  // e's slot becomes (d, c, a), f's slot (c, d, b).
  corner_[e] = d;
  corner_[e1] = c;
  corner_[e2] = a;
  corner_[f] = c;
  corner_[f1] = d;
  corner_[f2] = b;
  link(e1, t_ca);  // c -> a
  link(e2, t_ad);  // a -> d
  link(f1, t_db);  // d -> b
  link(f2, t_bc);  // b -> c
  if (!constrained_.empty()) {
    const std::uint8_t k_bc = constrained_[e1], k_ca = constrained_[e2];
    const std::uint8_t k_ad = constrained_[f1], k_db = constrained_[f2];
    constrained_[e] = constrained_[f] = 0;
    constrained_[e1] = k_ca;
    constrained_[e2] = k_ad;
    constrained_[f1] = k_db;
    constrained_[f2] = k_bc;
  }
  if (!vertex_edge_.empty()) {  // a flip between ghosts (outside the hull) moves kInfinite too
    if (a != kInfinite) vertex_edge_[a] = e2;
    if (b != kInfinite) vertex_edge_[b] = f2;
    if (c != kInfinite) vertex_edge_[c] = e1;
    if (d != kInfinite) vertex_edge_[d] = f1;
  }
}

void Triangulation::build_vertex_index(unsigned threads) {
  vertex_edge_.assign(vertex_count(), kNoId);
  // Any leaving half-edge will do, so two threads may race on a vertex: relaxed atomics make
  // that well-defined at the price of a plain store.
  parallel_chunks(threads, corner_.size(), [this](std::size_t begin, std::size_t end) {
    for (std::size_t e = begin; e < end; ++e) {
      const VertexId v = corner_[e];
      if (v < kInfinite)
        std::atomic_ref<EdgeId>(vertex_edge_[v])
            .store(static_cast<EdgeId>(e), std::memory_order_relaxed);
    }
  });
}

EdgeId Triangulation::find_edge(VertexId u, VertexId v) const {
  const EdgeId first = vertex_edge_[u];
  EdgeId e = first;
  do {
    if (dest(e) == v) return e;
    e = twin_[prev_edge(e)];  // the next half-edge leaving u, counter-clockwise
  } while (e != first);
  return kNoId;
}

void Triangulation::recount() {
  real_triangles_ = 0;
  for_each_triangle([&](TriangleId, const std::array<VertexId, 3>&) { ++real_triangles_; });
}

std::size_t Triangulation::memory_bytes() const {
  return xy_.capacity() * sizeof(Point2) + z_.capacity() * sizeof(double) +
         corner_.capacity() * sizeof(VertexId) + twin_.capacity() * sizeof(EdgeId) +
         constrained_.capacity() + vertex_edge_.capacity() * sizeof(EdgeId) + removed_.capacity();
}

namespace {

std::string describe_edge(const Triangulation& tin, EdgeId e) {
  auto name = [](VertexId v) { return v == kInfinite ? std::string("inf") : count_text(v); };
  return "edge " + count_text(e) + " (" + name(tin.origin(e)) + " -> " + name(tin.dest(e)) +
         ", triangle " + count_text(triangle_of(e)) + ")";
}

// Every triangle names existing, distinct vertices, at most one of them infinite, and a real
// triangle turns counter-clockwise. Counts each vertex's triangles in DEGREE and the ghosts.
std::string check_triangles(const Triangulation& tin, std::vector<std::uint32_t>& degree,
                            std::size_t& ghosts) {
  const std::size_t nv = tin.vertex_count();
  degree.assign(nv, 0);
  ghosts = 0;
  for (std::size_t t = 0; t < tin.triangle_slots(); ++t) {
    const auto tri = tin.triangle(static_cast<TriangleId>(t));
    int infinite = 0;
    for (int i = 0; i < 3; ++i) {
      if (tri[i] == kInfinite) {
        ++infinite;
      } else if (tri[i] >= nv) {
        return "triangle " + count_text(t) + " names vertex " + count_text(tri[i]) + " of " +
               count_text(nv);
      } else {
        ++degree[tri[i]];
      }
    }
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2])
      return "triangle " + count_text(t) + " repeats a corner";
    if (infinite > 1) return "triangle " + count_text(t) + " has two infinite corners";
    ghosts += infinite;
    if (!infinite &&
        predicates::orient2d(tin.point(tri[0]), tin.point(tri[1]), tin.point(tri[2])) <= 0)
      return "triangle " + count_text(t) + " is not counter-clockwise";
  }
  return {};
}

// Every vertex is in a triangle and in exactly one fan of them (a manifold), DEGREE counting its
// triangles; Euler's formula holds.
std::string check_fans(const Triangulation& tin, const std::vector<std::uint32_t>& degree) {
  const std::size_t nv = tin.vertex_count();
  for (std::size_t v = 0; v < nv; ++v)
    if (!degree[v]) return "vertex " + count_text(v) + " is in no triangle";
  std::vector<EdgeId> out_edge(nv, kNoId);
  for (std::size_t i = 0; i < 3 * tin.triangle_slots(); ++i) {
    const VertexId v = tin.origin(static_cast<EdgeId>(i));
    if (v < kInfinite) out_edge[v] = static_cast<EdgeId>(i);
  }
  for (std::size_t v = 0; v < nv; ++v) {
    std::uint32_t around = 0;
    EdgeId e = out_edge[v];
    do {
      e = tin.twin(prev_edge(e));  // the next half-edge leaving v, counter-clockwise
      if (++around > degree[v]) break;
    } while (e != out_edge[v]);
    if (around != degree[v])
      return "vertex " + count_text(v) + " has more than one fan of triangles";
  }
  if (tin.triangle_slots() + 2 != 2 * nv) return "Euler's formula fails: wrong number of triangles";
  return {};
}

// The hull: ghosts chain into one polygon that winds once (its convexity is checked with the
// edges between ghosts by check_local_delaunay). Exactly, in signs only: the direction of hull
// edge u -> v turns at v by less than half a turn either way (orient2d tells which way, and a
// collinear edge turns by 0 or doubles back), so the winding number is the count of the turns
// that carry the direction across the +x axis counter-clockwise, less those that carry it back.
// A direction is above the axis when dy > 0 or (dy = 0 and dx > 0); the sign of a difference of
// doubles is exact, so even coordinates 1e-320 apart (a LAS scale of 5e-324) are judged right.
std::string check_hull(const Triangulation& tin, std::size_t ghosts) {
  const auto upper = [](Point2 a, Point2 b) { return b.y > a.y || (b.y == a.y && b.x > a.x); };
  long long winding = 0;
  for (std::size_t i = 0; i < 3 * tin.triangle_slots(); ++i) {
    const auto e = static_cast<EdgeId>(i);
    if (tin.apex(e) != kInfinite) continue;
    // Ghost (u, v, inf); the next ghost along the hull is (v, w, inf), across v -> inf.
    const VertexId u = tin.origin(e), v = tin.dest(e);
    const EdgeId g = next_edge(tin.twin(next_edge(e)));
    if (tin.origin(g) != v || tin.apex(g) != kInfinite)
      return describe_edge(tin, e) + ": hull ghosts are not chained";
    const Point2 pu = tin.point(u), pv = tin.point(v), pw = tin.point(tin.dest(g));
    const int turn = predicates::orient2d(pu, pv, pw);
    const bool up_in = upper(pu, pv), up_out = upper(pv, pw);
    if (turn == 0) {
      // Straight on, or back along itself (a hull that folds: never valid).
      if ((pv.x < pu.x) != (pw.x < pv.x) || (pv.x > pu.x) != (pw.x > pv.x) ||
          (pv.y < pu.y) != (pw.y < pv.y) || (pv.y > pu.y) != (pw.y > pv.y))
        return describe_edge(tin, e) + ": the hull doubles back on itself";
    } else if (turn > 0 && !up_in && up_out) {
      ++winding;
    } else if (turn < 0 && up_in && !up_out) {
      --winding;
    }
  }
  if (ghosts > 0 && winding != 1 && winding != -1)
    return "the hull does not wind once around the triangulation";
  return {};
}

// Local Delaunay (if asked) of the unconstrained edges, and hull convexity, for the edges between
// two ghosts.
std::string check_local_delaunay(const Triangulation& tin, bool delaunay) {
  for (std::size_t i = 0; i < 3 * tin.triangle_slots(); ++i) {
    const auto e = static_cast<EdgeId>(i);
    if (tin.is_constrained(e)) continue;
    const bool hull_edge = tin.origin(e) == kInfinite || tin.dest(e) == kInfinite;
    if (!delaunay && !hull_edge) continue;
    if (!is_locally_delaunay(tin, e))
      return describe_edge(tin, e) +
             (hull_edge ? " leaves the hull non-convex" : " is not locally Delaunay");
  }
  return {};
}

}  // namespace

std::string Triangulation::validate(ValidateOptions options) const {
  if (corner_.size() != twin_.size() || corner_.size() != 3 * triangle_slots())
    return "corner and twin arrays differ in size";
  if (!constrained_.empty() && constrained_.size() != corner_.size())
    return "constraint flags differ in size from the corners";
  std::vector<std::uint32_t> degree;
  std::size_t ghosts = 0;
  if (std::string problem = check_triangles(*this, degree, ghosts); !problem.empty())
    return problem;
  for (std::size_t i = 0; i < corner_.size(); ++i) {
    const auto e = static_cast<EdgeId>(i);
    const EdgeId f = twin_[e];
    if (f >= corner_.size()) return describe_edge(*this, e) + " has no twin";
    if (twin_[f] != e) return describe_edge(*this, e) + " is not its twin's twin";
    if (triangle_of(f) == triangle_of(e))
      return describe_edge(*this, e) + " twins its own triangle";
    if (origin(f) != dest(e) || dest(f) != origin(e))
      return describe_edge(*this, e) + " and its twin do not join the same vertices";
    if (!constrained_.empty() && constrained_[e] != constrained_[f])
      return describe_edge(*this, e) + " is constrained on one side only";
  }
  if (std::string problem = check_fans(*this, degree); !problem.empty()) return problem;
  if (std::string problem = check_hull(*this, ghosts); !problem.empty()) return problem;
  return check_local_delaunay(*this, options.delaunay);
}

}  // namespace tincdt::mesh
