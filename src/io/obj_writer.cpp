// Wavefront OBJ: "v x y z" lines, then "f a b c" faces (1-based, counter-clockwise seen from
// above). Coordinates are written in their shortest round-trip form, so no bit is lost.
#include "io/writer_detail.hpp"

namespace tincdt::io::detail {

TinWriteStats write_obj(OutputFile& out, const mesh::Triangulation& tin,
                        const TinWriteOptions& options) {
  const std::string& path = out.path();
  const std::size_t nv = tin.vertex_count();
  const std::uint64_t nt = count_triangles(tin);

  std::string header =
      "# tincdt\n# vertices " + std::to_string(nv) + "\n# faces " + std::to_string(nt) + "\n";
  if (!is_zero(options.offset))
    header += "# offset " + format_point(options.offset) +
              " (subtracted from every vertex: add it back for the original coordinates)\n";

  BlockWriter w(out);
  w.put(header);
  for (std::size_t v = 0; v < nv; ++v) {
    const Point3 p = shifted_vertex(path, tin, static_cast<VertexId>(v), options.offset);
    w.put(std::string_view("v "));
    w.put_double(p.x);
    w.put(' ');
    w.put_double(p.y);
    w.put(' ');
    w.put_double(p.z);
    w.put('\n');
  }
  tin.for_each_triangle([&w](TriangleId, const std::array<VertexId, 3>& c) {
    w.put(std::string_view("f "));
    w.put_uint(std::uint64_t{c[0]} + 1);
    w.put(' ');
    w.put_uint(std::uint64_t{c[1]} + 1);
    w.put(' ');
    w.put_uint(std::uint64_t{c[2]} + 1);
    w.put('\n');
  });
  w.flush();
  return {nv, nt, 0};
}

}  // namespace tincdt::io::detail
