// For the quantized-mesh tests: a decoder written from the specification alone (none of the
// encoder's code), test meshes, and what a tile of a mesh must hold, worked out independently.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/terrain/quantized_mesh.hpp"
#include "support/splitmix.hpp"

namespace tincdt::test::terrain {

using io::terrain::GeoRectangle;
using io::terrain::TileMesh;

// ---- decoding -----------------------------------------------------------------------------

struct DecodedTile {
  std::array<double, 3> center{};
  float minimum_height = 0, maximum_height = 0;
  std::array<double, 3> sphere_center{};
  double sphere_radius = 0;
  std::array<double, 3> horizon_point{};
  std::vector<std::uint16_t> u, v, height;          // decoded (not the zig-zag deltas)
  std::size_t index_bytes = 0;                      // 2 or 4
  std::size_t triangles_offset = 0;                 // where triangleCount is in the file
  std::vector<std::uint32_t> indices;               // decoded (not the high-water-mark codes)
  std::array<std::vector<std::uint32_t>, 4> sides;  // west, south, east, north
  std::optional<std::vector<std::array<std::uint8_t, 2>>> normals;
  std::optional<std::string> metadata;
};

// Reads little-endian fields off a byte string, throwing at its end.
class Cursor {
 public:
  explicit Cursor(const std::string& bytes) : bytes_(bytes) {}
  std::uint64_t unsigned_le(int n) {
    if (pos_ + n > bytes_.size()) throw std::runtime_error("tile ends early");
    std::uint64_t v = 0;
    for (int i = n - 1; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(bytes_[pos_ + i]);
    pos_ += n;
    return v;
  }
  std::uint8_t u8() { return static_cast<std::uint8_t>(unsigned_le(1)); }
  std::uint16_t u16() { return static_cast<std::uint16_t>(unsigned_le(2)); }
  std::uint32_t u32() { return static_cast<std::uint32_t>(unsigned_le(4)); }
  double f64() { return std::bit_cast<double>(unsigned_le(8)); }
  float f32() { return std::bit_cast<float>(u32()); }
  std::string text(std::size_t n) {
    if (pos_ + n > bytes_.size()) throw std::runtime_error("tile ends early");
    pos_ += n;
    return bytes_.substr(pos_ - n, n);
  }
  std::size_t pos() const { return pos_; }
  bool at_end() const { return pos_ == bytes_.size(); }

 private:
  const std::string& bytes_;
  std::size_t pos_ = 0;
};

inline std::vector<std::uint16_t> read_zig_zag(Cursor& c, std::uint32_t n) {
  std::vector<std::uint16_t> out(n);
  int value = 0;
  for (auto& o : out) {
    const int code = c.u16();
    value += (code & 1) ? -((code + 1) / 2) : code / 2;
    o = static_cast<std::uint16_t>(value);
  }
  return out;
}

// Everything the tile holds. Throws std::runtime_error when the bytes do not parse, or padding
// is not zero.
inline DecodedTile decode_tile(const std::string& bytes) {
  Cursor c(bytes);
  DecodedTile t;
  for (double& d : t.center) d = c.f64();
  t.minimum_height = c.f32();
  t.maximum_height = c.f32();
  for (double& d : t.sphere_center) d = c.f64();
  t.sphere_radius = c.f64();
  for (double& d : t.horizon_point) d = c.f64();
  const std::uint32_t n = c.u32();
  t.u = read_zig_zag(c, n);
  t.v = read_zig_zag(c, n);
  t.height = read_zig_zag(c, n);
  t.index_bytes = n > 65536 ? 4 : 2;
  while (c.pos() % t.index_bytes != 0) {
    if (c.u8() != 0) throw std::runtime_error("padding is not zero");
  }
  t.triangles_offset = c.pos();
  const std::uint32_t triangles = c.u32();
  std::uint32_t highest = 0;
  for (std::uint64_t i = 0; i < 3ull * triangles; ++i) {
    const auto code = static_cast<std::uint32_t>(c.unsigned_le(static_cast<int>(t.index_bytes)));
    t.indices.push_back(highest - code);
    if (code == 0) ++highest;
  }
  for (auto& side : t.sides) {
    const std::uint32_t count = c.u32();
    for (std::uint32_t i = 0; i < count; ++i)
      side.push_back(static_cast<std::uint32_t>(c.unsigned_le(static_cast<int>(t.index_bytes))));
  }
  while (!c.at_end()) {
    const std::uint8_t id = c.u8();
    const std::uint32_t length = c.u32();
    const std::string data = c.text(length);
    if (id == 1) {
      if (length != 2ull * n) throw std::runtime_error("normals of the wrong size");
      t.normals.emplace();
      for (std::uint32_t i = 0; i < n; ++i)
        t.normals->push_back(
            {static_cast<std::uint8_t>(data[2 * i]), static_cast<std::uint8_t>(data[2 * i + 1])});
    } else if (id == 4) {
      Cursor m(data);
      const std::uint32_t json_length = m.u32();
      t.metadata = m.text(json_length);
      if (!m.at_end()) throw std::runtime_error("metadata longer than its JSON");
    } else {
      throw std::runtime_error("unknown extension " + std::to_string(id));
    }
  }
  return t;
}

// ---- geometry, from the definitions ---------------------------------------------------------

using Vec3 = std::array<double, 3>;

inline Vec3 sub(const Vec3& a, const Vec3& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
inline double dot3(const Vec3& a, const Vec3& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
inline Vec3 cross3(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double norm3(const Vec3& a) {
  return std::sqrt(dot3(a, a));
}

constexpr double kA = 6378137.0;
constexpr double kB = 6356752.314245179;  // WGS 84 semi-minor axis

// Geodetic to ECEF the way Cesium's Ellipsoid does it: from the surface normal n, the point
// (radii^2 * n) / sqrt(n . radii^2 * n) on the ellipsoid, plus the height along n.
inline Vec3 ecef(double lon_deg, double lat_deg, double h) {
  const double lon = lon_deg * std::numbers::pi / 180, lat = lat_deg * std::numbers::pi / 180;
  const Vec3 n{std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat)};
  const Vec3 k{kA * kA * n[0], kA * kA * n[1], kB * kB * n[2]};
  const double gamma = std::sqrt(dot3(n, k));
  return {k[0] / gamma + n[0] * h, k[1] / gamma + n[1] * h, k[2] / gamma + n[2] * h};
}

inline Vec3 scaled(const Vec3& p) {
  return {p[0] / kA, p[1] / kA, p[2] / kB};
}

// Cesium's horizon test (EllipsoidalOccluder.isScaledSpacePointVisible) for scaled-space
// POINT seen from scaled-space CAMERA.
inline bool hidden_by_horizon(const Vec3& point, const Vec3& camera) {
  const double vh2 = dot3(camera, camera) - 1.0;
  const Vec3 vt = sub(point, camera);
  const double vt_dot_vc = -dot3(vt, camera);
  return vh2 < 0 ? vt_dot_vc > 0 : vt_dot_vc > vh2 && vt_dot_vc * vt_dot_vc / dot3(vt, vt) > vh2;
}

// The unit vector of oct-encoded BYTES (Cigolle et al. 2014).
inline Vec3 oct_decode(const std::array<std::uint8_t, 2>& bytes) {
  double x = bytes[0] / 255.0 * 2 - 1, y = bytes[1] / 255.0 * 2 - 1;
  const double z = 1 - std::fabs(x) - std::fabs(y);
  if (z < 0) {
    const double old_x = x;
    x = (1 - std::fabs(y)) * (old_x < 0 ? -1 : 1);
    y = (1 - std::fabs(old_x)) * (y < 0 ? -1 : 1);
  }
  const Vec3 n{x, y, z};
  const double l = norm3(n);
  return {n[0] / l, n[1] / l, n[2] / l};
}

// ---- what a tile of a mesh must hold --------------------------------------------------------

// X on the spec's linear scale 0..32767 from LOW to HIGH, to the nearest step.
inline std::uint16_t quantized(double x, double low, double high) {
  return static_cast<std::uint16_t>(std::lround((x - low) / (high - low) * 32767.0));
}

// Vertex I of M quantized as u, v, height, on a tile whose heights run from LOW to HIGH.
inline std::array<std::uint16_t, 3> quantized_vertex(const TileMesh& m, std::uint32_t i, double low,
                                                     double high) {
  const Point3& p = m.vertices[i];
  const GeoRectangle& r = m.rectangle;
  return {quantized(p.x, r.west, r.east), quantized(p.y, r.south, r.north),
          low < high ? quantized(p.z, low, high) : std::uint16_t{0}};
}

// The vertices in the order the high-water-mark code forces: first use, then the unused ones.
inline std::vector<std::uint32_t> first_use(const TileMesh& m) {
  std::vector<std::uint32_t> order;
  std::vector<char> seen(m.vertices.size(), 0);
  for (const auto& t : m.triangles) {
    for (const auto c : t) {
      if (!seen[c]) order.push_back(c), seen[c] = 1;
    }
  }
  for (std::uint32_t i = 0; i < m.vertices.size(); ++i) {
    if (!seen[i]) order.push_back(i);
  }
  return order;
}

// The area-weighted normal of each vertex, in ECEF, from the unquantized vertices.
inline std::vector<Vec3> area_weighted_normals(const TileMesh& m) {
  std::vector<Vec3> p, sum(m.vertices.size(), Vec3{0, 0, 0});
  for (const auto& v : m.vertices) p.push_back(ecef(v.x, v.y, v.z));
  for (const auto& t : m.triangles) {
    const Vec3 f = cross3(sub(p[t[1]], p[t[0]]), sub(p[t[2]], p[t[0]]));
    for (const auto c : t) {
      for (int k = 0; k < 3; ++k) sum[c][k] += f[k];
    }
  }
  for (std::size_t i = 0; i < sum.size(); ++i) {
    const double l = norm3(sum[i]);
    if (l > 0) {
      sum[i] = {sum[i][0] / l, sum[i][1] / l, sum[i][2] / l};
    } else {  // no face with an area: the ellipsoid's normal
      const double lon = m.vertices[i].x * std::numbers::pi / 180;
      const double lat = m.vertices[i].y * std::numbers::pi / 180;
      sum[i] = {std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat)};
    }
  }
  return sum;
}

// ---- test meshes --------------------------------------------------------------------------

// A jittered grid of COLS x ROWS cells over RECT, two counter-clockwise triangles a cell, its
// outer vertices exactly on the sides, heights in [LOW, HIGH]; vertices and triangles shuffled
// when SHUFFLE (else row by row from the south-west), and EXTRA unused vertices appended.
inline TileMesh grid_mesh(std::uint64_t seed, const GeoRectangle& rect, int cols, int rows,
                          double low = -40, double high = 2500, int extra = 0,
                          bool shuffle = true) {
  SplitMix64 rng{seed};
  TileMesh m;
  m.rectangle = rect;
  const double dx = (rect.east - rect.west) / cols, dy = (rect.north - rect.south) / rows;
  auto height = [&] { return low + (high - low) * rng.unit(); };
  for (int j = 0; j <= rows; ++j) {
    for (int i = 0; i <= cols; ++i) {
      double x = i == cols ? rect.east : rect.west + i * dx;
      double y = j == rows ? rect.north : rect.south + j * dy;
      if (i > 0 && i < cols) x += (rng.unit() - 0.5) * 0.6 * dx;
      if (j > 0 && j < rows) y += (rng.unit() - 0.5) * 0.6 * dy;
      m.vertices.push_back({x, y, height()});
    }
  }
  const auto at = [&](int i, int j) { return static_cast<std::uint32_t>(j * (cols + 1) + i); };
  for (int j = 0; j < rows; ++j) {
    for (int i = 0; i < cols; ++i) {
      m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  // Shuffle (Fisher-Yates) the vertices, renumbering the corners, then the triangles, rotating
  // each one's corners.
  if (!shuffle) {
    for (int e = 0; e < extra; ++e)
      m.vertices.push_back({rect.west + (rect.east - rect.west) * rng.unit(),
                            rect.south + (rect.north - rect.south) * rng.unit(), height()});
    return m;
  }
  std::vector<std::uint32_t> to(m.vertices.size());
  for (std::uint32_t i = 0; i < to.size(); ++i) to[i] = i;
  for (std::size_t i = to.size(); i > 1; --i) std::swap(to[i - 1], to[rng.next() % i]);
  std::vector<Point3> moved(m.vertices.size());
  for (std::size_t i = 0; i < to.size(); ++i) moved[to[i]] = m.vertices[i];
  m.vertices = moved;
  for (auto& t : m.triangles) {
    for (auto& c : t) c = to[c];
    std::rotate(t.begin(), t.begin() + rng.next() % 3, t.end());
  }
  for (std::size_t i = m.triangles.size(); i > 1; --i)
    std::swap(m.triangles[i - 1], m.triangles[rng.next() % i]);
  for (int e = 0; e < extra; ++e)
    m.vertices.push_back({rect.west + (rect.east - rect.west) * rng.unit(),
                          rect.south + (rect.north - rect.south) * rng.unit(), height()});
  return m;
}

}  // namespace tincdt::test::terrain
