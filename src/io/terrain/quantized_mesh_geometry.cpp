// The geometry of a quantized-mesh tile: quantization, the header's centre, sphere and horizon
// occlusion point, and the vertex normals.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "io/terrain/quantized_mesh.hpp"
#include "io/terrain/quantized_mesh_detail.hpp"
#include "io/terrain/wgs84.hpp"

namespace tincdt::io::terrain {
namespace detail {

using wgs84::cross;
using wgs84::dot;
using wgs84::length;
using wgs84::operator+;
using wgs84::operator-;
using wgs84::operator*;

namespace {

// The magnitude given to a horizon occlusion point no finite point can be (a tile spanning a
// hemisphere, as at level 0): far enough that the point hides only from a camera within the
// ellipsoid's shadow cylinder behind it, which is where such a tile hides too.
constexpr double kUnboundedHorizonMagnitude = 1e6;

// The nearest floats at most and at least V.
float float_at_most(double v) {
  float f = static_cast<float>(v);
  if (static_cast<double>(f) > v) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}
float float_at_least(double v) {
  float f = static_cast<float>(v);
  if (static_cast<double>(f) < v) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

// V on the scale 0..kQuantizedMax from LOW to HIGH (LOW < HIGH), rounded to nearest. Exact at
// the ends: (high - low) / (high - low) is 1 and (low - low) is 0.
std::uint16_t quantize(double v, double low, double high) {
  const double q = std::round((v - low) / (high - low) * kQuantizedMax);
  return static_cast<std::uint16_t>(std::clamp(q, 0.0, static_cast<double>(kQuantizedMax)));
}

// Where a reader puts quantized Q of the scale LOW..HIGH.
double dequantize(std::uint16_t q, double low, double high) {
  return std::lerp(low, high, static_cast<double>(q) / kQuantizedMax);
}

// The ECEF position a reader gives vertex I.
Point3 decoded_position(const TileMesh& mesh, const QuantizedVertices& q, std::size_t i) {
  const GeoRectangle& r = mesh.rectangle;
  return wgs84::to_ecef(dequantize(q.u[i], r.west, r.east), dequantize(q.v[i], r.south, r.north),
                        dequantize(q.height[i], q.minimum_height, q.maximum_height));
}

double farthest(const std::vector<Point3>& points, const Point3& center) {
  double radius = 0;
  for (const Point3& p : points) radius = std::max(radius, length(p - center));
  return radius;
}

// The smaller of two spheres holding POINTS: about the middle of their bounding box, or about
// CENTER.
void bounding_sphere(const std::vector<Point3>& points, const Point3& center,
                     QuantizedMeshHeader& header) {
  Point3 low = points.front(), high = points.front();
  for (const Point3& p : points) {
    low = {std::min(low.x, p.x), std::min(low.y, p.y), std::min(low.z, p.z)};
    high = {std::max(high.x, p.x), std::max(high.y, p.y), std::max(high.z, p.z)};
  }
  const Point3 middle = (low + high) * 0.5;
  const double about_middle = farthest(points, middle);
  const double about_center = farthest(points, center);
  header.bounding_sphere_center = about_middle <= about_center ? middle : center;
  header.bounding_sphere_radius = std::min(about_middle, about_center);
}

// How far along the unit DIRECTION (scaled space) the horizon occlusion point must be for
// scaled-space POSITION to hide behind the horizon whenever the point does: the distance at
// which the ray meets the plane tangent to the horizon cone of POSITION. Points below the
// ellipsoid count as on it. Not positive (or not finite) when no point of the ray will do.
double horizon_magnitude(const Point3& position, const Point3& direction) {
  double magnitude_squared = dot(position, position);
  double magnitude = std::sqrt(magnitude_squared);
  const Point3 towards = position * (1.0 / magnitude);
  magnitude_squared = std::max(1.0, magnitude_squared);
  magnitude = std::max(1.0, magnitude);
  const double cos_alpha = dot(towards, direction);
  const double sin_alpha = length(cross(towards, direction));
  const double cos_beta = 1.0 / magnitude;
  const double sin_beta = std::sqrt(magnitude_squared - 1.0) * cos_beta;
  return 1.0 / (cos_alpha * cos_beta - sin_alpha * sin_beta);
}

// The horizon occlusion point of POINTS (ECEF), on the ray from the earth's centre through
// CENTER, in scaled space: if it is below a camera's horizon, so is every point.
Point3 horizon_occlusion_point(const std::vector<Point3>& points, const Point3& center) {
  const Point3 scaled_center = wgs84::to_scaled_space(center);
  const Point3 direction = scaled_center * (1.0 / length(scaled_center));
  double magnitude = 0;
  for (const Point3& p : points) {
    const double m = horizon_magnitude(wgs84::to_scaled_space(p), direction);
    if (!(m > 0) || !std::isfinite(m)) return direction * kUnboundedHorizonMagnitude;
    magnitude = std::max(magnitude, m);
  }
  return direction * magnitude;
}

// Oct encoding (Cigolle et al., "A Survey of Efficient Representations of Independent Unit
// Vectors", JCGT 2014): the unit vector projected on the octahedron |x| + |y| + |z| = 1, whose
// lower half folds over the upper, then x and y in -1..1 as 0..255.
std::array<std::uint8_t, 2> oct_encode(const Point3& n) {
  const double l1 = std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z);
  double x = n.x / l1, y = n.y / l1;
  if (n.z < 0) {
    const double folded_x = (1.0 - std::fabs(y)) * (x < 0 ? -1.0 : 1.0);
    const double folded_y = (1.0 - std::fabs(x)) * (y < 0 ? -1.0 : 1.0);
    x = folded_x;
    y = folded_y;
  }
  const auto to_byte = [](double s) {
    return static_cast<std::uint8_t>(std::round((std::clamp(s, -1.0, 1.0) * 0.5 + 0.5) * 255.0));
  };
  return {to_byte(x), to_byte(y)};
}

[[noreturn]] void refuse(const std::string& what) {
  throw InternalError("quantized-mesh tile: " + what);
}

}  // namespace

void check_tile_mesh(const TileMesh& mesh) {
  const GeoRectangle& r = mesh.rectangle;
  if (!(r.west < r.east && r.south < r.north && r.west >= -180 && r.east <= 180 && r.south >= -90 &&
        r.north <= 90))
    refuse("the rectangle is not a tile's");
  if (mesh.vertices.empty()) refuse("no vertices");
  if (mesh.vertices.size() > std::numeric_limits<std::uint32_t>::max() ||
      mesh.triangles.size() > std::numeric_limits<std::uint32_t>::max() / 3)
    refuse("too many vertices or triangles for 32-bit counts");
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Point3& p = mesh.vertices[i];
    if (!(p.x >= r.west && p.x <= r.east && p.y >= r.south && p.y <= r.north) ||
        !std::isfinite(p.z))
      refuse("vertex " + count_text(i) + " is outside the tile or not finite");
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (const std::uint32_t c : mesh.triangles[t]) {
      if (c >= mesh.vertices.size())
        refuse("triangle " + count_text(t) + " has no vertex " + count_text(c));
    }
  }
}

QuantizedVertices quantize_vertices(const TileMesh& mesh) {
  const GeoRectangle& r = mesh.rectangle;
  const auto [lowest, highest] =
      std::minmax_element(mesh.vertices.begin(), mesh.vertices.end(),
                          [](const Point3& a, const Point3& b) { return a.z < b.z; });
  QuantizedVertices q;
  q.minimum_height = float_at_most(lowest->z);
  q.maximum_height = float_at_least(highest->z);
  const std::size_t n = mesh.vertices.size();
  q.u.resize(n);
  q.v.resize(n);
  q.height.assign(n, 0);  // all 0 on a flat tile
  for (std::size_t i = 0; i < n; ++i) {
    const Point3& p = mesh.vertices[i];
    q.u[i] = quantize(p.x, r.west, r.east);
    q.v[i] = quantize(p.y, r.south, r.north);
    if (q.minimum_height < q.maximum_height)
      q.height[i] = quantize(p.z, q.minimum_height, q.maximum_height);
  }
  return q;
}

QuantizedMeshHeader header_of(const TileMesh& mesh, const QuantizedVertices& quantized) {
  const GeoRectangle& r = mesh.rectangle;
  QuantizedMeshHeader header{};
  header.minimum_height = quantized.minimum_height;
  header.maximum_height = quantized.maximum_height;
  header.center = wgs84::to_ecef(
      (r.west + r.east) / 2, (r.south + r.north) / 2,
      (static_cast<double>(quantized.minimum_height) + quantized.maximum_height) / 2);
  std::vector<Point3> positions(mesh.vertices.size());
  for (std::size_t i = 0; i < positions.size(); ++i)
    positions[i] = decoded_position(mesh, quantized, i);
  bounding_sphere(positions, header.center, header);
  header.horizon_occlusion_point = horizon_occlusion_point(positions, header.center);
  return header;
}

std::vector<std::array<std::uint8_t, 2>> oct_vertex_normals(const TileMesh& mesh) {
  std::vector<Point3> ecef(mesh.vertices.size());
  for (std::size_t i = 0; i < ecef.size(); ++i) {
    const Point3& p = mesh.vertices[i];
    ecef[i] = wgs84::to_ecef(p.x, p.y, p.z);
  }
  // The cross product of two sides is the face normal times twice the area: summed, each
  // vertex gets its faces' normals weighted by their areas.
  std::vector<Point3> sum(ecef.size(), Point3{0, 0, 0});
  for (const auto& t : mesh.triangles) {
    const Point3 face = cross(ecef[t[1]] - ecef[t[0]], ecef[t[2]] - ecef[t[0]]);
    for (const std::uint32_t c : t) sum[c] = sum[c] + face;
  }
  std::vector<std::array<std::uint8_t, 2>> normals(ecef.size());
  for (std::size_t i = 0; i < ecef.size(); ++i) {
    const double l = length(sum[i]);
    // A vertex of no triangle, or only of triangles of no area, faces straight up.
    const Point3 n = l > 0 && std::isfinite(l)
                         ? sum[i] * (1.0 / l)
                         : wgs84::surface_normal(mesh.vertices[i].x, mesh.vertices[i].y);
    normals[i] = oct_encode(n);
  }
  return normals;
}

}  // namespace detail
}  // namespace tincdt::io::terrain
