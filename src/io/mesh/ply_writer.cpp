// Stanford PLY, binary little-endian (default) or ASCII: double x/y/z vertices, uint triangle
// lists and, when the mesh has constrained edges, an `edge` element with their two vertices.
// With removed triangles only the vertices of kept faces are written (VertexNumbering), and only
// the constrained edges with a kept face on a side.
#include "io/gdal_support.hpp"
#include "io/mesh/writer_detail.hpp"

namespace tincdt::io::detail {
namespace {

std::string ply_header(bool ascii, std::size_t nv, std::uint64_t nt, std::uint64_t ne,
                       const TinWriteOptions& options) {
  std::string h = "ply\nformat ";
  h += ascii ? "ascii" : "binary_little_endian";
  h += " 1.0\ncomment tincdt\n";
  // The offset was subtracted from every vertex: add it back for the original coordinates.
  if (!is_zero(options.offset)) h += "comment offset " + format_point(options.offset) + "\n";
  if (!options.crs_wkt.empty()) {
    std::string crs = crs_code(options.crs_wkt);
    if (crs.empty()) crs = one_line(options.crs_wkt);
    h += "comment crs " + crs + "\n";
  }
  h += "element vertex " + std::to_string(nv) +
       "\nproperty double x\nproperty double y\nproperty double z\n";
  h += "element face " + std::to_string(nt) + "\nproperty list uchar uint vertex_indices\n";
  if (ne > 0)
    h += "element edge " + std::to_string(ne) + "\nproperty uint vertex1\nproperty uint vertex2\n";
  h += "end_header\n";
  return h;
}

}  // namespace

TinWriteStats write_ply(OutputFile& out, const mesh::Triangulation& tin,
                        const TinWriteOptions& options) {
  const std::string& path = out.path();
  const bool ascii = options.ply_ascii;
  const TriangleCounts counts = count_triangles(tin);
  const std::uint64_t nt = counts.kept;
  // With removed triangles: only the vertices of kept faces, renumbered, and only the constrained
  // edges with a kept face on a side.
  const bool compact = counts.removed > 0;
  const VertexNumbering number(tin, compact);
  const std::size_t nv = number.count();
  const std::uint64_t ne = count_constrained_segments(tin, compact);

  BlockWriter w(out);
  Progress progress(options.progress, "write", nv + nt);
  std::uint64_t done = 0;
  w.put(ply_header(ascii, nv, nt, ne, options));

  for (std::size_t i = 0; i < nv; ++i) {
    progress.tick(done++);
    const Point3 p = shifted_vertex(path, tin, number.vertex(i), options.offset);
    if (ascii) {
      w.put_xyz(p, ' ');
      w.put('\n');
    } else {
      w.put_le(p.x);
      w.put_le(p.y);
      w.put_le(p.z);
    }
  }

  if (ascii) {
    tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& c) {
      progress.tick(done++);
      w.put(std::string_view("3 "));
      w.put_uint(number(c[0]));
      w.put(' ');
      w.put_uint(number(c[1]));
      w.put(' ');
      w.put_uint(number(c[2]));
      w.put('\n');
    });
    for_each_constrained_segment(tin, compact, [&w, &number](VertexId a, VertexId b) {
      w.put_uint(number(a));
      w.put(' ');
      w.put_uint(number(b));
      w.put('\n');
    });
  } else if (number.compacted()) {
    tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& c) {
      progress.tick(done++);
      w.put_le(std::uint8_t{3});
      w.put_le(number(c[0]));
      w.put_le(number(c[1]));
      w.put_le(number(c[2]));
    });
    for_each_constrained_segment(tin, true, [&w, &number](VertexId a, VertexId b) {
      w.put_le(number(a));
      w.put_le(number(b));
    });
  } else {
    tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& c) {
      progress.tick(done++);
      w.put_le(std::uint8_t{3});
      w.put_le(c[0]);
      w.put_le(c[1]);
      w.put_le(c[2]);
    });
    for_each_constrained_segment(tin, false, [&w](VertexId a, VertexId b) {
      w.put_le(a);
      w.put_le(b);
    });
  }
  w.flush();
  progress.finish();
  return {nv, nt, 0};
}

}  // namespace tincdt::io::detail
