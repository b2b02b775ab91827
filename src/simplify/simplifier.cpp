// A run's start and end: the TIN of the kept points and segments, the points into the ranges of
// the triangles holding them, and the report. (The loop is in greedy.cpp.)
#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "core/memory.hpp"
#include "core/number_text.hpp"
#include "core/parallel.hpp"
#include "delaunay/delaunay.hpp"
#include "simplify/simplifier.hpp"

namespace tincdt::simplify::detail {

Simplifier::Simplifier(const PointSet& set, const SimplifyOptions& options,
                       std::span<std::uint32_t> arena)
    : set_(set),
      xy_(set.xy),
      z_(set.z),
      options_(options),
      pool_(thread_count(options.threads)),
      queue_(set.xy.data()) {
  if (xy_.size() != z_.size()) throw Error("simplify: x, y and z counts differ");
  if (xy_.size() >= kKept || set.size() > kMaxPoints)
    throw GeometryError("simplify: too many points for 32-bit ids");
  if (!(options.max_error >= 0))
    throw Error("simplify: the maximum error must be a number >= 0, not " +
                number_text(options.max_error));
  // Left unwritten: every entry is written before it is read, and fresh pages cost more than
  // the writes. (Huge pages were no faster here, and asking for them cost 0.2 s a 16M-point
  // run when memory was fragmented.)
  if (arena.empty()) {
    own_ids_ = std::make_unique_for_overwrite<std::uint32_t[]>(arena_slots(set.size()));
    arena = {own_ids_.get(), arena_slots(set.size())};
  }
  if (arena.size() < arena_slots(set.size()))
    throw InternalError("simplify: an arena too small for its run");
  ids_ = arena.data();
  arena_size_ = arena.size();
}

std::uint32_t Simplifier::member(std::uint32_t i) const {
  const std::size_t j = set_.find(i);
  if (j == set_.size())
    throw Error("simplify: a kept point or segment end is not one of the points");
  return static_cast<std::uint32_t>(j);
}

std::size_t Simplifier::place_vertices(std::span<const std::uint32_t> kept,
                                       std::span<const constraints::Segment> segments,
                                       std::span<const std::uint32_t> seeds) {
  // The kept points and segment ends, then the seeds that are none of them (a region may
  // insert the end of a segment it was not given).
  const auto sort_unique = [](std::vector<std::uint32_t>& v) {
    if (!std::is_sorted(v.begin(), v.end())) std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
  };
  std::vector<std::uint32_t>& places = vertex_places_;
  places.clear();
  for (std::uint32_t i : kept) places.push_back(member(i));
  for (const constraints::Segment& s : segments)
    places.insert(places.end(), {member(s.a), member(s.b)});
  sort_unique(places);
  std::vector<std::uint32_t> seed_places;
  for (std::uint32_t i : seeds) {
    const std::uint32_t j = member(i);
    if (!std::binary_search(places.begin(), places.end(), j)) seed_places.push_back(j);
  }
  sort_unique(seed_places);
  const std::size_t kept_places = places.size();
  places.insert(places.end(), seed_places.begin(), seed_places.end());
  std::inplace_merge(places.begin(), places.begin() + static_cast<std::ptrdiff_t>(kept_places),
                     places.end());
  assert(std::adjacent_find(places.begin(), places.end()) == places.end());
  return seed_places.size();
}

void Simplifier::insert_segments(std::span<const constraints::Segment> segments,
                                 std::span<const VertexId> vertex_of_place) {
  const std::vector<std::uint32_t>& places = vertex_places_;
  const auto vertex = [&](std::uint32_t i) {
    const auto k = std::lower_bound(places.begin(), places.end(), member(i)) - places.begin();
    return vertex_of_place[static_cast<std::size_t>(k)];
  };
  std::vector<constraints::Segment> s;
  s.reserve(segments.size());
  for (const constraints::Segment& g : segments) s.push_back({vertex(g.a), vertex(g.b), g.source});
  // In an order of their geometry, so that the caller's order does not decide.
  const auto key = [&](const constraints::Segment& g) {
    const Point2 a = tin_.point(g.a), b = tin_.point(g.b);
    return xy_less(a, b) ? std::pair{a, b} : std::pair{b, a};
  };
  std::sort(s.begin(), s.end(), [&](const constraints::Segment& a, const constraints::Segment& b) {
    const auto ka = key(a), kb = key(b);
    if (ka.first != kb.first) return xy_less(ka.first, kb.first);
    return xy_less(ka.second, kb.second);
  });
  constraints::insert_constraints(tin_, s);
  point_of_vertex_.resize(tin_.vertex_count(), kNoId);  // crossings
}

void Simplifier::start(std::span<const std::uint32_t> kept,
                       std::span<const constraints::Segment> segments,
                       std::span<const std::uint32_t> seeds) {
  const std::size_t m = set_.size();
  const std::size_t new_seeds = place_vertices(kept, segments, seeds);
  const std::vector<std::uint32_t>& places = vertex_places_;
  std::vector<Point3> points;
  points.reserve(places.size());
  for (std::uint32_t j : places) {
    const std::uint32_t i = set_[j];
    points.push_back({xy_[i].x, xy_[i].y, z_[i]});
  }
  report_.points = m;
  report_.kept_vertices = places.size() - new_seeds;
  report_.inserted = new_seeds;
  candidates_ = m - places.size();
  delaunay::DelaunayOptions d;
  d.keep_point_map = true;
  d.threads = options_.threads;
  delaunay::DelaunayResult r = delaunay::triangulate(std::move(points), d);
  if (r.duplicates_merged > 0)
    throw GeometryError("simplify: two kept points share x, y (merge duplicates first)");
  tin_ = std::move(r.tin);
  point_of_vertex_.assign(tin_.vertex_count(), kNoId);
  for (std::size_t k = 0; k < places.size(); ++k)
    point_of_vertex_[r.vertex_of_point[k]] = set_[places[k]];
  if (!segments.empty()) insert_segments(segments, r.vertex_of_point);
  if (!tin_.has_vertex_index()) tin_.build_vertex_index();
  first_greedy_vertex_ = tin_.vertex_count();
}

void Simplifier::assign_points() {
  const std::size_t n = set_.size();
  const std::size_t slots = tin_.triangle_slots();
  grow();

  // Where each point is, in chunks of consecutive points (every entry written: the arena
  // holds whatever its memory held).
  auto locate_chunk = [&](std::size_t c, std::size_t chunks) {
    Walk walk(*this, c);
    const std::size_t begin = n * c / chunks, end = n * (c + 1) / chunks;
    auto vertex = std::lower_bound(vertex_places_.begin(), vertex_places_.end(), begin);
    for (std::size_t i = begin; i < end; ++i) {
      if (vertex != vertex_places_.end() && *vertex == i) {
        ids_[i] = kKept;
        ++vertex;
        continue;
      }
      ids_[i] = walk.to(xy_[set_[i]]);
    }
  };
  pool_.run(locate_chunk, chunks_for(n));

  // The ranges, in slot order, each in point order.
  for (std::size_t i = 0; i < n; ++i)
    if (ids_[i] != kKept) ++count_[ids_[i]];
  std::size_t at = n;
  for (std::size_t t = 0; t < slots; ++t) {
    begin_[t] = at;
    at += count_[t];
  }
  assert(at == n + candidates_);  // every point not a vertex is in one triangle
  arena_end_ = at;
  // Each point measured as it is placed: in point order, the order of its range (the
  // points' arrays are read in order, and the triangles' planes and tallies are few).
  std::vector<std::size_t> cursor(begin_.begin(),
                                  begin_.begin() + static_cast<std::ptrdiff_t>(slots));
  std::vector<Plane> planes(slots);
  for (std::size_t t = 0; t < slots; ++t)
    if (count_[t] > 0) planes[t] = plane_of(static_cast<TriangleId>(t));
  std::vector<Tally> tallies(slots);
  for (std::size_t i = 0; i < n; ++i) {
    const TriangleId t = ids_[i];
    if (t == kKept) continue;
    const std::uint32_t q = set_[i];
    ids_[cursor[t]++] = q;
    tallies[t].add(planes[t].error(xy_[q], z_[q]), q, xy_.data());
  }
  release(cursor);
  for (std::size_t t = 0; t < slots; ++t)
    if (count_[t] > 0) set_tally(t, tallies[t]);

  queue_ranges();
  // The log of ranges, in slot order, which is arena order here.
  ranges_.clear();
  for (std::size_t t = 0; t < slots; ++t)
    if (count_[t] > 0)
      ranges_.push_back({static_cast<std::uint32_t>(begin_[t]), static_cast<TriangleId>(t)});
}

void Simplifier::queue_ranges() {
  for (std::size_t t = 0; t < count_.size(); ++t) {
    if (count_[t] == 0) continue;
    if (worst_error_[t] <= options_.max_error)
      settled_ += count_[t];
    else
      queue_.append({worst_error_[t], worst_[t], static_cast<TriangleId>(t)});
  }
  queue_.build();
}

SimplifyResult Simplifier::finish() {
  // The squares as each triangle's points were last measured, in slot order: the same for
  // any thread count.
  double max_error = 0, sum_sq = 0;
  for (std::size_t t = 0; t < count_.size(); ++t) {
    if (count_[t] == 0) continue;
    max_error = std::max(max_error, worst_error_[t]);
    sum_sq += sum_sq_[t];
  }
  report_.max_error = max_error;
  report_.rmse = report_.points ? std::sqrt(sum_sq / static_cast<double>(report_.points)) : 0;
  tin_.recount();
  report_.vertices = tin_.vertex_count();
  SimplifyResult result;
  result.tin = std::move(tin_);
  result.point_of_vertex = std::move(point_of_vertex_);
  result.report = report_;
  return result;
}

}  // namespace tincdt::simplify::detail
