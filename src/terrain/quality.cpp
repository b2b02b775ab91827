#include "terrain/quality.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>

namespace tincdt::terrain {

namespace {

constexpr int kBinsPerDecade = 4;

// Bin edge k of the length grid: 10^(k / 4).
double grid_edge(int k) {
  return std::pow(10.0, static_cast<double>(k) / kBinsPerDecade);
}
int grid_index(double length) {
  return static_cast<int>(std::floor(kBinsPerDecade * std::log10(length)));
}

void put_number(std::string& out, double v) {
  if (!std::isfinite(v)) {
    out += "null";
    return;
  }
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);  // shortest round-trip form
  out.append(buf, r.ptr);
}
void put_number(std::string& out, std::uint64_t v) {
  out += std::to_string(v);
}
template <class T>
void put_field(std::string& out, const char* key, T v) {
  if (out.size() > 1) out += ',';
  out += '"';
  out += key;
  out += "\":";
  put_number(out, v);
}
template <class Range>
void put_array(std::string& out, const char* key, const Range& values) {
  if (out.size() > 1) out += ',';
  out += '"';
  out += key;
  out += "\":[";
  bool first = true;
  for (const auto& v : values) {
    if (!first) out += ',';
    first = false;
    put_number(out, v);
  }
  out += ']';
}

}  // namespace

QualityReport measure_quality(const mesh::Triangulation& tin,
                              const std::vector<std::uint8_t>* on_contour) {
  QualityReport q;
  q.flats_need_contours = on_contour != nullptr;
  std::vector<std::uint8_t> used(tin.vertex_count(), 0);
  // Edge lengths are counted as they come (tens of millions of edges: no list of them), on the
  // fixed grid 10^(k/4); bin k's edges are tabled once for the whole double range.
  constexpr int kLowest = -1300, kHighest = 1300;
  static const std::vector<double> bin_edge = [] {
    std::vector<double> edges;
    for (int k = kLowest; k <= kHighest + 1; ++k) edges.push_back(grid_edge(k));
    return edges;
  }();
  std::vector<std::uint64_t> bins(static_cast<std::size_t>(kHighest - kLowest + 1), 0);
  double min_length = HUGE_VAL, max_length = 0, sum_length = 0;
  auto count_edge = [&](double l) {
    ++q.edges;
    min_length = std::min(min_length, l);
    max_length = std::max(max_length, l);
    sum_length += l;
    // The log can put a length that equals a bin edge on either side of it: settle it with the
    // tabled edges, so the counts agree with the bins as printed.
    int k = std::clamp(grid_index(l), kLowest + 1, kHighest - 1);
    if (l < bin_edge[static_cast<std::size_t>(k - kLowest)]) --k;
    if (l >= bin_edge[static_cast<std::size_t>(k + 1 - kLowest)]) ++k;
    ++bins[static_cast<std::size_t>(k - kLowest)];
  };
  double min_angle = 180, max_angle = 0, max_ratio = 0;

  tin.for_each_triangle([&](TriangleId t, const std::array<VertexId, 3>& c) {
    ++q.triangles;
    Point3 p[3];
    for (int i = 0; i < 3; ++i) {
      used[c[i]] = 1;
      const Point2 xy = tin.point(c[i]);
      p[i] = {xy.x, xy.y, tin.z(c[i])};
    }
    double len[3];  // len[i]: edge i -> i + 1
    for (int i = 0; i < 3; ++i) {
      const Point3 a = p[i], b = p[(i + 1) % 3];
      len[i] = std::hypot(b.x - a.x, b.y - a.y);
      // Count an edge from the side with the smaller origin, or from its only kept side.
      const EdgeId e = 3 * t + static_cast<EdgeId>(i);
      if (c[i] < c[(i + 1) % 3] || !tin.is_kept(mesh::triangle_of(tin.twin(e)))) count_edge(len[i]);
    }
    // Areas from coordinate differences (large map coordinates stay exact enough).
    const double ux = p[1].x - p[0].x, uy = p[1].y - p[0].y, uz = p[1].z - p[0].z;
    const double vx = p[2].x - p[0].x, vy = p[2].y - p[0].y, vz = p[2].z - p[0].z;
    const double area2 = ux * vy - uy * vx;
    q.area_2d += 0.5 * area2;
    q.area_3d += 0.5 * std::sqrt((uy * vz - uz * vy) * (uy * vz - uz * vy) +
                                 (uz * vx - ux * vz) * (uz * vx - ux * vz) + area2 * area2);
    // Angle at corner i between the edges to the other two: atan2(|cross|, dot) is accurate for
    // angles near 0 and 180 where acos of a law-of-cosines ratio is not.
    double smallest = 180;
    for (int i = 0; i < 3; ++i) {
      const Point3 a = p[i], b = p[(i + 1) % 3], d = p[(i + 2) % 3];
      const double bx = b.x - a.x, by = b.y - a.y, dx = d.x - a.x, dy = d.y - a.y;
      const double deg =
          std::atan2(std::fabs(bx * dy - by * dx), bx * dx + by * dy) * 180 / std::numbers::pi;
      smallest = std::min(smallest, deg);
      max_angle = std::max(max_angle, deg);
      ++q.angle_histogram[std::min<std::size_t>(17, static_cast<std::size_t>(deg / 10))];
    }
    min_angle = std::min(min_angle, smallest);
    if (smallest < 20) ++q.triangles_below_20deg;
    // R / r = abc / (4A) / (2A / (a + b + c)) = abc (a + b + c) / (8 A^2), with 2A = area2.
    const double ratio =
        len[0] * len[1] * len[2] * (len[0] + len[1] + len[2]) / (2 * area2 * area2);
    max_ratio = std::max(max_ratio, ratio);
    if (is_flat(tin, c, on_contour)) ++q.flat_triangles;
  });

  for (std::uint8_t u : used) q.vertices += u;
  if (q.triangles) {
    q.min_angle_deg = min_angle;
    q.max_angle_deg = max_angle;
    q.max_radius_ratio = max_ratio;
  }
  if (q.edges) {
    q.min_edge_length = min_length;
    q.max_edge_length = max_length;
    q.mean_edge_length = sum_length / static_cast<double>(q.edges);
    std::size_t first = 0, last = bins.size() - 1;
    while (bins[first] == 0) ++first;
    while (bins[last] == 0) --last;
    for (std::size_t k = first; k <= last + 1; ++k) q.edge_length_bin_edges.push_back(bin_edge[k]);
    q.edge_length_histogram.assign(bins.begin() + static_cast<std::ptrdiff_t>(first),
                                   bins.begin() + static_cast<std::ptrdiff_t>(last) + 1);
  }
  return q;
}

std::string QualityReport::to_json() const {
  std::string out = "{";
  put_field(out, "triangles", triangles);
  put_field(out, "vertices", vertices);
  put_field(out, "area_2d", area_2d);
  put_field(out, "area_3d", area_3d);
  put_field(out, "min_angle_deg", min_angle_deg);
  put_field(out, "max_angle_deg", max_angle_deg);
  put_field(out, "angle_bin_width_deg", std::uint64_t{10});
  put_array(out, "angle_histogram", angle_histogram);
  put_field(out, "triangles_below_20deg", triangles_below_20deg);
  put_field(out, "max_circumradius_to_inradius", max_radius_ratio);
  put_field(out, "flat_triangles", flat_triangles);
  out += ",\"flat_rule\":";
  out += flats_need_contours ? "\"equal z, all corners on contours\"" : "\"equal z\"";
  put_field(out, "edges", edges);
  put_field(out, "min_edge_length", min_edge_length);
  put_field(out, "mean_edge_length", mean_edge_length);
  put_field(out, "max_edge_length", max_edge_length);
  put_array(out, "edge_length_bin_edges", edge_length_bin_edges);
  put_array(out, "edge_length_histogram", edge_length_histogram);
  out += '}';
  return out;
}

}  // namespace tincdt::terrain
