#include "products/rasterize.hpp"

#include <algorithm>
#include <atomic>
#include <vector>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "core/parallel.hpp"

namespace tincdt::products {

using mesh::next_edge;
using mesh::prev_edge;
using mesh::triangle_of;
using predicates::orient2d;

namespace {

// Directions from a vertex w, compared by angle in [0, 2 pi) counter-clockwise from +x, exactly:
// the half-plane (angle in [0, pi) or [pi, 2 pi)) from the signs of the differences, then
// orient2d within a half-plane.
int half_of(Point2 w, Point2 d) {
  return (d.y > w.y || (d.y == w.y && d.x > w.x)) ? 0 : 1;
}
bool angle_less(Point2 w, Point2 a, Point2 b) {
  const int ha = half_of(w, a), hb = half_of(w, b);
  if (ha != hb) return ha < hb;
  return orient2d(w, a, b) > 0;
}
bool angle_is_zero(Point2 w, Point2 d) {
  return d.y == w.y && d.x > w.x;
}

// P is the corner of T at half-edge E_OUT (leaving the corner w). See owns_point: T owns w when
// +x lies in [end(K), end(T)), K the kept triangle before T clockwise around w.
bool owns_vertex(const mesh::Triangulation& tin, EdgeId e_out) {
  const Point2 w = tin.point(tin.origin(e_out));
  const Point2 end_t = tin.point(tin.origin(prev_edge(e_out)));
  // Clockwise around w: across the first edge of the wedge (w -> b) lies the previous triangle,
  // where that edge runs b -> w; its own first edge is the next half-edge.
  EdgeId e = e_out;
  for (;;) {
    e = next_edge(tin.twin(e));
    if (e == e_out) return true;  // the only kept triangle around w
    if (tin.is_kept(triangle_of(e))) break;
  }
  const Point2 end_k = tin.point(tin.origin(prev_edge(e)));
  // +x in the counter-clockwise half-open range [end_k, end_t).
  if (angle_is_zero(w, end_k)) return true;
  return !angle_is_zero(w, end_t) && angle_less(w, end_t, end_k);
}

// Rows per band: enough bands for the threads to share the work evenly, each a few hundred rows
// at most so that the band's cells stay near in memory.
std::uint32_t band_rows(const Grid& grid, unsigned threads) {
  const std::uint32_t per_thread = grid.height / (4 * threads) + 1;
  return std::clamp<std::uint32_t>(per_thread, 1, 256);
}

}  // namespace

bool owns_point(const mesh::Triangulation& tin, TriangleId t, Point2 p) {
  if (!tin.is_kept(t)) return false;
  const EdgeId e0 = 3 * t;
  int zero_count = 0;
  EdgeId zero_edge = kNoId;
  for (EdgeId e = e0; e < e0 + 3; ++e) {
    const int o = orient2d(tin.point(tin.origin(e)), tin.point(tin.dest(e)), p);
    if (o < 0) return false;
    if (o == 0) {
      // Two zero edges meet at their shared corner: remember the one leaving it.
      zero_edge = zero_count == 0 ? e : (zero_edge == prev_edge(e) ? e : zero_edge);
      ++zero_count;
    }
  }
  if (zero_count == 0) return true;
  if (zero_count == 1) {
    if (!tin.is_kept(triangle_of(tin.twin(zero_edge)))) return true;
    const Point2 a = tin.point(tin.origin(zero_edge)), b = tin.point(tin.dest(zero_edge));
    return b.y < a.y || (b.y == a.y && b.x > a.x);
  }
  // On two edges (three is impossible for a triangle of positive area): P is their common
  // corner, the origin of the later one.
  return owns_vertex(tin, zero_edge);
}

namespace {

// The kept triangles of each band (CSR: band b's are triangles[start[b], start[b + 1])): a
// triangle goes to every band its rows reach.
struct BandIndex {
  std::vector<std::size_t> start;
  std::vector<TriangleId> triangles;
};

BandIndex index_bands(const mesh::Triangulation& tin, const Grid& grid, std::uint32_t rows_per_band,
                      std::uint32_t bands) {
  const auto slots = static_cast<TriangleId>(tin.triangle_slots());
  std::vector<std::uint32_t> first_band(slots, kNoId), last_band(slots, 0);
  BandIndex index;
  index.start.assign(std::size_t{bands} + 1, 0);
  std::vector<std::size_t>& start = index.start;
  for (TriangleId t = 0; t < slots; ++t) {
    if (!tin.is_kept(t)) continue;
    const auto c = tin.triangle(t);
    const double y0 = tin.point(c[0]).y, y1 = tin.point(c[1]).y, y2 = tin.point(c[2]).y;
    const std::uint32_t r0 = detail::first_row_at_or_below(grid, std::max({y0, y1, y2}));
    const std::uint32_t r1 =
        detail::first_row_at_or_below(grid, std::nextafter(std::min({y0, y1, y2}), -INFINITY));
    if (r0 >= r1) continue;
    first_band[t] = r0 / rows_per_band;
    last_band[t] = (r1 - 1) / rows_per_band;
    for (std::uint32_t b = first_band[t]; b <= last_band[t]; ++b) ++start[b + 1];
  }
  for (std::uint32_t b = 0; b < bands; ++b) start[b + 1] += start[b];
  index.triangles.resize(start[bands]);
  std::vector<std::size_t> fill(start.begin(), start.end() - 1);
  for (TriangleId t = 0; t < slots; ++t) {
    if (first_band[t] == kNoId) continue;
    for (std::uint32_t b = first_band[t]; b <= last_band[t]; ++b) index.triangles[fill[b]++] = t;
  }
  return index;
}

// Writes the cells of rows [ROW_BEGIN, ROW_END) whose centres triangle T owns; returns how many.
template <class T>
std::uint64_t fill_triangle(const mesh::Triangulation& tin, const Grid& grid, TriangleId t,
                            std::uint32_t row_begin, std::uint32_t row_end, std::span<T> cells) {
  // The plane through the corners, as z(a) + gx (x - a.x) + gy (y - a.y): differences from a
  // corner keep the digits of map coordinates. A is the corner smallest by (x, y) and the others
  // follow in the triangle's order, so the same triangle gives the same doubles in any TIN that
  // holds it (the DEM tiles of a tiled job match the whole job).
  auto v = tin.triangle(t);
  const auto before = [&tin](VertexId p, VertexId q) {
    const Point2 pp = tin.point(p), pq = tin.point(q);
    return pp.x < pq.x || (pp.x == pq.x && pp.y < pq.y);
  };
  if (before(v[1], v[0]) && before(v[1], v[2]))
    v = {v[1], v[2], v[0]};
  else if (before(v[2], v[0]) && before(v[2], v[1]))
    v = {v[2], v[0], v[1]};
  const Point2 a = tin.point(v[0]), pb = tin.point(v[1]), pc = tin.point(v[2]);
  const double za = tin.z(v[0]);
  const double bx = pb.x - a.x, by = pb.y - a.y, bz = tin.z(v[1]) - za;
  const double cx = pc.x - a.x, cy = pc.y - a.y, cz = tin.z(v[2]) - za;
  const double det = bx * cy - cx * by;
  const double gx = (bz * cy - cz * by) / det;
  const double gy = (cz * bx - bz * cx) / det;
  std::uint64_t count = 0;
  scan_triangle(tin, grid, t, row_begin, row_end,
                [&](std::uint32_t row, std::uint32_t first, std::uint32_t end) {
                  const double z_row = za + gy * (grid.centre_y(row) - a.y);
                  T* out = cells.data() + std::size_t{row} * grid.width;
                  for (std::uint32_t col = first; col < end; ++col)
                    out[col] = static_cast<T>(z_row + gx * (grid.centre_x(col) - a.x));
                  count += end - first;
                });
  return count;
}

}  // namespace

template <class T>
RasterizeStats rasterize(const mesh::Triangulation& tin, const Grid& grid, T nodata,
                         std::span<T> cells, const RasterizeOptions& options) {
  if (cells.size() != grid.cells())
    throw Error("rasterize: " + count_text(cells.size()) + " cells given for a grid of " +
                count_text(grid.cells()));
  RasterizeStats stats;
  if (grid.cells() == 0) return stats;
  const auto threads = static_cast<unsigned>(thread_count(options.threads));
  const std::uint32_t rows_per_band = band_rows(grid, threads);
  const std::uint32_t bands = (grid.height + rows_per_band - 1) / rows_per_band;
  const BandIndex index = index_bands(tin, grid, rows_per_band, bands);

  // Threads take the bands in turn; each band's cells are its own.
  Progress progress(options.progress, "dem", bands);
  std::atomic<std::uint32_t> next_band{0};
  std::atomic<std::uint32_t> bands_done{0};
  std::atomic<bool> stop{false};
  std::atomic<std::uint64_t> with_value{0};
  const auto work = [&](std::size_t worker) {
    try {
      std::uint64_t count = 0;
      while (!stop.load(std::memory_order_relaxed)) {
        const std::uint32_t b = next_band.fetch_add(1);
        if (b >= bands) break;
        const std::uint32_t row_begin = b * rows_per_band;
        const std::uint32_t row_end = std::min(grid.height, row_begin + rows_per_band);
        T* band = cells.data() + std::size_t{row_begin} * grid.width;
        std::fill(band, band + std::size_t{row_end - row_begin} * grid.width, nodata);
        for (std::size_t i = index.start[b]; i < index.start[b + 1]; ++i)
          count += fill_triangle(tin, grid, index.triangles[i], row_begin, row_end, cells);
        const std::uint32_t done = bands_done.fetch_add(1) + 1;
        if (worker == 0) progress.tick(done);  // the callback need not be thread-safe
      }
      with_value.fetch_add(count);
    } catch (...) {
      stop = true;
      throw;
    }
  };
  run_workers(std::min<unsigned>(threads, bands), work);
  progress.finish();
  stats.cells_with_value = with_value.load();
  return stats;
}

template RasterizeStats rasterize<float>(const mesh::Triangulation&, const Grid&, float,
                                         std::span<float>, const RasterizeOptions&);
template RasterizeStats rasterize<double>(const mesh::Triangulation&, const Grid&, double,
                                          std::span<double>, const RasterizeOptions&);

}  // namespace tincdt::products
