#include "mesh/point_insertion.hpp"
#include "core/xorshift.hpp"

#include <cassert>

#include "core/error.hpp"
#include "mesh/geometry.hpp"
#include "predicates/predicates.hpp"

namespace tincdt::mesh {

TriangleId PointInserter::new_slot(VertexId a, VertexId b, VertexId c) {
  if (next_slot_ == kNoId) return tin_.add_triangle(a, b, c);
  tin_.set_corners(next_slot_, a, b, c);
  return next_slot_++;
}

void PointInserter::start(VertexId a, VertexId b, VertexId c) {
  const TriangleId t = new_slot(a, b, c);
  const TriangleId g_ab = new_slot(b, a, kInfinite);
  const TriangleId g_bc = new_slot(c, b, kInfinite);
  const TriangleId g_ca = new_slot(a, c, kInfinite);
  tin_.link(3 * t, 3 * g_ab);
  tin_.link(3 * t + 1, 3 * g_bc);
  tin_.link(3 * t + 2, 3 * g_ca);
  tin_.link(3 * g_ab + 1, 3 * g_ca + 2);  // a -> inf
  tin_.link(3 * g_bc + 1, 3 * g_ab + 2);  // b -> inf
  tin_.link(3 * g_ca + 1, 3 * g_bc + 2);  // c -> inf
  last_ = t;
}

Location PointInserter::locate(Point2 p, TriangleId hint) {
  TriangleId t = hint == kNoId ? last_ : hint;
  if (tin_.is_ghost(t)) {
    EdgeId e = 3 * t;
    while (tin_.origin(e) == kInfinite || tin_.dest(e) == kInfinite) e = next_edge(e);
    t = triangle_of(tin_.twin(e));
  }
  const bool stochastic = tin_.has_constraints();
  EdgeId from = kNoId;
  for (;;) {
    int o[3];
    EdgeId crossed = kNoId;
    int first = 0;
    if (stochastic) {
      first = static_cast<int>(random_edge(random_));
    }
    for (int i = 0; i < 3; ++i) {
      const int k = first + i < 3 ? first + i : first + i - 3;
      const EdgeId e = 3 * t + static_cast<EdgeId>(k);
      if (e == from) {
        o[k] = 1;  // entered through this edge: p is strictly on its inner side
        continue;
      }
      o[k] = predicates::orient2d(tin_.point(tin_.origin(e)), tin_.point(tin_.dest(e)), p);
      if (o[k] < 0) {
        crossed = e;
        break;
      }
    }
    if (crossed != kNoId) {
      from = tin_.twin(crossed);
      t = triangle_of(from);
      if (tin_.apex(from) == kInfinite) return {Location::in_triangle, from};  // outside the hull
      continue;
    }
    const int zeros = (o[0] == 0) + (o[1] == 0) + (o[2] == 0);
    if (zeros == 0) return {Location::in_triangle, 3 * t};
    if (zeros == 1) {
      const int k = o[0] == 0 ? 0 : (o[1] == 0 ? 1 : 2);
      return {Location::on_edge, 3 * t + static_cast<EdgeId>(k)};
    }
    // Two edges through p: p is their shared corner, which the nonzero edge does not touch:
    // it is the origin of the edge before the nonzero one.
    const int k = o[0] != 0 ? 2 : (o[1] != 0 ? 0 : 1);
    return {Location::on_vertex, 3 * t + static_cast<EdgeId>(k)};
  }
}

template <int K>
void PointInserter::make_fan(const VertexId (&ring)[K], const EdgeId (&outer)[K],
                             const TriangleId (&slots)[K], VertexId v) {
  // Debug builds: outer[i] runs ring[i + 1] -> ring[i], the base of the new triangle i.
  for (int i = 0; i < K; ++i)
    assert(ring[i] != v && tin_.origin(outer[i]) == ring[(i + 1) % K] &&
           tin_.dest(outer[i]) == ring[i]);
  for (int i = 0; i < K; ++i) tin_.set_corners(slots[i], ring[i], ring[(i + 1) % K], v);
  for (int i = 0; i < K; ++i) {
    const EdgeId base = 3 * slots[i];
    tin_.link(base, outer[i]);
    tin_.link(base + 1, 3 * slots[(i + 1) % K] + 2);
    stack_.push_back(base);
  }
  if (tin_.has_constraints()) {  // reused slots hold stale flags: take the outer edges' own
    for (int i = 0; i < K; ++i) {
      const EdgeId base = 3 * slots[i];
      tin_.set_constrained(base, tin_.is_constrained(outer[i]));
      tin_.set_constrained(base + 1, false);
    }
  }
  if (tin_.has_vertex_index()) {
    for (int i = 0; i < K; ++i)
      if (ring[i] != kInfinite) tin_.set_edge_from(ring[i], 3 * slots[i]);
    tin_.set_edge_from(v, 3 * slots[0] + 2);
  }
  last_ = slots[0];
}

void PointInserter::insert(VertexId v, const Location& at) {
  const auto new_slot = [this] { return this->new_slot(kNoId, kNoId, kNoId); };
  if (at.kind == Location::on_vertex)
    throw GeometryError("internal: a point coincides with an existing vertex");
  if (at.kind == Location::in_triangle) {
    const EdgeId e = 3 * triangle_of(at.edge);
    const VertexId ring[3] = {tin_.origin(e), tin_.origin(e + 1), tin_.origin(e + 2)};
    const EdgeId outer[3] = {tin_.twin(e), tin_.twin(e + 1), tin_.twin(e + 2)};
    const TriangleId slots[3] = {triangle_of(e), new_slot(), new_slot()};
    make_fan(ring, outer, slots, v);
  } else {
    const EdgeId e = at.edge, f = tin_.twin(e);
    const bool constrained = tin_.is_constrained(e);
    const VertexId a = tin_.origin(e), b = tin_.dest(e);
    const VertexId ring[4] = {b, tin_.apex(e), a, tin_.apex(f)};
    const EdgeId outer[4] = {tin_.twin(next_edge(e)), tin_.twin(prev_edge(e)),
                             tin_.twin(next_edge(f)), tin_.twin(prev_edge(f))};
    const TriangleId slots[4] = {triangle_of(e), new_slot(), triangle_of(f), new_slot()};
    if (constrained) tin_.set_constrained(e, false);
    make_fan(ring, outer, slots, v);
    if (constrained) {
      tin_.set_constrained(3 * slots[0] + 2, true);  // v -> b
      tin_.set_constrained(3 * slots[2] + 2, true);  // v -> a
    }
  }
  restore(tin_.point(v));
}

// Lawson: every queued edge has the new point p as its apex.
void PointInserter::restore(Point2 p) {
  while (!stack_.empty()) {
    const EdgeId e = stack_.back();
    stack_.pop_back();
    const EdgeId f = tin_.twin(e);
    const VertexId d = tin_.apex(f);
    if (d == kInfinite) continue;  // a hull edge seen from inside
    const VertexId a = tin_.origin(e), b = tin_.dest(e);
    bool flip;
    if (a == kInfinite || b == kInfinite) {
      // Between two ghosts: flip when p sees the neighbouring hull edge from outside.
      flip = in_circle(tin_, b, a, d, p) > 0;
    } else {
      flip = predicates::incircle_perturbed(tin_.point(a), tin_.point(b), p, tin_.point(d)) > 0 &&
             !tin_.is_constrained(e);
    }
    if (!flip) continue;
    tin_.flip(e);
    ++flips_;
    stack_.push_back(prev_edge(e));  // a -> d, apex p
    stack_.push_back(next_edge(f));  // d -> b, apex p
  }
}

}  // namespace tincdt::mesh
