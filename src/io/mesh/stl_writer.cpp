// Binary STL: an 80-byte header, the triangle count, then per triangle its unit normal and three
// corners as little-endian float32 and a zero attribute word; counter-clockwise seen from above,
// so every normal points up. STL has float32 only: at map coordinates (500000 m) a float is
// 3 cm coarse, so the coordinates should be shifted by an offset; stl_precision_warning() says so
// when the rounding would exceed 1 mm.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "io/crs.hpp"
#include "io/mesh/writer_detail.hpp"

namespace tincdt::io {
namespace {

// Largest rounding error allowed silently: 1 mm in metres (1/300 foot in feet).
constexpr double kQuietRounding = 1e-3;

}  // namespace

std::string stl_precision_warning(const mesh::Triangulation& tin, const Point3& offset) {
  double largest = 0;  // largest |coordinate| written
  tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& c) {
    for (const VertexId v : c) {
      const Point2 p = tin.point(v);
      largest = std::max({largest, std::fabs(p.x - offset.x), std::fabs(p.y - offset.y),
                          std::fabs(tin.z(v) - offset.z)});
    }
  });
  // Half the spacing of floats at that magnitude.
  const double rounding = std::ldexp(largest, -24);
  if (!(rounding > kQuietRounding)) return {};
  char text[200];
  std::snprintf(text, sizeof text,
                "STL stores float32: coordinates up to %.0f are rounded by up to %.3g", largest,
                rounding);
  return text;
}

namespace detail {
namespace {

constexpr std::size_t kFacetBytes = 50;

// One facet: its unit normal, its corners shifted by OFFSET, a zero attribute word.
void put_facet(BlockWriter& w, const std::string& path, const mesh::Triangulation& tin,
               const std::array<VertexId, 3>& c, const Point3& offset) {
  Point3 p[3];
  for (int i = 0; i < 3; ++i) p[i] = shifted_vertex(path, tin, c[i], offset);
  const double ux = p[1].x - p[0].x, uy = p[1].y - p[0].y, uz = p[1].z - p[0].z;
  const double vx = p[2].x - p[0].x, vy = p[2].y - p[0].y, vz = p[2].z - p[0].z;
  double nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
  const double norm = std::sqrt(nx * nx + ny * ny + nz * nz);
  if (norm > 0) {
    nx /= norm;
    ny /= norm;
    nz /= norm;
  }
  w.put_le(static_cast<float>(nx));
  w.put_le(static_cast<float>(ny));
  w.put_le(static_cast<float>(nz));
  for (const Point3& q : p) {
    w.put_le(static_cast<float>(q.x));
    w.put_le(static_cast<float>(q.y));
    w.put_le(static_cast<float>(q.z));
  }
  w.put_le(std::uint16_t{0});
}

}  // namespace

TinWriteStats write_stl(OutputFile& out, const mesh::Triangulation& tin,
                        const TinWriteOptions& options) {
  const std::string& path = out.path();
  const TriangleCounts counts = count_triangles(tin, options.threads);
  if (counts.kept > std::numeric_limits<std::uint32_t>::max())
    throw OutputError(path, "", "more than 2^32 - 1 triangles do not fit in an STL file");

  // The header must not start with "solid", which some readers take for the text format.
  std::string header = "tincdt binary STL";
  if (!is_zero(options.offset)) header += "; offset " + format_point(options.offset);
  if (!options.crs_wkt.empty()) {
    const std::string crs = crs_code(options.crs_wkt);
    if (!crs.empty()) header += "; crs " + crs;
  }
  header.resize(80, ' ');

  BlockWriter w(out);
  Progress progress(options.progress, "write", tin.triangle_slots());
  w.put(header);
  w.put_le(static_cast<std::uint32_t>(counts.kept));
  write_blocks(w, options.threads, tin.triangle_slots(), kFacetBytes, progress, 0,
               [&](BlockWriter& b, std::size_t begin, std::size_t end) {
                 for_each_triangle_in(tin, begin, end,
                                      [&](TriangleId, const std::array<VertexId, 3>& c) {
                                        put_facet(b, path, tin, c, options.offset);
                                      });
               });
  w.flush();
  progress.finish();

  const VertexNumbering number(tin, counts.removed > 0);  // only to count the vertices used
  return {number.count(), counts.kept, 0};
}

}  // namespace detail
}  // namespace tincdt::io
