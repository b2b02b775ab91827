// The last run's start from the regions' runs (see regions.cpp): what assign_points() does, but
// taking as they are the triangles that a region's run has too.
//
// Why a shared triangle can be taken as it is: a triangle of this TIN with the same three
// points as a triangle of part k's TIN lies in part k's hull (its corners are points of part
// k), and that hull holds no point of another part (the parts are cells of a grid, and a
// part's hull is within its cell). Every point of part k in it was in the same triangle there,
// measured against the plane of the same three corners. So its range, its worst point and its
// sum of squares are those of part k's slot, and only the other (loose) points are located and
// measured.
//
// The arena: the parts' runs kept their ranges in this run's arena (the regions share one), so
// an adopted triangle keeps its range where it is. A triangle with loose points gets a new
// range past the parts' arenas, over the parts' point lists, which are read by then.
#include <algorithm>
#include <functional>

#include "core/error.hpp"
#include "core/memory.hpp"
#include "simplify/simplifier.hpp"

namespace tincdt::simplify::detail {

using mesh::prev_edge;
using mesh::triangle_of;

struct Simplifier::Adoption {
  // Per slot of this TIN: the part and the slot of its run that it takes as it is, or kNoId.
  std::vector<std::pair<std::uint32_t, TriangleId>> source;
  // Per part, per slot of its run: the slot of this TIN that takes it, or kNoId.
  std::vector<std::vector<TriangleId>> target_of;
  // Per part: its points that are neither vertices nor in a taken triangle, ascending.
  std::vector<std::vector<std::uint32_t>> loose_of;
};

void Simplifier::adopt(std::span<const Part> parts) {
  if (!set_.ids.empty()) throw InternalError("simplify: adopt() on a subset");
  grow();
  Adoption a = match_parts(parts);
  std::vector<std::uint32_t> loose;
  for (const auto& l : a.loose_of) loose.insert(loose.end(), l.begin(), l.end());
  release(a.loose_of);

  // The loose points located, on all threads.
  std::vector<TriangleId> loose_triangle(loose.size());
  auto locate_chunk = [&](std::size_t c, std::size_t chunks) {
    Walk walk(*this, c);
    for (std::size_t i = loose.size() * c / chunks; i < loose.size() * (c + 1) / chunks; ++i)
      loose_triangle[i] = walk.to(xy_[loose[i]]);
  };
  pool_.run(locate_chunk, chunks_for(loose.size()));

  for (const TriangleId t : loose_triangle) ++count_[t];
  const std::vector<std::uint8_t> measured = place_ranges(parts, a);
  // The loose points at the ends of their triangles' ranges (past the adopted points), each
  // range's in the order of `loose`: filled from the end, the last first.
  std::vector<std::size_t> end(measured.size());
  for (std::size_t u = 0; u < end.size(); ++u)
    if (measured[u]) end[u] = begin_[u] + count_[u];
  for (std::size_t i = loose.size(); i-- > 0;) {
    assert(measured[loose_triangle[i]]);  // an adopted range has no loose point
    ids_[--end[loose_triangle[i]]] = loose[i];
  }
  release(end);
  release(loose);
  release(loose_triangle);
  for_each_range([&](std::size_t u) {
    if (measured[u]) set_tally(u, measure(u));
  });
  queue_ranges();
  log_adopted_ranges(parts, a, measured);
}

// Per slot, which part's triangle it takes as it is, and each part's loose points: a part at a
// time, on all threads (no two parts share a triangle of this TIN).
Simplifier::Adoption Simplifier::match_parts(std::span<const Part> parts) {
  // The triangle of three points, if this TIN has it, is found around the first one's vertex.
  IdMap vertex_of;  // of a point (the vertices are few next to the points)
  for (VertexId v = 0; v < point_of_vertex_.size(); ++v)
    if (point_of_vertex_[v] != kNoId) vertex_of.insert(point_of_vertex_[v], v);  // not a crossing
  Adoption a;
  a.source.assign(tin_.triangle_slots(), {kNoId, kNoId});
  a.target_of.resize(parts.size());
  a.loose_of.resize(parts.size());
  auto match = [&](std::size_t k, std::size_t) { match_part(parts[k], k, vertex_of, a); };
  pool_.run(match, parts.size());
  return a;
}

// Part k's share of match_parts(). Its loose points in the order of their ids, which is
// spatial (a grid, or the Delaunay stage's Hilbert order), so that the walks that locate them
// are short and stay in cache.
void Simplifier::match_part(const Part& part, std::size_t k, const IdMap& vertex_of, Adoption& a) {
  std::vector<std::uint32_t>& loose = a.loose_of[k];
  const auto add_loose = [&](std::uint32_t q) {
    if (vertex_of.find(q) == kNoId) loose.push_back(q);  // not a vertex
  };
  const Simplifier* r = part.run;
  if (!r) {  // (ascending already)
    for (std::uint32_t q : part.points) add_loose(q);
    return;
  }
  std::vector<TriangleId>& target = a.target_of[k];
  target.assign(r->count_.size(), kNoId);
  std::vector<VertexId> here(r->point_of_vertex_.size());  // (a lookup per vertex, not corner)
  for (VertexId w = 0; w < here.size(); ++w) {
    const std::uint32_t q = r->point_of_vertex_[w];
    here[w] = q == kNoId ? kNoId : vertex_of.find(q);
  }
  for (TriangleId t = 0; t < r->count_.size(); ++t) {
    if (r->count_[t] == 0) continue;
    const TriangleId u = shared_triangle(*r, here, t);
    if (u != kNoId) {
      assert(a.source[u].first == kNoId);  // a triangle is in one part's hull
      a.source[u] = {static_cast<std::uint32_t>(k), t};
      target[t] = u;
      continue;
    }
    for (std::size_t j = r->begin_[t]; j < r->begin_[t] + r->count_[t]; ++j) add_loose(r->ids_[j]);
  }
  for (VertexId w = 0; w < here.size(); ++w)
    if (r->point_of_vertex_[w] != kNoId && here[w] == kNoId)
      loose.push_back(r->point_of_vertex_[w]);
  std::sort(loose.begin(), loose.end());
}

// The slot of this TIN with the corners of slot t of run r, in the same order up to rotation,
// or kNoId. (`here`: this TIN's vertex of each of r's vertices, or kNoId.)
TriangleId Simplifier::shared_triangle(const Simplifier& r, std::span<const VertexId> here,
                                       TriangleId t) const {
  VertexId v[3];
  for (int i = 0; i < 3; ++i) {
    v[i] = here[r.tin_.origin(3 * t + static_cast<EdgeId>(i))];
    if (v[i] == kNoId) return kNoId;
  }
  const EdgeId first = tin_.edge_from(v[0]);
  EdgeId e = first;
  do {
    if (tin_.dest(e) == v[1]) return tin_.apex(e) == v[2] ? triangle_of(e) : kNoId;
    e = tin_.twin(prev_edge(e));
  } while (e != first);
  return kNoId;
}

// The first place of the arena past the parts' runs' arenas, which must lie in this run's.
std::size_t Simplifier::past_parts_arenas(std::span<const Part> parts) const {
  std::size_t at = 0;
  const std::less<const std::uint32_t*> before;  // (a total order on any pointers)
  for (const Part& part : parts) {
    if (!part.run) continue;
    if (before(part.run->ids_, ids_) ||
        before(ids_ + arena_size_, part.run->ids_ + part.run->arena_size_))
      throw InternalError("simplify: a part's arena is not in the adopting run's");
    at = std::max(at, static_cast<std::size_t>(part.run->ids_ - ids_) + part.run->arena_size_);
  }
  return at;
}

// The ranges: an adopted triangle without loose points keeps its range and tally where they
// are; any other with points gets a new range past the parts' arenas, its adopted points first
// (count_ holds the loose points' counts on entry). Returns, per slot, whether it is to be
// measured (else adopted as it was).
std::vector<std::uint8_t> Simplifier::place_ranges(std::span<const Part> parts, const Adoption& a) {
  const std::size_t slots = tin_.triangle_slots();
  std::size_t at = past_parts_arenas(parts);
  std::vector<std::uint8_t> measured(slots, 1);
  std::uint64_t points = 0;
  for (std::size_t u = 0; u < slots; ++u) {
    const std::uint32_t loose_count = count_[u];
    const Simplifier* r = a.source[u].first != kNoId ? parts[a.source[u].first].run : nullptr;
    const TriangleId t = a.source[u].second;
    if (r) {
      count_[u] += r->count_[t];
      if (loose_count == 0) {
        begin_[u] = static_cast<std::size_t>(r->ids_ - ids_) + r->begin_[t];
        set_tally(u, r->tally_of(t));
        measured[u] = 0;
        points += count_[u];
        continue;
      }
    }
    if (count_[u] == 0) continue;
    if (at + count_[u] > arena_size_)
      throw InternalError("simplify: the adopted ranges overflow the arena");
    begin_[u] = at;
    if (r) std::copy_n(r->ids_ + r->begin_[t], count_[u] - loose_count, ids_ + at);
    at += count_[u];
    points += count_[u];
  }
  arena_end_ = at;
  if (points != candidates_)  // each point once: in a triangle, or a vertex
    throw InternalError("simplify: the regions' triangles do not hold every point once");
  return measured;
}

// The log of ranges in arena order, as compact() needs it: the ranges kept in place as their
// runs' logs list them (the parts' arenas in the order they lie), then the new ones.
void Simplifier::log_adopted_ranges(std::span<const Part> parts, const Adoption& a,
                                    std::span<const std::uint8_t> measured) {
  ranges_.clear();
  const std::less<const std::uint32_t*> before;
  std::vector<std::size_t> by_place;
  for (std::size_t k = 0; k < parts.size(); ++k)
    if (parts[k].run) by_place.push_back(k);
  std::sort(by_place.begin(), by_place.end(), [&](std::size_t x, std::size_t y) {
    return before(parts[x].run->ids_, parts[y].run->ids_);
  });
  for (const std::size_t k : by_place) {
    const Simplifier& r = *parts[k].run;
    const auto offset = static_cast<std::uint32_t>(r.ids_ - ids_);
    for (const auto& [begin, t] : r.ranges_) {
      if (r.count_[t] == 0 || r.begin_[t] != begin) continue;  // not live
      const TriangleId u = a.target_of[k][t];
      if (u != kNoId && !measured[u]) ranges_.push_back({offset + begin, u});
    }
  }
  for (std::size_t u = 0; u < measured.size(); ++u)
    if (count_[u] > 0 && measured[u])
      ranges_.push_back({static_cast<std::uint32_t>(begin_[u]), static_cast<TriangleId>(u)});
}

}  // namespace tincdt::simplify::detail
