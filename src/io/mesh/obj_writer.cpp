// Wavefront OBJ: "v x y z" lines, then "f a b c" faces (1-based, counter-clockwise seen from
// above). Coordinates are written in their shortest round-trip form, so no bit is lost. With
// removed triangles only the vertices of kept faces are written (VertexNumbering).
#include "io/mesh/writer_detail.hpp"

namespace tincdt::io::detail {

TinWriteStats write_obj(OutputFile& out, const mesh::Triangulation& tin,
                        const TinWriteOptions& options) {
  const std::string& path = out.path();
  const TriangleCounts counts = count_triangles(tin);
  const std::uint64_t nt = counts.kept;
  const VertexNumbering number(tin, counts.removed > 0);
  const std::size_t nv = number.count();

  std::string header =
      "# tincdt\n# vertices " + std::to_string(nv) + "\n# faces " + std::to_string(nt) + "\n";
  if (!is_zero(options.offset))
    header += "# offset " + format_point(options.offset) +
              " (subtracted from every vertex: add it back for the original coordinates)\n";

  BlockWriter w(out);
  Progress progress(options.progress, "write", nv + nt);
  std::uint64_t done = 0;
  w.put(header);
  for (std::size_t i = 0; i < nv; ++i) {
    progress.tick(done++);
    const Point3 p = shifted_vertex(path, tin, number.vertex(i), options.offset);
    w.put(std::string_view("v "));
    w.put_xyz(p, ' ');
    w.put('\n');
  }
  const auto face = [&](VertexId a, VertexId b, VertexId c) {
    progress.tick(done++);
    w.put(std::string_view("f "));
    w.put_uint(std::uint64_t{a} + 1);
    w.put(' ');
    w.put_uint(std::uint64_t{b} + 1);
    w.put(' ');
    w.put_uint(std::uint64_t{c} + 1);
    w.put('\n');
  };
  if (number.compacted()) {
    tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& c) {
      face(number(c[0]), number(c[1]), number(c[2]));
    });
  } else {
    tin.for_each_triangle(
        [&](TriangleId, const std::array<VertexId, 3>& c) { face(c[0], c[1], c[2]); });
  }
  w.flush();
  progress.finish();
  return {nv, nt, 0};
}

}  // namespace tincdt::io::detail
