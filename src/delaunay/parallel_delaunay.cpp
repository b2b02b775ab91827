#include "delaunay/parallel_delaunay.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <limits>
#include <new>
#include <numeric>
#include <string>
#include <thread>

#if defined(__unix__) || defined(__APPLE__)
#include <sys/mman.h>
#endif

#include "core/error.hpp"
#include "core/parallel.hpp"
#include "delaunay/spatial_order.hpp"
#include "mesh/geometry.hpp"
#include "mesh/point_insertion.hpp"
#include "predicates/predicates.hpp"

namespace tincdt::delaunay {
namespace {
using namespace mesh;  // the half-edge vocabulary: next_edge, triangle_of, kInfinite, ...

bool lex_less(Point2 a, Point2 b) {
  return a.x < b.x || (a.x == b.x && a.y < b.y);
}

GeometryError internal_error(const std::string& what) {
  return GeometryError("internal: parallel Delaunay merge: " + what);
}

// Runs left() on this thread and right() on a new one (or, if not concurrent, one after the
// other); rethrows the first exception.
template <class Left, class Right>
void run_two(bool concurrent, Left&& left, Right&& right) {
  if (!concurrent) {
    left();
    right();
    return;
  }
  std::exception_ptr right_error;
  std::thread worker([&] {
    try {
      right();
    } catch (...) {
      right_error = std::current_exception();
    }
  });
  std::exception_ptr left_error;
  try {
    left();
  } catch (...) {
    left_error = std::current_exception();
  }
  worker.join();
  if (left_error) std::rethrow_exception(left_error);
  if (right_error) std::rethrow_exception(right_error);
}

// Scratch memory for the big temporary arrays, mapped and unmapped directly so that it goes back
// to the system when released: malloc keeps freed blocks below its mmap threshold, which it
// raises after large frees, and they would then add to the peak memory.
template <class T>
class Scratch {
 public:
  explicit Scratch(std::size_t n) : size_(n) {
    if (n == 0) return;
#if defined(__unix__) || defined(__APPLE__)
    void* p =
        mmap(nullptr, n * sizeof(T), PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
    data_ = static_cast<T*>(p);
#else
    data_ = new T[n];
#endif
  }
  Scratch(const Scratch&) = delete;
  Scratch& operator=(const Scratch&) = delete;
  ~Scratch() {
    release();
  }
  void release() {
    if (!data_) return;
#if defined(__unix__) || defined(__APPLE__)
    munmap(data_, size_ * sizeof(T));
#else
    delete[] data_;
#endif
    data_ = nullptr;
  }
  // Gives back the whole pages inside elements [begin, end), which must not be used again.
  void release(std::size_t begin, std::size_t end) {
#if defined(__unix__) || defined(__APPLE__)
    if (!data_) return;
    const auto page = static_cast<std::uintptr_t>(4096);
    const auto from = (reinterpret_cast<std::uintptr_t>(data_ + begin) + page - 1) & ~(page - 1);
    const auto to = reinterpret_cast<std::uintptr_t>(data_ + end) & ~(page - 1);
    if (from < to)
      munmap(reinterpret_cast<void*>(from), to - from);  // release() unmaps again: fine
#else
    (void)begin;
    (void)end;
#endif
  }
  T* data() const {
    return data_;
  }
  T& operator[](std::size_t i) const {
    return data_[i];
  }

 private:
  std::size_t size_;
  T* data_ = nullptr;
};

// Sorts one half's items into insertion order.
void sort_half(const std::vector<Point3>& input, std::uint64_t* items, std::size_t m) {
  Scratch<std::uint64_t> buffer(m);
  sort_by_key_then_xyz(input, items, buffer.data(), m);
}

// Passes one half's distinct points, in order and with equal x, y merged, to put(k, point);
// vertex_of_point (if not null) gets each point's index k within the half, duplicates (if not
// null) the merged groups with vertex ids within the half. Now and then calls consumed(k): the
// items before k are read.
struct HalfPoints {
  std::size_t count = 0;
  std::uint64_t duplicates = 0;
};

template <class Put, class Consumed>
HalfPoints gather_half(const std::vector<Point3>& input, const std::uint64_t* items, std::size_t m,
                       VertexId* vertex_of_point,
                       std::vector<DelaunayResult::Duplicate>* duplicates, DuplicatePolicy policy,
                       Put&& put, Consumed&& consumed) {
  HalfPoints half;
  Point3 current{};
  MergedZ merged{};
  for (std::size_t k = 0; k < m; ++k) {
    if ((k & 0x1ffff) == 0 && k > 0) consumed(k);  // items before k are read
    const auto i = static_cast<std::uint32_t>(items[k]);
    const Point3& p = input[i];
    if (half.count > 0 && current.x == p.x && current.y == p.y) {
      if (duplicates)
        record_duplicate(*duplicates, static_cast<VertexId>(half.count - 1), merged.z, p.z,
                         merged.count + 1);
      merged.add(p.z, i, policy);
      current.z = merged.z;
      ++half.duplicates;
    } else {
      if (half.count > 0) put(half.count - 1, current);
      current = p;
      merged = MergedZ::start(p.z, i);
      ++half.count;
    }
    if (vertex_of_point) vertex_of_point[i] = static_cast<VertexId>(half.count - 1);
  }
  if (half.count > 0) put(half.count - 1, current);
  return half;
}

// Until the triangles take them, the slots can hold sorted points: point k in corners
// [6k, 6k + 6), the last one (there are 6n - 6 corners) aside.
class PointStash {
 public:
  PointStash(Triangulation& tin, std::size_t n) : tin_(tin), n_(n) {}
  void put(std::size_t k, const Point3& p) {
    if (k + 1 == n_) {
      last_ = p;
      return;
    }
    const auto words = std::bit_cast<std::array<std::uint32_t, 6>>(p);
    for (std::size_t w = 0; w < 6; ++w) tin_.set_corner(static_cast<EdgeId>(6 * k + w), words[w]);
  }
  Point3 get(std::size_t k) const {
    if (k + 1 == n_) return last_;
    std::array<std::uint32_t, 6> words;
    for (std::size_t w = 0; w < 6; ++w) words[w] = tin_.origin(static_cast<EdgeId>(6 * k + w));
    return std::bit_cast<Point3>(words);
  }

 private:
  Triangulation& tin_;
  std::size_t n_;
  Point3 last_{};
};

// Vertices [first, last), all on one line (at least two): the doubly covered segment, 2k - 2
// ghosts from `slot` on. Ghost (p[i+1], p[i], inf) lies on one side of edge p[i] p[i+1] and
// (p[i], p[i+1], inf) on the other; around each vertex the ghosts chain as around any hull.
void build_segment(Triangulation& tin, VertexId first, VertexId last, TriangleId slot) {
  std::vector<VertexId> p(last - first);
  std::iota(p.begin(), p.end(), first);
  std::sort(p.begin(), p.end(),
            [&](VertexId u, VertexId v) { return lex_less(tin.point(u), tin.point(v)); });
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

// A half-edge of a ghost in slots [first, last) whose apex is the infinite vertex.
EdgeId find_ghost(const Triangulation& tin, TriangleId first, TriangleId last) {
  for (TriangleId t = first; t < last; ++t)
    for (EdgeId e = 3 * t; e < 3 * t + 3; ++e)
      if (tin.apex(e) == kInfinite) return e;
  throw internal_error("a half has no ghost");
}

// Triangulates vertices [first, last) (distinct, at least two) into slots from `slot` on; returns
// a ghost half-edge and adds the flips to `flips`. Every 1024 insertions calls `tick(i)`, and
// returns kNoId at once if that is false.
template <class Tick>
EdgeId triangulate_half(Triangulation& tin, VertexId first, VertexId last, TriangleId slot,
                        std::uint64_t& flips, Tick&& tick) {
  if (last < first + 2) throw internal_error("a half needs two vertices");
  const TriangleId end_slot = slot + 2 * (last - first) - 2;
  VertexId third = first + 2;
  int turn = 0;
  for (; third < last; ++third) {
    turn = predicates::orient2d(tin.point(first), tin.point(first + 1), tin.point(third));
    if (turn != 0) break;
  }
  if (third == last) {
    build_segment(tin, first, last, slot);
    return 3 * slot;
  }
  mesh::PointInserter inserter(tin, slot);
  if (turn > 0) {
    inserter.start(first, first + 1, third);
  } else {
    inserter.start(first + 1, first, third);
  }
  for (VertexId v = first + 2; v < last; ++v) {
    if (v == third) continue;
    inserter.insert(v);
    if (((v - first) & 1023) == 0 && !tick(v - first)) return kNoId;
  }
  if (inserter.next_slot() != end_slot) throw internal_error("a half used the wrong slot count");
  flips += inserter.flips();
  return find_ghost(tin, slot, end_slot);
}

// ---- merge
// ---------------------------------------------------------------------------------------- A hull
// edge is named by the finite half-edge g of its ghost (apex infinite): g runs v -> u for the hull
// edge u -> v, which has the hull's inside on its left (counter-clockwise order).
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

}  // namespace

EdgeId triangulate_range(Triangulation& tin, VertexId first, VertexId last, TriangleId slot,
                         std::uint64_t* flips) {
  std::uint64_t count = 0;
  const EdgeId ghost =
      triangulate_half(tin, first, last, slot, count, [](VertexId) { return true; });
  if (flips) *flips += count;
  return ghost;
}

std::uint64_t merge_triangulations(Triangulation& tin, EdgeId left_ghost, EdgeId right_ghost,
                                   TriangleId spare0, TriangleId spare1) {
  const Hull hull(tin);
  // The left hull edge leaving the lexicographically largest left vertex, the right one arriving
  // at the smallest right vertex: the starting points of both tangent searches.
  std::size_t left_size = 0, right_size = 0;
  EdgeId left_out = left_ghost;
  for (EdgeId g = left_ghost;;) {
    if (lex_less(hull.at(hull.from(left_out)), hull.at(hull.from(g)))) left_out = g;
    ++left_size;
    g = hull.next(g);
    if (g == left_ghost) break;
    if (left_size > 2 * tin.vertex_count()) throw internal_error("left hull does not close");
  }
  EdgeId right_in = right_ghost;
  for (EdgeId g = right_ghost;;) {
    if (lex_less(hull.at(hull.to(g)), hull.at(hull.to(right_in)))) right_in = g;
    ++right_size;
    g = hull.next(g);
    if (g == right_ghost) break;
    if (right_size > 2 * tin.vertex_count()) throw internal_error("right hull does not close");
  }
  const std::size_t step_limit = 2 * (left_size + right_size) + 8;

  // Lower tangent l0 -> r0: every point on or left of it; when points are collinear with it,
  // the two closest ones (a hull edge of the union must not pass over a vertex).
  EdgeId gl = left_out;  // hull edge leaving l0
  EdgeId gr = right_in;  // hull edge arriving at r0
  VertexId l0 = hull.from(gl), r0 = hull.to(gr);
  for (std::size_t steps = 0;; ++steps) {
    if (steps > step_limit) throw internal_error("lower tangent search does not end");
    const EdgeId cl = hull.prev(gl);  // arrives at l0 from its clockwise neighbour
    if (hull.orient(l0, r0, hull.from(cl)) < 0) {
      gl = cl;
      l0 = hull.from(gl);
      continue;
    }
    const EdgeId cr = hull.next(gr);  // leaves r0 to its counter-clockwise neighbour
    if (hull.orient(l0, r0, hull.to(cr)) < 0) {
      gr = cr;
      r0 = hull.to(gr);
      continue;
    }
    break;
  }
  // Upper tangent lt -> rt (the union hull runs rt -> lt): every point on or right of it.
  EdgeId ga = hull.prev(left_out);  // hull edge arriving at lt
  EdgeId gb = hull.next(right_in);  // hull edge leaving rt
  VertexId lt = hull.to(ga), rt = hull.from(gb);
  for (std::size_t steps = 0;; ++steps) {
    if (steps > step_limit) throw internal_error("upper tangent search does not end");
    const EdgeId cl = hull.next(ga);
    if (hull.orient(lt, rt, hull.to(cl)) > 0) {
      ga = cl;
      lt = hull.to(ga);
      continue;
    }
    const EdgeId cr = hull.prev(gb);
    if (hull.orient(lt, rt, hull.from(cr)) > 0) {
      gb = cr;
      rt = hull.from(gb);
      continue;
    }
    break;
  }

  // The facing chains: left l0 -> ... -> lt counter-clockwise, right r0 -> ... -> rt clockwise.
  // When a tangent point is shared (l0 == lt) the chain is either empty or, if the other half
  // sees the hull edge after it, the whole hull (the half lies inside the union's hull but for
  // that vertex).
  bool left_all = false, right_all = false;
  if (l0 == lt) {
    const VertexId s = hull.to(gl);
    left_all = hull.orient(l0, s, r0) < 0 || hull.orient(l0, s, rt) < 0;
  }
  if (r0 == rt) {
    const VertexId s = hull.from(gr);
    right_all = hull.orient(s, r0, l0) < 0 || hull.orient(s, r0, lt) < 0;
  }
  std::vector<EdgeId> chain_l, chain_r;  // ghost half-edges of the chain's hull edges
  std::vector<VertexId> lv{l0}, rv{r0};
  if (l0 != lt || left_all) {
    for (EdgeId g = gl;; g = hull.next(g)) {
      chain_l.push_back(g);
      lv.push_back(hull.to(g));
      if (g == ga) break;
      if (chain_l.size() > left_size) throw internal_error("left chain does not reach lt");
    }
  }
  if (r0 != rt || right_all) {
    for (EdgeId g = gr;; g = hull.prev(g)) {
      chain_r.push_back(g);
      rv.push_back(hull.from(g));
      if (g == gb) break;
      if (chain_r.size() > right_size) throw internal_error("right chain does not reach rt");
    }
  }
  if (lv.back() != lt || rv.back() != rt) throw internal_error("chains end off the tangents");

  // Everything read from the chain ghosts before their slots are reused.
  const std::size_t a = chain_l.size(), b = chain_r.size();
  std::vector<EdgeId> outer_l(a), outer_r(b);
  for (std::size_t i = 0; i < a; ++i) outer_l[i] = tin.twin(chain_l[i]);
  for (std::size_t j = 0; j < b; ++j) outer_r[j] = tin.twin(chain_r[j]);
  const EdgeId into_l0 = left_all ? kNoId : tin.twin(next_edge(gl));     // inf -> l0
  const EdgeId out_of_lt = left_all ? kNoId : tin.twin(prev_edge(ga));   // lt -> inf
  const EdgeId out_of_r0 = right_all ? kNoId : tin.twin(prev_edge(gr));  // r0 -> inf
  const EdgeId into_rt = right_all ? kNoId : tin.twin(next_edge(gb));    // inf -> rt
  std::vector<TriangleId> pool;
  pool.reserve(a + b + 2);
  for (EdgeId g : chain_l) pool.push_back(triangle_of(g));
  for (EdgeId g : chain_r) pool.push_back(triangle_of(g));
  pool.push_back(spare0);
  pool.push_back(spare1);
  // A chain ghost's outer twin may itself be a chain ghost (a collinear half covered on both
  // sides): map those to the replacing triangle's edge once known.
  std::vector<std::pair<EdgeId, EdgeId>> replaced;  // old ghost half-edge -> new half-edge
  replaced.reserve(a + b);

  const TriangleId low = pool[a + b], up = pool[a + b + 1];
  const auto set_triangle = [&](TriangleId t, VertexId x, VertexId y, VertexId z) {
    tin.set_corner(3 * t, x);
    tin.set_corner(3 * t + 1, y);
    tin.set_corner(3 * t + 2, z);
  };
  set_triangle(low, r0, l0, kInfinite);  // outside the new hull edge l0 -> r0
  set_triangle(up, lt, rt, kInfinite);   // outside the new hull edge rt -> lt

  // Zipper: from base l -> r, add (l, r, next right) or (l, r, next left), whichever stays inside
  // the gap; when both do, the one whose circumcircle is empty of the other candidate.
  std::vector<EdgeId> fresh;  // half-edges to check for local Delaunay
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
    const TriangleId t = pool[k++];
    const EdgeId e = 3 * t;
    if (can_r) {
      set_triangle(t, l, r, rv[j + 1]);
      replaced.emplace_back(chain_r[j], e + 1);  // r -> r1
      tin.link(e, base_twin);
      base_twin = e + 2;  // r1 -> l
      ++j;
    } else {
      set_triangle(t, l, r, lv[i + 1]);
      replaced.emplace_back(chain_l[i], e + 2);  // l1 -> l
      tin.link(e, base_twin);
      base_twin = e + 1;  // r -> l1
      ++i;
    }
    fresh.insert(fresh.end(), {e, e + 1, e + 2});
  }
  tin.link(3 * up, base_twin);

  // The chain edges take the ghosts' outer twins.
  std::sort(replaced.begin(), replaced.end());
  const auto renamed = [&](EdgeId old) {
    const auto it =
        std::lower_bound(replaced.begin(), replaced.end(), std::make_pair(old, EdgeId{0}));
    return it != replaced.end() && it->first == old ? it->second : old;
  };
  for (std::size_t q = 0; q < a; ++q) tin.link(renamed(chain_l[q]), renamed(outer_l[q]));
  for (std::size_t q = 0; q < b; ++q) tin.link(renamed(chain_r[q]), renamed(outer_r[q]));
  // The new ghosts join the hull's ghost cycle.
  tin.link(3 * low + 1, left_all ? 3 * up + 2 : into_l0);     // l0 -> inf
  tin.link(3 * low + 2, right_all ? 3 * up + 1 : out_of_r0);  // inf -> r0
  if (!left_all) tin.link(3 * up + 2, out_of_lt);             // inf -> lt
  if (!right_all) tin.link(3 * up + 1, into_rt);              // rt -> inf

  // Lawson flips from the new triangles until every edge is locally Delaunay.
  std::uint64_t flips = 0;
  while (!fresh.empty()) {
    const EdgeId e = fresh.back();
    fresh.pop_back();
    const EdgeId f = tin.twin(e);
    const VertexId pa = tin.origin(e), pb = tin.dest(e), pc = tin.apex(e), pd = tin.apex(f);
    if (pa == kInfinite || pb == kInfinite || pc == kInfinite || pd == kInfinite) continue;
    if (predicates::incircle_perturbed(hull.at(pa), hull.at(pb), hull.at(pc), hull.at(pd)) < 0)
      continue;
    tin.flip(e);
    ++flips;
    fresh.insert(fresh.end(), {next_edge(e), prev_edge(e), next_edge(f), prev_edge(f)});
  }
  return flips;
}

bool triangulate_in_two(std::vector<Point3>& input, const BBox& box, const DelaunayOptions& options,
                        const ProgressFn* progress, DelaunayResult& result) {
  const std::size_t n = input.size();
  if (n < 4) return false;
  // One thread or two, the work is the same, and so is every bit of the result.
  const bool concurrent = thread_count(options.threads) != 1;

  // Pivot: the lexicographic median of a sample; left = points strictly smaller. The sample is
  // drawn by a hash of the coordinates, so the split (and with it the vertex numbering and every
  // triangle slot) is a rule of the points alone, not of their order in the input. When the
  // sample says it costs little balance, split between two x values rather than inside a run of
  // equal x (a lattice column): each half's hull then has that whole run as its facing side,
  // instead of a long slanted edge over a fan of thin triangles that the merge would flip away.
  const std::uint64_t sample_mask = std::bit_floor(std::max<std::size_t>(n / 4096, 1)) - 1;
  std::vector<Point2> sample;
  {
    std::vector<Point2> part[2];
    // Multiply-xor: enough spread for a sample, and a third of point_hash()'s cost.
    const auto bits = [](double v) { return std::bit_cast<std::uint64_t>(v + 0.0); };
    const auto draw = [&](std::size_t begin, std::size_t end, std::vector<Point2>& to) {
      to.reserve(2 * (end - begin) / (sample_mask + 1) + 16);
      for (std::size_t i = begin; i < end; ++i) {
        const Point3& p = input[i];
        const std::uint64_t h =
            bits(p.x) * 0x9e3779b97f4a7c15ULL ^ bits(p.y) * 0xc2b2ae3d27d4eb4fULL;
        if (((h >> 40) & sample_mask) == 0) to.push_back({p.x, p.y});
      }
    };
    run_two(
        concurrent, [&] { draw(0, n / 2, part[0]); }, [&] { draw(n / 2, n, part[1]); });
    sample = std::move(part[0]);
    sample.insert(sample.end(), part[1].begin(), part[1].end());
  }
  if (sample.empty()) return false;
  std::sort(sample.begin(), sample.end(), lex_less);
  const std::size_t samples = sample.size();
  Point2 pivot = sample[samples / 2];
  {
    const auto x_less = [](Point2 a, Point2 b) { return a.x < b.x; };
    const auto lo = std::lower_bound(sample.begin(), sample.end(), pivot, x_less);
    const auto hi = std::upper_bound(sample.begin(), sample.end(), pivot, x_less);
    const auto off_middle = [&](auto it) {
      const auto k = static_cast<std::size_t>(it - sample.begin());
      return k > samples / 2 ? k - samples / 2 : samples / 2 - k;
    };
    const std::size_t tolerance = samples / 20;  // 5 %
    constexpr double inf = std::numeric_limits<double>::infinity();
    if (off_middle(lo) <= off_middle(hi) && off_middle(lo) <= tolerance) {
      pivot.y = -inf;  // left: x < pivot.x
    } else if (off_middle(hi) <= tolerance) {
      pivot.y = inf;  // left: x <= pivot.x
    }
  }
  const auto is_left = [pivot](const Point3& p) {
    return p.x < pivot.x || (p.x == pivot.x && p.y < pivot.y);
  };

  // Each half needs two distinct points, and not all points may be collinear.
  {
    std::size_t first[2] = {n, n}, second[2] = {n, n};
    for (std::size_t i = 0; i < n && (second[0] == n || second[1] == n); ++i) {
      const Point3& p = input[i];
      const int side = is_left(p) ? 0 : 1;
      if (first[side] == n) {
        first[side] = i;
      } else if (second[side] == n &&
                 (input[first[side]].x != p.x || input[first[side]].y != p.y)) {
        second[side] = i;
      }
    }
    if (second[0] == n || second[1] == n) return false;
    const Point2 a{input[first[0]].x, input[first[0]].y};
    const Point2 b{input[second[0]].x, input[second[0]].y};
    bool off_line = false;
    for (std::size_t i = 0; i < n && !off_line; ++i)
      off_line = predicates::orient2d(a, b, {input[i].x, input[i].y}) != 0;
    if (!off_line) return false;
  }

  // Meanwhile a third thread makes the triangle slots, betting that no two points coincide (then
  // there are 2n - 2); this is the one phase where they fit in the memory budget beside the input.
  // It is also the longest part before the insertion can start (the first touch of 48 bytes per
  // point in one thread, as Triangulation grows only by add_triangle), so as much work as possible
  // runs beside it. It touches only the triangle arrays of tin; until it is joined, the other
  // threads touch only the vertex arrays (add_vertex), never the same member.
  Triangulation& tin = result.tin;
  tin.reserve_vertices(n);
  std::exception_ptr slot_error;
  const auto make_slots = [&] {
    try {
      tin.reserve_triangles(2 * n - 2);
      for (std::size_t t = 0; t + 2 < 2 * n; ++t) tin.add_triangle(kNoId, kNoId, kNoId);
    } catch (...) {
      slot_error = std::current_exception();
    }
  };
  std::thread slot_maker;
  if (concurrent) {
    slot_maker = std::thread(make_slots);
  } else {
    make_slots();
  }
  struct Joiner {
    std::thread& thread;
    ~Joiner() {
      if (thread.joinable()) thread.join();
    }
  } joiner{slot_maker};

  // The (key, index) items, left ones first, each side in input order; then each side sorted.
  Scratch<std::uint64_t> items(n);
  const std::size_t mid = n / 2;
  std::size_t left_in_chunk[2] = {0, 0};
  run_two(
      concurrent,
      [&] {
        for (std::size_t i = 0; i < mid; ++i) left_in_chunk[0] += is_left(input[i]);
      },
      [&] {
        for (std::size_t i = mid; i < n; ++i) left_in_chunk[1] += is_left(input[i]);
      });
  const std::size_t left_items = left_in_chunk[0] + left_in_chunk[1];
  const OrderKey key(box);
  const auto fill = [&](std::size_t begin, std::size_t end, std::size_t at_left,
                        std::size_t at_right) {
    for (std::size_t i = begin; i < end; ++i) {
      const std::uint64_t item = (std::uint64_t{key(input[i])} << 32) | i;
      if (is_left(input[i])) {
        items[at_left++] = item;
      } else {
        items[at_right++] = item;
      }
    }
  };
  run_two(
      concurrent, [&] { fill(0, mid, 0, left_items); },
      [&] { fill(mid, n, left_in_chunk[0], left_items + (mid - left_in_chunk[0])); });
  run_two(
      concurrent, [&] { sort_half(input, items.data(), left_items); },
      [&] { sort_half(input, items.data() + left_items, n - left_items); });

  // Each side's distinct points, in order: the left ones straight into the vertices while the
  // slots are still being made, the right ones, once the slots exist, into the stash from
  // left_items on. Items are given back as they are read.
  if (options.keep_point_map) result.vertex_of_point.assign(n, kNoId);
  VertexId* point_map = options.keep_point_map ? result.vertex_of_point.data() : nullptr;
  PointStash stash(tin, n);
  HalfPoints half[2];
  // Merged groups: the left half's straight into the result, the right half's (vertex ids within
  // the half) into a list of their own, appended once both are done.
  std::vector<DelaunayResult::Duplicate> right_duplicates;
  std::vector<DelaunayResult::Duplicate>* duplicates[2] = {nullptr, nullptr};
  if (options.keep_duplicates) {
    duplicates[0] = &result.duplicates;
    duplicates[1] = &right_duplicates;
  }
  run_two(
      concurrent,
      [&] {
        half[0] = gather_half(
            input, items.data(), left_items, point_map, duplicates[0], options.on_duplicate,
            [&](std::size_t, const Point3& p) {
              tin.add_vertex({p.x, p.y}, p.z);
            },
            [&](std::size_t k) { items.release(0, k); });
      },
      [&] {
        if (slot_maker.joinable()) slot_maker.join();
        if (slot_error) std::rethrow_exception(slot_error);
        half[1] = gather_half(
            input, items.data() + left_items, n - left_items, point_map, duplicates[1],
            options.on_duplicate,
            [&](std::size_t k, const Point3& p) { stash.put(left_items + k, p); },
            [&](std::size_t k) {
              if (!point_map) items.release(left_items, left_items + k);  // else read below
            });
      });
  const auto nl = static_cast<VertexId>(half[0].count);
  const auto nr = static_cast<VertexId>(half[1].count);
  const VertexId nv = nl + nr;
  if (point_map)
    for (std::size_t k = left_items; k < n; ++k)
      point_map[static_cast<std::uint32_t>(items[k])] += nl;
  result.duplicates_merged = half[0].duplicates + half[1].duplicates;
  if (options.keep_duplicates) {
    result.duplicates.reserve(result.duplicates.size() + right_duplicates.size());
    for (DelaunayResult::Duplicate d : right_duplicates) {
      d.vertex += nl;
      result.duplicates.push_back(d);
    }
  }
  items.release();
  std::vector<Point3>().swap(input);

  // Then the right vertices.
  const auto add_right = [&](Triangulation& to) {
    for (std::size_t k = 0; k < nr; ++k) {
      const Point3 p = stash.get(left_items + k);
      to.add_vertex({p.x, p.y}, p.z);
    }
  };
  if (nv == n) {
    add_right(tin);
  } else {  // coinciding points: too many slots were made, make them again
    Triangulation exact;
    exact.reserve_vertices(nv);
    for (VertexId v = 0; v < nl; ++v) exact.add_vertex(tin.point(v), tin.z(v));
    add_right(exact);
    tin = std::move(exact);
    tin.reserve_triangles(2 * std::size_t{nv} - 2);
    for (std::size_t t = 0; t + 2 < 2 * std::size_t{nv}; ++t) tin.add_triangle(kNoId, kNoId, kNoId);
  }

  // Slots: left [0, 2nl - 2), right [2nl - 2, 2nv - 4), two spares for the merge.
  Progress report(progress, "delaunay", nv);
  std::atomic<bool> stop{false};  // set when either half fails, so that the other gives up
  std::uint64_t flips[2] = {0, 0};
  EdgeId ghost[2] = {kNoId, kNoId};
  const TriangleId right_slot = 2 * nl - 2;
  const auto guarded = [&](auto&& work) {
    try {
      work();
    } catch (...) {
      stop.store(true);
      throw;
    }
  };
  run_two(
      concurrent,
      [&] {
        guarded([&] {
          ghost[0] = triangulate_half(tin, 0, nl, 0, flips[0], [&](VertexId done) {
            report.tick(std::uint64_t{done} * nv / nl);  // both halves go at about one pace
            return !stop.load(std::memory_order_relaxed);
          });
        });
      },
      [&] {
        guarded([&] {
          ghost[1] = triangulate_half(tin, nl, nv, right_slot, flips[1], [&](VertexId) {
            return !stop.load(std::memory_order_relaxed);
          });
        });
      });
  if (ghost[0] == kNoId || ghost[1] == kNoId) throw internal_error("a half stopped early");
  const auto spare = 2 * nv - 4;
  const std::uint64_t merge_flips = merge_triangulations(tin, ghost[0], ghost[1], spare, spare + 1);
  result.flips = flips[0] + flips[1] + merge_flips;
  tin.recount();
  report.finish();
  return true;
}

}  // namespace tincdt::delaunay
