// Wavefront OBJ: "v x y z" lines, then "f a b c" faces (1-based, counter-clockwise seen from
// above). Coordinates are written in their shortest round-trip form, so no bit is lost. With
// removed triangles only the vertices of kept faces are written (VertexNumbering).
#include "io/mesh/writer_detail.hpp"

namespace tincdt::io::detail {

namespace {

// Rough bytes of a record, for the size of the blocks formatted apart.
constexpr std::size_t kVertexBytes = 62, kFaceBytes = 24;

// The faces of every triangle slot, in blocks on the writer's threads, under the vertices'
// written numbers or (not RENUMBER) their ids.
template <bool kRenumber>
void write_faces(BlockWriter& w, const mesh::Triangulation& tin, const VertexNumbering& number,
                 const TinWriteOptions& options, Progress& progress, std::uint64_t done) {
  const auto id = [&number](VertexId v) { return std::uint64_t{kRenumber ? number(v) : v} + 1; };
  write_blocks(w, options.threads, tin.triangle_slots(), kFaceBytes, progress, done,
               [&](BlockWriter& b, std::size_t begin, std::size_t end) {
                 for_each_triangle_in(tin, begin, end,
                                      [&](TriangleId, const std::array<VertexId, 3>& c) {
                                        b.put(std::string_view("f "));
                                        b.put_uint(id(c[0]));
                                        b.put(' ');
                                        b.put_uint(id(c[1]));
                                        b.put(' ');
                                        b.put_uint(id(c[2]));
                                        b.put('\n');
                                      });
               });
}

}  // namespace

TinWriteStats write_obj(OutputFile& out, const mesh::Triangulation& tin,
                        const TinWriteOptions& options) {
  const std::string& path = out.path();
  const WrittenTin written(tin, options.threads);
  const VertexNumbering& number = written.number;
  const std::size_t nv = number.count();

  std::string header = "# tincdt\n# vertices " + std::to_string(nv) + "\n# faces " +
                       std::to_string(written.triangles) + "\n";
  if (!is_zero(options.offset))
    header += "# offset " + format_point(options.offset) +
              " (subtracted from every vertex: add it back for the original coordinates)\n";

  BlockWriter w(out);
  Progress progress(options.progress, "write", nv + tin.triangle_slots());
  w.put(header);
  write_blocks(w, options.threads, nv, kVertexBytes, progress, 0,
               [&](BlockWriter& b, std::size_t begin, std::size_t end) {
                 for (std::size_t i = begin; i < end; ++i) {
                   const Point3 p = shifted_vertex(path, tin, number.vertex(i), options.offset);
                   b.put(std::string_view("v "));
                   b.put_xyz(p, ' ');
                   b.put('\n');
                 }
               });
  if (number.compacted())
    write_faces<true>(w, tin, number, options, progress, nv);
  else
    write_faces<false>(w, tin, number, options, progress, nv);
  w.flush();
  progress.finish();
  return {nv, written.triangles, 0};
}

}  // namespace tincdt::io::detail
