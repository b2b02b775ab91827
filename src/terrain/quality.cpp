#include "terrain/quality.hpp"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <numbers>

#include "core/json.hpp"
#include "core/parallel.hpp"

namespace tincdt::terrain {

namespace {

constexpr int kBinsPerDecade = 4;

// Bin edge k of the length grid: 10^(k / 4).
double grid_edge(int k) {
  return std::pow(10.0, static_cast<double>(k) / kBinsPerDecade);
}

// Edge lengths are counted as they come (tens of millions of edges: no list of them), on the
// fixed grid 10^(k/4); bin k's edges are tabled once for the whole double range.
constexpr int kLowest = -1300, kHighest = 1300;
constexpr std::size_t kLengthBins = kHighest - kLowest + 1;

const std::vector<double>& bin_edges() {
  static const std::vector<double> edges = [] {
    std::vector<double> e;
    for (int k = kLowest; k <= kHighest + 1; ++k) e.push_back(grid_edge(k));
    return e;
  }();
  return edges;
}

// The bins of the lengths 2^(f - 1023), by the raw exponent field f of a double.
const std::vector<int>& octave_bins() {
  static const std::vector<int> bins = [] {
    const std::vector<double>& edge = bin_edges();
    std::vector<int> b(2048);
    for (int f = 0; f < 2048; ++f) {
      const double l = std::ldexp(1.0, std::clamp(f, 1, 2046) - 1023);
      int k = kLowest;
      while (k < kHighest && l >= edge[static_cast<std::size_t>(k + 1 - kLowest)]) ++k;
      b[static_cast<std::size_t>(f)] = k;
    }
    return b;
  }();
  return bins;
}

// The bin of a length l > 0: bin_edges()[k] <= l < bin_edges()[k + 1]. The bin of l's octave
// (its binary exponent), then at most two steps up, since an octave spans 1.2 bins, taken
// without a branch; so the counts agree with the bins as printed.
inline std::size_t length_bin(double l, const std::vector<double>& edge,
                              const std::vector<int>& octave) {
  int k = octave[static_cast<std::size_t>(std::bit_cast<std::uint64_t>(l) >> 52 & 0x7ff)];
  while (k > kLowest && l < edge[static_cast<std::size_t>(k - kLowest)]) --k;  // subnormal
  k += static_cast<int>(k < kHighest && l >= edge[static_cast<std::size_t>(k + 1 - kLowest)]);
  k += static_cast<int>(k < kHighest && l >= edge[static_cast<std::size_t>(k + 1 - kLowest)]);
  return static_cast<std::size_t>(k - kLowest);
}

// cos^2 of 10, 20, ..., 80 degrees: an angle of cosine c >= 0 is at least 10 j degrees exactly
// when c^2 <= kCos2[j - 1].
constexpr double kCos2[8] = {0.96984631039295421, 0.88302222155948906, 0.75000000000000011,
                             0.58682408883346526, 0.41317591116653485, 0.25000000000000011,
                             0.11697777844051105, 0.030153689607045842};

// How many of 10, 20, ..., 80 degrees an acute angle of squared cosine c2 reaches, that is how
// many kCos2[j] are >= c2, by a table over 256 cells of [0, 1]: no two thresholds share a cell,
// so the count is the cell's own (thresholds above it) plus at most one comparison.
struct AngleCells {
  std::array<std::uint8_t, 257> above{};
  std::array<double, 257> inside{};  // the threshold inside the cell, or -1
  AngleCells() {
    for (std::size_t i = 0; i <= 256; ++i) {
      const double low = static_cast<double>(i) / 256, high = static_cast<double>(i + 1) / 256;
      inside[i] = -1;
      for (double c : kCos2) {
        if (c >= high)
          ++above[i];
        else if (c >= low)
          inside[i] = c;
      }
    }
  }
};
const AngleCells kAngleCells;

// The 10-degree bin of an angle from its cosine's sign and square: no trigonometry.
inline std::size_t angle_bin(double dot, double cos2) {
  if (dot == 0) return 9;
  const auto cell = static_cast<std::size_t>((cos2 < 1 ? cos2 : 1.0) * 256);  // NaN: 1
  const int below = kAngleCells.above[cell] + (cos2 <= kAngleCells.inside[cell]);
  return static_cast<std::size_t>(dot > 0 ? below : 17 - below);
}

// An angle key that decreases as the angle grows over [0, 180]: sign(cos) cos^2.
double angle_key(double dot, double cos2) {
  return dot >= 0 ? cos2 : -cos2;
}

// One triangle's corner, to measure exactly at the end.
struct Corner {
  TriangleId t = kNoId;
  int i = 0;
  double key = 0;
};

double corner_degrees(const mesh::Triangulation& tin, const Corner& c) {
  const std::array<VertexId, 3> v = tin.triangle(c.t);
  const Point2 a = tin.point(v[static_cast<std::size_t>(c.i)]);
  const Point2 b = tin.point(v[static_cast<std::size_t>((c.i + 1) % 3)]);
  const Point2 d = tin.point(v[static_cast<std::size_t>((c.i + 2) % 3)]);
  const double bx = b.x - a.x, by = b.y - a.y, dx = d.x - a.x, dy = d.y - a.y;
  // atan2(|cross|, dot) is accurate near 0 and 180 degrees, where acos of a ratio is not.
  return std::atan2(std::fabs(bx * dy - by * dx), bx * dx + by * dy) * 180 / std::numbers::pi;
}

// Counts, minima and maxima: they merge in any order. A block keeps its own on the stack (so
// that they can live in registers) and adds it to its thread's at the end.
struct Tally {
  std::uint64_t triangles = 0, below_20 = 0, flats = 0, edges = 0;
  std::uint64_t removed = 0;  // real triangles that are removed (trimmed, clipped, erased)
  std::array<std::uint64_t, 18> angles{};
  double min_length = HUGE_VAL, max_length = 0, max_ratio = 0;
  Corner smallest{kNoId, 0, -2}, largest{kNoId, 0, 2};  // by angle_key
};

// Sums of doubles go per block, so that they do not depend on the threads.
struct Sums {
  double area_2d = 0, area_3d = 0, length = 0;
};

// What one thread measures of its share of the triangles.
struct Partial {
  Tally tally;
  std::vector<std::uint64_t> lengths = std::vector<std::uint64_t>(kLengthBins, 0);
};

void merge(Tally& into, const Tally& p) {
  into.triangles += p.triangles;
  into.below_20 += p.below_20;
  into.flats += p.flats;
  into.edges += p.edges;
  into.removed += p.removed;
  for (std::size_t k = 0; k < into.angles.size(); ++k) into.angles[k] += p.angles[k];
  into.min_length = std::min(into.min_length, p.min_length);
  into.max_length = std::max(into.max_length, p.max_length);
  into.max_ratio = std::max(into.max_ratio, p.max_ratio);
  // Ties go to the lower triangle id, so that the corner does not depend on the threads.
  const auto better = [](const Corner& a, const Corner& b, bool larger_key) {
    if (a.key != b.key) return larger_key ? a.key > b.key : a.key < b.key;
    return a.t < b.t;
  };
  if (p.smallest.t != kNoId && better(p.smallest, into.smallest, true)) into.smallest = p.smallest;
  if (p.largest.t != kNoId && better(p.largest, into.largest, false)) into.largest = p.largest;
}

constexpr std::size_t kBlock = 1 << 16;  // triangle slots per block of sums

// Edge lengths waiting to be binned. The triangle loop only appends them (a store to a known
// address); binning them there, a store to a computed address, held up every load after it.
struct Lengths {
  static constexpr std::size_t kPending = 4096;
  std::uint64_t* histogram;
  std::size_t n;
  double pending[kPending + 1];
};

class Measurer {
 public:
  Measurer(const mesh::Triangulation& tin, const std::vector<std::uint8_t>* on_contour)
      : tin_(tin), on_contour_(on_contour), edge_(bin_edges()), octave_(octave_bins()) {}

  void block(std::size_t b, Partial& into, Sums& s) const {
    Tally p;
    Lengths lengths{into.lengths.data(), 0, {}};
    const std::size_t end = std::min(tin_.triangle_slots(), (b + 1) * kBlock);
    for (std::size_t t = b * kBlock; t < end; ++t) {
      const auto id = static_cast<TriangleId>(t);
      if (tin_.is_kept(id)) {
        triangle(id, p, s, lengths);
      } else {
        if (!tin_.is_ghost(id)) ++p.removed;
        boundary(id, p, s, lengths);
      }
    }
    flush(lengths, p, s);
    merge(into.tally, p);
  }

 private:
  // Every edge is counted once: from a kept triangle where it runs from the smaller vertex id
  // to the larger, or, when its other side is not kept (a ghost on the hull, a removed
  // triangle), from that other side here. So the hot loop never looks at a neighbour.
  void boundary(TriangleId t, Tally& p, Sums& s, Lengths& lengths) const {
    for (EdgeId e = 3 * t; e < 3 * t + 3; ++e) {
      const EdgeId twin = tin_.twin(e);
      const VertexId u = tin_.origin(e), v = tin_.dest(e);
      if (!tin_.is_kept(mesh::triangle_of(twin)) || !(v > u)) continue;
      const Point2 a = tin_.point(u), b = tin_.point(v);
      const double dx = b.x - a.x, dy = b.y - a.y;
      edge(std::sqrt(dx * dx + dy * dy), true, p, s, lengths);
    }
  }

  void triangle(TriangleId t, Tally& p, Sums& s, Lengths& lengths) const {
    const std::array<VertexId, 3> c = tin_.triangle(t);
    ++p.triangles;
    // The three-step loops are unrolled so that the corners stay in registers.
    Point3 q[3];
#pragma GCC unroll 3
    for (int i = 0; i < 3; ++i) {
      const Point2 xy = tin_.point(c[i]);
      q[i] = {xy.x, xy.y, tin_.z(c[i])};
    }
    // e[i]: corner i -> i + 1, in x, y; l2 its squared length, len its length.
    double ex[3], ey[3], l2[3], len[3];
#pragma GCC unroll 3
    for (int i = 0; i < 3; ++i) {
      const Point3& a = q[i];
      const Point3& b = q[(i + 1) % 3];
      ex[i] = b.x - a.x;
      ey[i] = b.y - a.y;
      l2[i] = ex[i] * ex[i] + ey[i] * ey[i];
      len[i] = std::sqrt(l2[i]);
      // The other side of the rest: boundary().
      edge(len[i], c[i] < c[(i + 1) % 3], p, s, lengths);
    }
    // Areas from coordinate differences (large map coordinates stay exact enough).
    const double uz = q[1].z - q[0].z, vz = q[2].z - q[0].z;
    const double ux = ex[0], uy = ey[0], vx = -ex[2], vy = -ey[2];
    const double area2 = ux * vy - uy * vx;
    s.area_2d += 0.5 * area2;
    s.area_3d += 0.5 * std::sqrt((uy * vz - uz * vy) * (uy * vz - uz * vy) +
                                 (uz * vx - ux * vz) * (uz * vx - ux * vz) + area2 * area2);
    // Corner i lies between edge i (outgoing) and edge i - 1 (incoming, reversed); its cos^2 is
    // dot^2 / (l2[i] l2[i - 1]) = dot^2 l2[i + 1] / (l2[0] l2[1] l2[2]): one division for three.
    const double inverse = 1 / (l2[0] * l2[1] * l2[2]);
    double key[3];
#pragma GCC unroll 3
    for (int i = 0; i < 3; ++i) {
      const int in = (i + 2) % 3;
      const double dot = -(ex[i] * ex[in] + ey[i] * ey[in]);
      const double cos2 = dot * dot * l2[(i + 1) % 3] * inverse;
      ++p.angles[angle_bin(dot, cos2)];
      key[i] = angle_key(dot, cos2);
    }
    // The triangle's smallest and largest angle first; which corner, only for a new extreme.
    const double smallest = std::max({key[0], key[1], key[2]});
    const double largest = std::min({key[0], key[1], key[2]});
    if (smallest > p.smallest.key) p.smallest = {t, corner_with(key, smallest), smallest};
    if (largest < p.largest.key) p.largest = {t, corner_with(key, largest), largest};
    if (smallest > kCos2[1]) ++p.below_20;
    // R / r = abc / (4A) / (2A / (a + b + c)) = abc (a + b + c) / (8 A^2), with 2A = area2.
    const double ratio =
        len[0] * len[1] * len[2] * (len[0] + len[1] + len[2]) / (2 * area2 * area2);
    p.max_ratio = std::max(p.max_ratio, ratio);
    // Flat needs equal z, rare: the contour test only then.
    if (q[0].z == q[1].z && q[0].z == q[2].z && is_flat(tin_, c, on_contour_)) ++p.flats;
  }

  static int corner_with(const double (&key)[3], double k) {
    return key[0] == k ? 0 : (key[1] == k ? 1 : 2);
  }

  // Queues an edge of length L when COUNTED, without a branch: half the edges of a triangle are
  // counted and half are not, in no order a predictor could learn.
  void edge(double l, bool counted, Tally& p, Sums& s, Lengths& lengths) const {
    lengths.pending[lengths.n] = l;
    lengths.n += counted;
    if (lengths.n == Lengths::kPending) flush(lengths, p, s);
  }
  void flush(Lengths& lengths, Tally& p, Sums& s) const {
    for (std::size_t i = 0; i < lengths.n; ++i) {
      const double l = lengths.pending[i];
      p.min_length = std::min(p.min_length, l);
      p.max_length = std::max(p.max_length, l);
      s.length += l;
      ++lengths.histogram[length_bin(l, edge_, octave_)];
    }
    p.edges += lengths.n;
    lengths.n = 0;
  }

  const mesh::Triangulation& tin_;
  const std::vector<std::uint8_t>* on_contour_;
  const std::vector<double>& edge_;
  const std::vector<int>& octave_;
};

void merge(Partial& into, const Partial& p) {
  merge(into.tally, p.tally);
  for (std::size_t k = 0; k < kLengthBins; ++k) into.lengths[k] += p.lengths[k];
}

void fill(QualityReport& q, const Partial& all, const mesh::Triangulation& tin) {
  const Tally& p = all.tally;
  q.triangles = p.triangles;
  q.triangles_below_20deg = p.below_20;
  q.flat_triangles = p.flats;
  q.angle_histogram = p.angles;
  q.edges = p.edges;
  if (q.triangles) {
    q.min_angle_deg = corner_degrees(tin, p.smallest);
    q.max_angle_deg = corner_degrees(tin, p.largest);
    q.max_radius_ratio = p.max_ratio;
  }
  if (!q.edges) return;
  q.min_edge_length = p.min_length;
  q.max_edge_length = p.max_length;
  std::size_t first = 0, last = kLengthBins - 1;
  const std::vector<std::uint64_t>& lengths = all.lengths;
  while (lengths[first] == 0) ++first;
  while (lengths[last] == 0) --last;
  const std::vector<double>& edge = bin_edges();
  q.edge_length_bin_edges.assign(edge.begin() + static_cast<std::ptrdiff_t>(first),
                                 edge.begin() + static_cast<std::ptrdiff_t>(last) + 2);
  q.edge_length_histogram.assign(lengths.begin() + static_cast<std::ptrdiff_t>(first),
                                 lengths.begin() + static_cast<std::ptrdiff_t>(last) + 1);
}

// Vertices that are a corner of a kept triangle. Every vertex of a TIN without removed triangles
// is; with removed ones, the kept triangles mark theirs.
std::uint64_t used_vertices(const mesh::Triangulation& tin, bool removed, unsigned threads) {
  if (!removed) return tin.vertex_count();
  std::vector<std::uint8_t> used(tin.vertex_count(), 0);
  parallel_chunks(threads, tin.triangle_slots(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t) {
      if (!tin.is_kept(static_cast<TriangleId>(t))) continue;
      for (VertexId v : tin.triangle(static_cast<TriangleId>(t)))
        std::atomic_ref<std::uint8_t>(used[v]).store(1, std::memory_order_relaxed);
    }
  });
  std::uint64_t n = 0;
  for (std::uint8_t u : used) n += u;
  return n;
}

}  // namespace

QualityReport measure_quality(const mesh::Triangulation& tin,
                              const std::vector<std::uint8_t>* on_contour, unsigned threads) {
  QualityReport q;
  q.flats_need_contours = on_contour != nullptr;
  const std::size_t blocks = (tin.triangle_slots() + kBlock - 1) / kBlock;
  std::vector<Sums> sums(blocks);
  // One part of blocks per thread, each with its own Partial.
  const std::size_t parts = part_count(threads, blocks, 1);
  std::vector<Partial> partial(parts);
  const Measurer measurer(tin, on_contour);
  parallel_parts(parts, blocks, [&](std::size_t part, std::size_t begin, std::size_t end) {
    for (std::size_t b = begin; b < end; ++b) measurer.block(b, partial[part], sums[b]);
  });
  Partial all;
  for (const Partial& p : partial) merge(all, p);
  fill(q, all, tin);
  double length = 0;
  for (const Sums& s : sums) {
    q.area_2d += s.area_2d;
    q.area_3d += s.area_3d;
    length += s.length;
  }
  if (q.edges) q.mean_edge_length = length / static_cast<double>(q.edges);
  q.vertices = used_vertices(tin, all.tally.removed > 0, threads);
  return q;
}

std::string QualityReport::to_json() const {
  json::Writer j(json::Numbers::shortest);
  j.begin_object(json::Layout::compact);
  j.field("triangles", triangles).field("vertices", vertices);
  j.field("area_2d", area_2d).field("area_3d", area_3d);
  j.field("min_angle_deg", min_angle_deg).field("max_angle_deg", max_angle_deg);
  j.field("angle_bin_width_deg", 10).key("angle_histogram").array(angle_histogram);
  j.field("triangles_below_20deg", triangles_below_20deg);
  j.field("max_circumradius_to_inradius", max_radius_ratio);
  j.field("flat_triangles", flat_triangles);
  j.field("flat_rule", flats_need_contours ? "equal z, all corners on contours" : "equal z");
  j.field("edges", edges).field("min_edge_length", min_edge_length);
  j.field("mean_edge_length", mean_edge_length).field("max_edge_length", max_edge_length);
  j.key("edge_length_bin_edges").array(edge_length_bin_edges);
  j.key("edge_length_histogram").array(edge_length_histogram);
  j.end_object();
  return j.str();
}

}  // namespace tincdt::terrain
