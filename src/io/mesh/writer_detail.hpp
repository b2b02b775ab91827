// Private to the writers (src/io/*_writer.cpp): a block buffer that formats numbers without
// losing precision, the per-format entry points that write_tin() dispatches to, and the GeoJSON
// pieces (CRS member, vertex positions) that the TIN and constraint-line writers share.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cassert>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/json_text.hpp"
#include "core/parallel.hpp"
#include "core/progress.hpp"
#include "core/thread_pool.hpp"
#include "core/types.hpp"
#include "io/mesh/tin_writer.hpp"
#include "io/output_file.hpp"
#include "mesh/triangulation.hpp"

class OGRSpatialReference;  // GDAL's (ogr_spatialref.h), for parse_crs()

namespace tincdt::io::detail {

// The shortest text that reads back to the same double: plain decimals ("500000",
// "4000000.987654321") in the range coordinates live in, exponent form only for tiny or huge
// magnitudes (std::to_chars alone would write 500000 as "5e+05"). At most 24 characters.
inline char* format_double(char* first, char* last, double v) {
  const double a = std::fabs(v);
  if (a == 0 || (a >= 1e-5 && a < 1e15))
    return std::to_chars(first, last, v, std::chars_format::fixed).ptr;
  return std::to_chars(first, last, v).ptr;
}

// Collects text or packed binary records and passes them to an OutputFile in large blocks,
// so the hot loops never call into stdio; or, made without a file, keeps them all (growing as
// needed) for a block of records formatted apart from the file (write_blocks()). Numbers are
// formatted with std::to_chars: a double becomes its shortest text that reads back to the same
// bits.
class BlockWriter {
 public:
  static constexpr std::size_t kBlock = std::size_t{4} << 20;
  // Longest single item a put_* call appends (a double is at most 24 characters).
  static constexpr std::size_t kMaxItem = 32;

  explicit BlockWriter(OutputFile& out) : out_(&out), cap_(kBlock), buf_(allocate(cap_)) {}
  // In memory, starting with room for CAPACITY bytes.
  explicit BlockWriter(std::size_t capacity) : cap_(capacity), buf_(allocate(cap_)) {}
  BlockWriter(const BlockWriter&) = delete;
  BlockWriter& operator=(const BlockWriter&) = delete;

  void put(char c) {
    room();
    buf_[pos_++] = c;
  }
  void put(std::string_view s) {
    if (pos_ + s.size() > cap_) {
      if (out_ == nullptr) {
        grow(pos_ + s.size());
      } else {
        flush();
        if (s.size() > cap_) {
          out_->write(s.data(), s.size());
          return;
        }
      }
    }
    std::memcpy(buf_.get() + pos_, s.data(), s.size());
    pos_ += s.size();
  }
  void put_double(double v) {
    room();
    pos_ = static_cast<std::size_t>(
        format_double(buf_.get() + pos_, buf_.get() + pos_ + kMaxItem, v) - buf_.get());
  }
  // "x<SEP>y<SEP>z", each in shortest round-trip form (OBJ and PLY lines, GeoJSON positions).
  void put_xyz(const Point3& p, char sep) {
    put_double(p.x);
    put(sep);
    put_double(p.y);
    put(sep);
    put_double(p.z);
  }
  void put_uint(std::uint64_t v) {
    room();
    pos_ = static_cast<std::size_t>(
        std::to_chars(buf_.get() + pos_, buf_.get() + pos_ + kMaxItem, v).ptr - buf_.get());
  }
  // Little-endian binary of an arithmetic value, whatever the host's byte order.
  template <class T>
  void put_le(T v) {
    static_assert(sizeof(T) <= kMaxItem);
    room();
    char bytes[sizeof(T)];
    std::memcpy(bytes, &v, sizeof(T));
    if constexpr (std::endian::native == std::endian::big) {
      for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
    }
    std::memcpy(buf_.get() + pos_, bytes, sizeof(T));
    pos_ += sizeof(T);
  }
  // Hands the buffered bytes to the OutputFile (also done by the hot paths when a block fills).
  void flush() {
    assert(out_ != nullptr);
    if (pos_ == 0) return;
    out_->write(buf_.get(), pos_);
    pos_ = 0;
  }
  // After the buffered bytes, BYTES straight to the OutputFile (a block formatted apart).
  void write_block(std::string_view bytes) {
    flush();
    out_->write(bytes.data(), bytes.size());
  }

  // In memory: the bytes put so far, and forgetting them (the room stays).
  std::string_view bytes() const { return {buf_.get(), pos_}; }
  void clear() { pos_ = 0; }

 private:
  // CAPACITY bytes and the room for one more item.
  static std::unique_ptr<char[]> allocate(std::size_t capacity) {
    return std::make_unique_for_overwrite<char[]>(capacity + kMaxItem);
  }
  void room() {
    if (pos_ >= cap_) full();
  }
  void full() {
    if (out_ != nullptr)
      flush();
    else
      grow(pos_ + kMaxItem);
  }
  // In memory: room for at least SIZE bytes, keeping those put.
  void grow(std::size_t size) {
    const std::size_t capacity = std::max(size, 2 * cap_);
    std::unique_ptr<char[]> bigger = allocate(capacity);
    std::memcpy(bigger.get(), buf_.get(), pos_);
    buf_ = std::move(bigger);
    cap_ = capacity;
  }

  OutputFile* out_ = nullptr;  // null: in memory
  std::size_t cap_;            // bytes put before a flush (file) or a growth (memory)
  std::unique_ptr<char[]> buf_;
  std::size_t pos_ = 0;
};

// Bytes aimed at per block of records formatted apart (write_blocks()): a millisecond or so of
// work, small enough that twice as many blocks as threads cost little memory.
inline constexpr std::size_t kRecordBlockBytes = std::size_t{1} << 20;

// Records per block when a record takes about RECORD_BYTES.
inline std::size_t records_per_block(std::size_t record_bytes) {
  return std::max<std::size_t>(1, kRecordBlockBytes / record_bytes);
}

// Records [0, N) formatted in blocks of records_per_block(RECORD_BYTES) on THREADS threads
// (0 = one per core) and written through W in order, so that the bytes are those of one thread
// formatting them all. FORMAT(BlockWriter&, begin, end) appends records [begin, end) to an
// in-memory writer. An error FORMAT throws comes out when its block's turn to be written comes:
// the error of the earliest record, whatever the thread count. While a batch of blocks (one per
// thread) is formatted, the batch before it is written, so at most twice THREADS blocks are held
// at once. PROGRESS ticks DONE plus the records written so far, on the calling thread.
template <class Format>
void write_blocks(BlockWriter& w, unsigned threads, std::size_t n, std::size_t record_bytes,
                  Progress& progress, std::uint64_t done, const Format& format) {
  const std::size_t per_block = records_per_block(record_bytes);
  const std::size_t blocks = (n + per_block - 1) / per_block;
  if (blocks == 0) return;
  const std::size_t width = std::min(thread_count(threads), blocks);  // blocks per batch
  const std::size_t batches = (blocks + width - 1) / width;
  struct Block {
    BlockWriter text{kRecordBlockBytes};
    std::exception_ptr error;
  };
  // Two halves: batch b is formatted in half b % 2 while the other half is written.
  const auto held = std::make_unique<Block[]>(2 * width);
  const auto batch_size = [&](std::size_t b) { return std::min(width, blocks - b * width); };
  std::size_t written = 0;  // records
  const auto write_batch = [&](std::size_t b) {
    Block* half = held.get() + (b % 2) * width;
    for (std::size_t i = 0; i < batch_size(b); ++i) {
      if (half[i].error) std::rethrow_exception(half[i].error);
      w.write_block(half[i].text.bytes());
      half[i].text.clear();
      written = std::min(n, written + per_block);
    }
  };
  ThreadPool pool(width);
  for (std::size_t b = 0; b < batches; ++b) {
    // Chunk 0 writes batch b - 1 (from b = 1 on); the others format batch b.
    const std::size_t writing = b > 0 ? 1 : 0;
    auto chunk = [&](std::size_t c, std::size_t) {
      if (c < writing) return write_batch(b - 1);
      const std::size_t block = b * width + (c - writing);
      Block& out = held[(b % 2) * width + (c - writing)];
      try {
        format(out.text, block * per_block, std::min(n, (block + 1) * per_block));
      } catch (...) {
        out.error = std::current_exception();
      }
    };
    progress.tick(done + written);
    pool.run(chunk, writing + batch_size(b));
  }
  write_batch(batches - 1);
  progress.tick(done + written);
}

// Calls f(TriangleId, std::array<VertexId, 3>) for the triangles of slots [BEGIN, END) that
// Triangulation::for_each_triangle() visits, in the same order.
template <class F>
void for_each_triangle_in(const mesh::Triangulation& tin, std::size_t begin, std::size_t end,
                          F&& f) {
  for (std::size_t t = begin; t < end; ++t) {
    const auto id = static_cast<TriangleId>(t);
    const std::array<VertexId, 3> c = tin.triangle(id);
    if (c[0] >= mesh::kInfinite || c[1] >= mesh::kInfinite || c[2] >= mesh::kInfinite) continue;
    if (tin.is_removed(id)) continue;
    f(id, c);
  }
}

// Vertex v with the offset subtracted; throws OutputError for a NaN or infinite coordinate,
// which no format can carry meaningfully (and would make the GeoJSON invalid).
inline Point3 shifted_vertex(const std::string& path, const mesh::Triangulation& tin, VertexId v,
                             const Point3& offset) {
  const Point2 p = tin.point(v);
  const Point3 q{p.x - offset.x, p.y - offset.y, tin.z(v) - offset.z};
  if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z))
    throw OutputError(path, "vertex " + std::to_string(v), "coordinate is not a finite number");
  return q;
}

// The cross product of triangle C's edges, its vertices shifted as shifted_vertex(): the face's
// normal times twice its area, up for a counter-clockwise triangle.
inline std::array<double, 3> face_normal(const std::string& path, const mesh::Triangulation& tin,
                                         const std::array<VertexId, 3>& c, const Point3& offset) {
  Point3 p[3];
  for (int i = 0; i < 3; ++i) p[i] = shifted_vertex(path, tin, c[i], offset);
  const double ux = p[1].x - p[0].x, uy = p[1].y - p[0].y, uz = p[1].z - p[0].z;
  const double vx = p[2].x - p[0].x, vy = p[2].y - p[0].y, vz = p[2].z - p[0].z;
  return {uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx};
}

inline bool is_zero(const Point3& p) {
  return p.x == 0 && p.y == 0 && p.z == 0;
}

// Real triangles, counted from the corner array (the count written in headers must match the
// records exactly, whatever the state of Triangulation::triangle_count()): `kept` are written,
// `removed` (clipped, erased, trimmed) are not. One pass over the slots, as cheap as counting the
// kept ones alone, split between THREADS threads (0 = one per core).
struct TriangleCounts {
  std::uint64_t kept = 0;
  std::uint64_t removed = 0;
};
inline TriangleCounts count_triangles(const mesh::Triangulation& tin, unsigned threads = 1) {
  std::atomic<std::uint64_t> kept{0}, removed{0};
  parallel_chunks(threads, tin.triangle_slots(), [&](std::size_t begin, std::size_t end) {
    TriangleCounts n;
    for (std::size_t t = begin; t < end; ++t) {
      const auto id = static_cast<TriangleId>(t);
      if (tin.is_ghost(id)) continue;
      if (tin.is_removed(id))
        ++n.removed;
      else
        ++n.kept;
    }
    kept += n.kept;
    removed += n.removed;
  });
  return {kept, removed};
}

// The vertex numbers a writer uses. With no removed triangle (the common case) every vertex is
// written under its own id: no table, no extra pass. With removed triangles only the vertices of
// kept triangles are written, renumbered 0, 1, ... in id order, so a clipped TIN carries no
// vertex that no face uses.
class VertexNumbering {
 public:
  VertexNumbering(const mesh::Triangulation& tin, bool compact) : count_(tin.vertex_count()) {
    if (!compact) return;
    new_id_.assign(tin.vertex_count(), kNoId);
    tin.for_each_triangle([this](TriangleId, const std::array<VertexId, 3>& c) {
      for (const VertexId v : c) new_id_[v] = 0;  // used; numbered below
    });
    old_id_.reserve(new_id_.size());
    for (std::size_t v = 0; v < new_id_.size(); ++v) {
      if (new_id_[v] == kNoId) continue;
      new_id_[v] = static_cast<VertexId>(old_id_.size());
      old_id_.push_back(static_cast<VertexId>(v));
    }
    count_ = old_id_.size();
  }
  // Vertices written.
  std::size_t count() const { return count_; }
  bool compacted() const { return !new_id_.empty(); }
  // The written number of vertex v (v must be a corner of a kept triangle when compacted).
  VertexId operator()(VertexId v) const { return new_id_.empty() ? v : new_id_[v]; }
  // The vertex written as number i, for i < count().
  VertexId vertex(std::size_t i) const {
    return old_id_.empty() ? static_cast<VertexId>(i) : old_id_[i];
  }
  // The written vertices' ids in order (empty when not compacted: every vertex, in order).
  const std::vector<VertexId>& vertices() const { return old_id_; }

 private:
  std::size_t count_;
  std::vector<VertexId> new_id_;  // vertex -> written number; empty when not compacted
  std::vector<VertexId> old_id_;  // written number -> vertex
};

// What a mesh writer writes of TIN: the kept triangles, and the vertices numbered for them
// (compacted when some triangles are removed). Counted in THREADS threads.
struct WrittenTin {
  WrittenTin(const mesh::Triangulation& tin, unsigned threads)
      : WrittenTin(tin, count_triangles(tin, threads)) {}

  std::uint64_t triangles;  // kept
  bool compact;             // some removed: only the kept triangles' vertices, renumbered
  VertexNumbering number;

 private:
  WrittenTin(const mesh::Triangulation& tin, const TriangleCounts& counts)
      : triangles(counts.kept), compact(counts.removed > 0), number(tin, compact) {}
};

// Calls f(origin, dest) once per constrained edge between two real vertices whose first
// half-edge (Triangulation::for_each_constrained_edge()'s) is in [BEGIN, END), in the same order;
// with `kept_only`, only for edges with a kept triangle on at least one side (the edges of the
// written TIN).
template <class F>
void for_each_constrained_segment_in(const mesh::Triangulation& tin, bool kept_only,
                                     std::size_t begin, std::size_t end, F&& f) {
  if (!tin.has_constraints()) return;
  for (std::size_t i = begin; i < end; ++i) {
    const auto e = static_cast<EdgeId>(i);
    if (!tin.is_constrained(e)) continue;
    const VertexId a = tin.origin(e);
    const VertexId b = tin.dest(e);
    if (a >= b || b >= mesh::kInfinite) continue;  // the twin's turn, or a ghost edge
    if (kept_only && !tin.is_kept(mesh::triangle_of(e)) &&
        !tin.is_kept(mesh::triangle_of(tin.twin(e))))
      continue;
    f(a, b);
  }
}

template <class F>
void for_each_constrained_segment(const mesh::Triangulation& tin, bool kept_only, F&& f) {
  for_each_constrained_segment_in(tin, kept_only, 0, 3 * tin.triangle_slots(), f);
}

// The constrained segments for_each_constrained_segment() visits, counted on THREADS threads
// (0 = one per core).
inline std::uint64_t count_constrained_segments(const mesh::Triangulation& tin, bool kept_only,
                                                unsigned threads = 1) {
  if (!tin.has_constraints()) return 0;
  std::atomic<std::uint64_t> total{0};
  parallel_chunks(threads, 3 * tin.triangle_slots(), [&](std::size_t begin, std::size_t end) {
    std::uint64_t n = 0;
    for_each_constrained_segment_in(tin, kept_only, begin, end, [&n](VertexId, VertexId) { ++n; });
    total += n;
  });
  return total;
}

// "X Y Z" in shortest round-trip form, for the offset lines of the headers.
std::string format_point(const Point3& p);
// "EPSG:2949" (any AUTHORITY:CODE) when crs_label() identifies the CRS, else "".
std::string crs_code(const std::string& wkt);

// ---- GDAL and GeoJSON helpers (geojson_writer.cpp) ------------------------------------------

// Any CRS text OSR reads (WKT, "EPSG:n", ...) as an OSR object in traditional GIS axis order
// (x = easting / longitude); throws OutputError naming PATH and WHAT when OSR cannot read it.
OGRSpatialReference parse_crs(const std::string& path, const std::string& wkt, const char* what);
// "[x,y,z]" in shortest round-trip form.
void put_position(BlockWriter& w, const Point3& p);
// The opening of a GeoJSON FeatureCollection, up to and including "\"features\": [\n": the
// "crs" member the way GDAL writes it (none for WGS 84 or an unknown CRS) and the "tincdt_offset"
// foreign member when there is an offset.
void put_feature_collection_start(BlockWriter& w, const std::string& path,
                                  const TinWriteOptions& options);

// A format writer: writes the whole file through `out` (not committed) and returns the vertex
// and triangle counts; write_tin() owns the OutputFile(s) and commits them.
using FormatWriter = TinWriteStats(OutputFile& out, const mesh::Triangulation& tin,
                                   const TinWriteOptions& options);
FormatWriter write_obj, write_ply, write_geojson, write_landxml, write_stl, write_gltf;
// GDAL creates the GeoPackage itself, at out.take_path().
FormatWriter write_gpkg;

}  // namespace tincdt::io::detail
