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
  if (!options.ply_trimmed.empty()) h += "comment trimmed " + options.ply_trimmed + "\n";
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

// Rough bytes of a record, for the size of the blocks formatted apart.
constexpr std::size_t kBinaryVertexBytes = 24, kAsciiVertexBytes = 60;
constexpr std::size_t kBinaryFaceBytes = 13, kAsciiFaceBytes = 24;

void put_ascii_face(BlockWriter& w, VertexId a, VertexId b, VertexId c) {
  w.put(std::string_view("3 "));
  w.put_uint(a);
  w.put(' ');
  w.put_uint(b);
  w.put(' ');
  w.put_uint(c);
  w.put('\n');
}

void put_binary_face(BlockWriter& w, VertexId a, VertexId b, VertexId c) {
  w.put_le(std::uint8_t{3});
  w.put_le(a);
  w.put_le(b);
  w.put_le(c);
}

// The faces of every triangle slot, in blocks on the writer's threads: text or binary, under the
// vertices' written numbers or (not RENUMBER) their ids.
template <bool kAscii, bool kRenumber>
void write_faces(BlockWriter& w, const mesh::Triangulation& tin, const VertexNumbering& number,
                 const TinWriteOptions& options, Progress& progress, std::uint64_t done) {
  const auto id = [&number](VertexId v) { return kRenumber ? number(v) : v; };
  write_blocks(
      w, options.threads, tin.triangle_slots(), kAscii ? kAsciiFaceBytes : kBinaryFaceBytes,
      progress, done, [&](BlockWriter& b, std::size_t begin, std::size_t end) {
        for_each_triangle_in(tin, begin, end, [&](TriangleId, const std::array<VertexId, 3>& c) {
          if constexpr (kAscii)
            put_ascii_face(b, id(c[0]), id(c[1]), id(c[2]));
          else
            put_binary_face(b, id(c[0]), id(c[1]), id(c[2]));
        });
      });
}

// Rough bytes per half-edge of the `edge` element's blocks: most half-edges are not constrained.
constexpr std::size_t kHalfEdgeBytes = 4;

template <bool kAscii>
void put_edge(BlockWriter& w, VertexId a, VertexId b) {
  if constexpr (kAscii) {
    w.put_uint(a);
    w.put(' ');
    w.put_uint(b);
    w.put('\n');
  } else {
    w.put_le(a);
    w.put_le(b);
  }
}

// The `edge` element: the written TIN's constrained segments under the vertices' written numbers,
// in blocks of half-edges on the writer's threads. Its NE records take the writer's progress from
// DONE of TOTAL records on; polled between blocks as the faces are, so that a request to stop
// gets through.
template <bool kAscii>
void write_edges(BlockWriter& w, const mesh::Triangulation& tin, const WrittenTin& written,
                 const TinWriteOptions& options, std::uint64_t done, std::uint64_t ne,
                 std::uint64_t total) {
  if (!tin.has_constraints()) return;
  const VertexNumbering& number = written.number;
  const std::size_t half_edges = 3 * tin.triangle_slots();
  // The blocks count half-edges; the writer's progress counts the records they hold.
  const ProgressFn* writer = options.progress;
  const ProgressFn share = [&](std::string_view stage, double fraction) {
    return (*writer)(stage, (static_cast<double>(done) + fraction * static_cast<double>(ne)) /
                                static_cast<double>(total));
  };
  Progress progress(writer != nullptr && *writer ? &share : nullptr, "write", half_edges);
  write_blocks(w, options.threads, half_edges, kHalfEdgeBytes, progress, 0,
               [&](BlockWriter& b, std::size_t begin, std::size_t end) {
                 for_each_constrained_segment_in(tin, written.compact, begin, end,
                                                 [&](VertexId v1, VertexId v2) {
                                                   put_edge<kAscii>(b, number(v1), number(v2));
                                                 });
               });
}

}  // namespace

TinWriteStats write_ply(OutputFile& out, const mesh::Triangulation& tin,
                        const TinWriteOptions& options) {
  const std::string& path = out.path();
  const bool ascii = options.ply_ascii;
  // With removed triangles: only the vertices of kept faces, renumbered, and only the constrained
  // edges with a kept face on a side.
  const WrittenTin written(tin, options.threads);
  const VertexNumbering& number = written.number;
  const std::size_t nv = number.count();
  const std::uint64_t ne = count_constrained_segments(tin, written.compact, options.threads);

  BlockWriter w(out);
  const std::uint64_t total = nv + tin.triangle_slots() + ne;
  Progress progress(options.progress, "write", total);
  w.put(ply_header(ascii, nv, written.triangles, ne, options));

  write_blocks(w, options.threads, nv, ascii ? kAsciiVertexBytes : kBinaryVertexBytes, progress, 0,
               [&](BlockWriter& b, std::size_t begin, std::size_t end) {
                 for (std::size_t i = begin; i < end; ++i) {
                   const Point3 p = shifted_vertex(path, tin, number.vertex(i), options.offset);
                   if (ascii) {
                     b.put_xyz(p, ' ');
                     b.put('\n');
                   } else {
                     b.put_le(p.x);
                     b.put_le(p.y);
                     b.put_le(p.z);
                   }
                 }
               });
  if (ascii && number.compacted())
    write_faces<true, true>(w, tin, number, options, progress, nv);
  else if (ascii)
    write_faces<true, false>(w, tin, number, options, progress, nv);
  else if (number.compacted())
    write_faces<false, true>(w, tin, number, options, progress, nv);
  else
    write_faces<false, false>(w, tin, number, options, progress, nv);

  const std::uint64_t faces_done = nv + tin.triangle_slots();
  if (ascii)
    write_edges<true>(w, tin, written, options, faces_done, ne, total);
  else
    write_edges<false>(w, tin, written, options, faces_done, ne, total);
  w.flush();
  progress.finish();
  return {nv, written.triangles, 0};
}

}  // namespace tincdt::io::detail
