// The greedy loop: the worst point in, and the points of the triangles it replaced into the new
// triangles around it.
//
// Why only the star: inserting v (Lawson flips from the triangle holding it) replaces some
// triangles by others that all have v as a corner, and leaves every other triangle as it was.
// So the replaced triangles' slots are exactly those of v's star, after the insertion too (a
// slot is reused in place), and their points, and no others, now lie in the star: each lies in
// one cone (apex v, ring[i], ring[i + 1]). Each cone's points make a new range at the arena's
// end; the old ranges are abandoned, and compact() closes the gaps when the end is reached.
#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "simplify/simplifier.hpp"

namespace tincdt::simplify::detail {

using mesh::kInfinite;
using mesh::prev_edge;
using mesh::triangle_of;

void Simplifier::run(const ProgressFn* progress) {
  Progress report(progress, "simplify", candidates_ ? candidates_ : 1);
  mesh::PointInserter inserter(tin_);
  while (!queue_.empty()) {
    const Entry top = queue_.top();  // insert() updates its slot
    assert(top.error > options_.max_error && count_[top.tri] > 0);
    if (options_.max_vertices && tin_.vertex_count() >= options_.max_vertices) {
      report_.stopped_at_max_vertices = true;
      break;
    }
    insert(inserter, top.point, top.tri);
    ++report_.inserted;
    report.tick(settled_);
  }
  report.finish();
}

// Inserts point p, which lies in triangle t, and measures again the points of the triangles
// the insertion replaced: they are exactly the triangles now around the new vertex.
void Simplifier::insert(mesh::PointInserter& inserter, std::uint32_t p, TriangleId t) {
  const Point2 at = xy_[p];
  const mesh::Location where = inserter.locate(at, t);
  if (where.kind == mesh::Location::on_vertex)
    throw GeometryError("simplify: a point shares x, y with a vertex (merge duplicates first)");
  const VertexId v = tin_.add_vertex(at, z_[p]);
  point_of_vertex_.push_back(p);
  inserter.insert(v, where);
  grow();

  const bool cyclic = build_fan(v, at, z_[p]);
  const std::size_t total = release_star();
  const Fan fan{at,
                z_[p],
                ring_.data(),
                spokes_.data(),
                bounds_.data(),
                cones_.data(),
                static_cast<int>(cones_.size()),
                cyclic};
  if (cones_.size() < 255)
    redistribute(fan, p, total, cone8_, std::uint8_t{255});
  else
    redistribute(fan, p, total, cone32_, kNoId);
  requeue_star();
}

// The star of v, counter-clockwise, into star_, and its real triangles as a fan (ring_,
// spokes_, bounds_, cones_). They form one cyclic run (v inside the hull) or, v on the hull, one
// run from the vertex after the edge v -> inf.
bool Simplifier::build_fan(VertexId v, Point2 at, double z) {
  star_.clear();
  const EdgeId e0 = tin_.edge_from(v);
  EdgeId e = e0;
  do {
    star_.push_back(e);
    e = tin_.twin(prev_edge(e));
  } while (e != e0);
  const std::size_t k = star_.size();
  assert(k >= 3);
  std::size_t ghost = k;
  for (std::size_t i = 0; i < k; ++i)
    if (tin_.dest(star_[i]) == kInfinite) ghost = i;
  const bool cyclic = ghost == k;
  const std::size_t first = cyclic ? 0 : ghost + 1;
  ring_.clear();
  spokes_.clear();
  cones_.clear();
  for (std::size_t i = 0; i < (cyclic ? k : k - 1); ++i)
    ring_.push_back(pt(tin_.dest(star_[(first + i) % k])));
  if (cyclic) ring_.push_back(ring_.front());
  double reach = 0;
  for (const Point2& r : ring_) {
    spokes_.push_back({r.x - at.x, r.y - at.y});
    reach = std::max({reach, std::fabs(spokes_.back().x), std::fabs(spokes_.back().y)});
  }
  bounds_.clear();
  for (const Point2& d : spokes_) bounds_.push_back(predicates::cross_bound(d, reach));
  for (std::size_t i = 0; i < (cyclic ? k : k - 2); ++i) {
    const EdgeId s = star_[(first + i) % k];
    const VertexId a = tin_.dest(s), b = tin_.apex(s);
    assert(b != kInfinite);
    cones_.push_back({triangle_of(s), Gradient(at, z, pt(a), tin_.z(a), pt(b), tin_.z(b))});
  }
  assert(ring_.size() == cones_.size() + 1);
  return cyclic;
}

// The replaced triangles' ranges (the star's slots that held points) into old_, their slots
// reset; returns their point count. Compacts the arena first if their points would not fit
// at its end.
std::size_t Simplifier::release_star() {
  std::size_t total = 0;
  for (const EdgeId s : star_) total += count_[triangle_of(s)];
  if (arena_end_ + total > arena_size_) compact();
  assert(arena_end_ + total <= arena_size_);
  old_.clear();
  for (const EdgeId s : star_) {
    const TriangleId u = triangle_of(s);
    if (count_[u] == 0) continue;
    old_.push_back({begin_[u], count_[u]});
    if (worst_error_[u] <= options_.max_error) settled_ -= count_[u];
    count_[u] = 0;
    worst_[u] = kNoId;
    worst_error_[u] = -1.0;
    sum_sq_[u] = 0;
  }
  return total;
}

// The star's slots held the replaced triangles: their entries go or take the new values.
void Simplifier::requeue_star() {
  for (const EdgeId s : star_) {
    const TriangleId u = triangle_of(s);
    if (count_[u] == 0 || worst_error_[u] <= options_.max_error) queue_.erase(u);
  }
  for (const Cone& cone : cones_) {
    const TriangleId u = cone.tri;
    if (count_[u] == 0) continue;
    if (worst_error_[u] <= options_.max_error)
      settled_ += count_[u];
    else
      queue_.set({worst_error_[u], worst_[u], u});
  }
}

// The points of the old ranges (all but p) into new ranges, one per cone, at the arena's
// end: first each point's cone and error (split among threads when there are many), then
// the moves. Each new range keeps its points in their old order.
template <class C>
void Simplifier::redistribute(const Fan& fan, std::uint32_t p, std::size_t total,
                              std::vector<C>& cone_of, C skip) {
  const auto m = static_cast<std::size_t>(fan.m);
  if (cone_of.size() < total) cone_of.resize(total);
  const std::size_t chunks = chunks_for(total);
  tallies_.assign(chunks * m, Tally{});
  // A few ranges become one run of ids, so that the prefetches in scan() run across them
  // (most ranges are shorter than the prefetch distance).
  const std::uint32_t* gathered = nullptr;
  if (chunks == 1 && old_.size() > 1) {
    gathered_.clear();
    for (const Range& r : old_)
      gathered_.insert(gathered_.end(), ids_ + r.begin, ids_ + r.begin + r.count);
    gathered = gathered_.data();
  }
  // Calls f(ids, count, j) on the slices of the old ranges that hold points [lo, hi) of their
  // concatenation, j being the first one's place in it.
  const auto for_slices = [&](std::size_t lo, std::size_t hi, auto&& f) {
    if (gathered) {
      if (lo < hi) f(gathered + lo, hi - lo, lo);
      return;
    }
    std::size_t j = 0;
    for (const Range& r : old_) {
      const std::size_t from = std::max(lo, j), to = std::min(hi, j + r.count);
      if (from < to) f(ids_ + r.begin + (from - j), to - from, from);
      j += r.count;
    }
  };
  auto scan_chunk = [&](std::size_t c, std::size_t n_chunks) {
    Tally* tally = tallies_.data() + c * m;
    int hint = 0;
    for_slices(total * c / n_chunks, total * (c + 1) / n_chunks,
               [&](const std::uint32_t* ids, std::size_t count, std::size_t j) {
                 hint = scan(fan, ids, count, p, cone_of.data() + j, skip, tally, hint);
               });
  };
  pool_.run(scan_chunk, chunks);
  // New ranges cone by cone, each chunk's share in chunk order; a tally's count becomes
  // its chunk's write position.
  std::size_t at = arena_end_;
  for (std::size_t i = 0; i < m; ++i) {
    const TriangleId u = fan.cones[i].tri;
    begin_[u] = at;
    for (std::size_t c = 0; c < chunks; ++c) {
      Tally& t = tallies_[c * m + i];
      absorb(t, u);
      const std::size_t count = t.count;
      t.count = static_cast<std::uint32_t>(at - arena_end_);
      at += count;
    }
    if (count_[u] > 0) ranges_.push_back({static_cast<std::uint32_t>(begin_[u]), u});
  }
  assert(at + 1 == arena_end_ + total);  // every point but p, the new vertex, has a cone
  std::uint32_t* out = ids_ + arena_end_;
  arena_end_ = at;
  auto move_chunk = [&](std::size_t c, std::size_t n_chunks) {
    Tally* cursor = tallies_.data() + c * m;
    for_slices(total * c / n_chunks, total * (c + 1) / n_chunks,
               [&](const std::uint32_t* ids, std::size_t count, std::size_t j) {
                 const C* cone = cone_of.data() + j;
                 for (std::size_t i = 0; i < count; ++i)
                   if (cone[i] != skip) out[cursor[cone[i]].count++] = ids[i];
               });
  };
  pool_.run(move_chunk, chunks);
}

// Classifies and measures `count` points: their cones into `cone` (p, the new vertex,
// gets `skip`), their errors into the cones' tallies. Returns the last cone, the next hint.
template <class C>
int Simplifier::scan(const Fan& shared_fan, const std::uint32_t* ids, std::size_t count,
                     std::uint32_t p, C* cone, C skip, Tally* tally, int hint) const {
  // A copy in registers: the byte stores to `cone` may alias anything in memory.
  const Fan fan = shared_fan;
  const Point2* xy = xy_.data();
  const double* z = z_.data();
  for (std::size_t i = 0; i < count; ++i) {
    if (i + kPrefetch < count) {  // the points are scattered: ask for them ahead
      __builtin_prefetch(xy + ids[i + kPrefetch]);
      __builtin_prefetch(z + ids[i + kPrefetch]);
    }
    const std::uint32_t q = ids[i];
    if (q == p) {
      cone[i] = skip;
      continue;
    }
    const Point2 xq = xy[q];
    const Point2 d{xq.x - fan.apex.x, xq.y - fan.apex.y};
    hint = fan.classify(xq, d, hint);
    cone[i] = static_cast<C>(hint);
    const Gradient& g = fan.cones[hint].plane;
    tally[hint].add(std::fabs(z[q] - (fan.apex_z + g.gx * d.x + g.gy * d.y)), q, xy);
  }
  return hint;
}

void Simplifier::compact() {
  std::size_t at = 0, live = 0;
  for (const auto& [begin, t] : ranges_) {
    if (count_[t] == 0 || begin_[t] != begin) continue;
    assert(at <= begin);  // the log is in arena order
    std::copy_n(ids_ + begin, count_[t], ids_ + at);
    begin_[t] = at;
    ranges_[live++] = {static_cast<std::uint32_t>(at), t};
    at += count_[t];
  }
  ranges_.resize(live);
  arena_end_ = at;
}

}  // namespace tincdt::simplify::detail
