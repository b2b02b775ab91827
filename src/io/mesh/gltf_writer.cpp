// glTF 2.0 binary (GLB): one scene, one node, one mesh, for three.js, Blender, game engines and
// 3D Tiles content. The file is a 12-byte header, a JSON chunk (padded with spaces to 4 bytes)
// and a BIN chunk (padded with zeros) holding, in this order: POSITION (float32 VEC3), NORMAL
// (float32 VEC3, area-weighted vertex normals), the triangle indices and, when the TIN has
// constrained edges, their indices for a second primitive of mode LINES (uint16 indices when
// there are at most 65535 vertices, uint32 otherwise; glTF reserves the largest value of each).
//
// Axes: glTF is y-up and right-handed, the TIN is z-up (x east, y north). The vertex data is
// rotated, not the node: glTF (x, y, z) = (x - cx, z - cz, cy - y) with c the centre of the
// written vertices' bounding box, which is the node's translation (in double, so a vertex is
// placed as exactly as float32 allows around the centre: 1 mm across a TIN up to 32 km wide).
// Putting the rotation in the data keeps the mesh upright for tools that read the mesh alone,
// and 3D Tiles turns glTF's y-up content to z-up itself. The rotation (-90 degrees about x) keeps
// handedness, so triangles counter-clockwise seen from above stay counter-clockwise seen from +y
// and their faces point up. glTF has no CRS: asset.extras records the CRS and the offset.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/json.hpp"
#include "core/number_text.hpp"
#include "io/mesh/writer_detail.hpp"

namespace tincdt::io::detail {
namespace {

constexpr std::uint32_t kMagic = 0x46546C67;      // "glTF"
constexpr std::uint32_t kJsonChunk = 0x4E4F534A;  // "JSON"
constexpr std::uint32_t kBinChunk = 0x004E4942;   // "BIN\0"
constexpr int kFloat = 5126, kUnsignedShort = 5123, kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;
constexpr int kModeLines = 1;
// How a reader gets the source coordinates back from a glTF world position (X, Y, Z).
constexpr const char* kAxes =
    "source x = X + offset[0], y = offset[1] - Z, z = Y + offset[2] for a glTF world position "
    "(X, Y, Z): glTF is y-up, the source z-up";

std::uint64_t padded4(std::uint64_t n) {
  return (n + 3) & ~std::uint64_t{3};
}

struct Float3 {
  float x, y, z;
};

// Vertex P (source axes, offset subtracted) in glTF axes around CENTRE, rounded to float32.
Float3 gltf_position(const Point3& p, const Point3& centre) {
  return {static_cast<float>(p.x - centre.x), static_cast<float>(p.z - centre.z),
          static_cast<float>(centre.y - p.y)};
}

// What the JSON says about the BIN chunk: counts, bounds and where each array starts.
struct Layout {
  std::size_t vertices = 0;
  std::uint64_t triangles = 0;
  std::uint64_t segments = 0;  // constrained edges: the LINES primitive's
  Point3 centre;               // of the bounding box, source axes, offset subtracted
  Float3 min{}, max{};         // of POSITION, exactly as written
  int index_type = kUnsignedInt;
  std::uint64_t index_size = 4;
  std::uint64_t normals_at = 0, triangles_at = 0, lines_at = 0, bin_length = 0;
};

// The centre of the written vertices' bounding box, then the bounds of their float positions.
void find_bounds(const std::string& path, const mesh::Triangulation& tin,
                 const VertexNumbering& number, const TinWriteOptions& options, Layout& layout,
                 Progress& progress, std::uint64_t& done) {
  Point3 lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
            std::numeric_limits<double>::infinity()};
  Point3 hi{-lo.x, -lo.y, -lo.z};
  for (std::size_t i = 0; i < layout.vertices; ++i) {
    progress.tick(done++);
    const Point3 p = shifted_vertex(path, tin, number.vertex(i), options.offset);
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  layout.centre = {lo.x + (hi.x - lo.x) / 2, lo.y + (hi.y - lo.y) / 2, lo.z + (hi.z - lo.z) / 2};
  constexpr float kInf = std::numeric_limits<float>::infinity();
  layout.min = {kInf, kInf, kInf};
  layout.max = {-kInf, -kInf, -kInf};
  for (std::size_t i = 0; i < layout.vertices; ++i) {
    const Float3 q =
        gltf_position(shifted_vertex(path, tin, number.vertex(i), options.offset), layout.centre);
    layout.min = {std::min(layout.min.x, q.x), std::min(layout.min.y, q.y),
                  std::min(layout.min.z, q.z)};
    layout.max = {std::max(layout.max.x, q.x), std::max(layout.max.y, q.y),
                  std::max(layout.max.z, q.z)};
  }
}

// Per written vertex, the sum of its kept triangles' cross products (twice their area times
// their unit normal), source axes: x, y, z of vertex i at 3i.
std::vector<double> normal_sums(const std::string& path, const mesh::Triangulation& tin,
                                const VertexNumbering& number, const TinWriteOptions& options,
                                Progress& progress, std::uint64_t& done) {
  std::vector<double> sum(3 * number.count(), 0.0);
  tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& c) {
    progress.tick(done++);
    const std::array<double, 3> n = face_normal(path, tin, c, options.offset);
    for (const VertexId v : c) {
      double* s = &sum[3 * std::size_t{number(v)}];
      for (int k = 0; k < 3; ++k) s[k] += n[k];
    }
  });
  return sum;
}

// The unit normal of a vertex in glTF axes; straight up for a vertex no triangle uses.
Float3 gltf_normal(const double* s) {
  const double norm = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
  if (!(norm > 0) || !std::isfinite(norm)) return {0, 1, 0};
  return {static_cast<float>(s[0] / norm), static_cast<float>(s[2] / norm),
          static_cast<float>(-s[1] / norm)};
}

void put_float3(json::Writer& j, const Float3& v) {
  j.begin_array(json::Layout::compact);
  j.value(static_cast<double>(v.x)).value(static_cast<double>(v.y));
  j.value(static_cast<double>(v.z));
  j.end_array();
}

void put_accessor(json::Writer& j, int view, int type, std::uint64_t count, const char* shape) {
  j.begin_object(json::Layout::compact);
  j.field("bufferView", view).field("componentType", type).field("count", count);
  j.field("type", shape);
}

void put_view(json::Writer& j, std::uint64_t at, std::uint64_t length, int target) {
  j.begin_object(json::Layout::compact);
  j.field("buffer", 0).field("byteOffset", at).field("byteLength", length);
  j.field("target", target).end_object();
}

void put_asset(json::Writer& j, const TinWriteOptions& options) {
  j.key("asset").begin_object(json::Layout::compact).field("version", "2.0");
#ifdef TINCDT_VERSION
  j.field("generator", "tincdt " TINCDT_VERSION);
#else
  j.field("generator", "tincdt");
#endif
  j.key("extras").begin_object(json::Layout::compact);
  if (!options.crs_wkt.empty()) {
    const std::string code = crs_code(options.crs_wkt);
    if (!code.empty()) j.field("crs", code);
    j.field("crs_wkt", options.crs_wkt);
  }
  j.key("offset");
  j.begin_array(json::Layout::compact);
  j.value(options.offset.x).value(options.offset.y).value(options.offset.z).end_array();
  j.field("axes", kAxes).end_object().end_object();
}

// The mesh's two primitives (the LINES one only with constrained edges) and their materials:
// a matte surface (glTF's default material is fully metallic, black in many viewers) and red
// lines, so the constrained edges stand out from the surface they lie on.
void put_mesh(json::Writer& j, const Layout& layout) {
  j.key("meshes").begin_array(json::Layout::compact).begin_object(json::Layout::compact);
  j.field("name", "tin").key("primitives").begin_array(json::Layout::compact);
  j.begin_object(json::Layout::compact).key("attributes").begin_object(json::Layout::compact);
  j.field("POSITION", 0).field("NORMAL", 1).end_object();
  j.field("indices", 2).field("material", 0).end_object();
  if (layout.segments > 0) {
    j.begin_object(json::Layout::compact).key("attributes").begin_object(json::Layout::compact);
    j.field("POSITION", 0).end_object();
    j.field("indices", 3).field("mode", kModeLines).field("material", 1).end_object();
  }
  j.end_array().end_object().end_array();

  j.key("materials").begin_array(json::Layout::compact);
  j.begin_object(json::Layout::compact).field("name", "terrain");
  j.key("pbrMetallicRoughness").begin_object(json::Layout::compact);
  j.field("metallicFactor", 0).end_object().end_object();
  if (layout.segments > 0) {
    j.begin_object(json::Layout::compact).field("name", "constrained edges");
    j.key("pbrMetallicRoughness").begin_object(json::Layout::compact);
    j.key("baseColorFactor").begin_array(json::Layout::compact);
    j.value(0.8).value(0.1).value(0.1).value(1).end_array();
    j.field("metallicFactor", 0).end_object().end_object();
  }
  j.end_array();
}

void put_buffers(json::Writer& j, const Layout& layout) {
  const std::uint64_t nv = layout.vertices;
  j.key("accessors").begin_array(json::Layout::compact);
  put_accessor(j, 0, kFloat, nv, "VEC3");
  j.key("min");
  put_float3(j, layout.min);
  j.key("max");
  put_float3(j, layout.max);
  j.end_object();
  put_accessor(j, 1, kFloat, nv, "VEC3");
  j.end_object();
  put_accessor(j, 2, layout.index_type, 3 * layout.triangles, "SCALAR");
  j.end_object();
  if (layout.segments > 0) {
    put_accessor(j, 3, layout.index_type, 2 * layout.segments, "SCALAR");
    j.end_object();
  }
  j.end_array();

  j.key("bufferViews").begin_array(json::Layout::compact);
  put_view(j, 0, 12 * nv, kArrayBuffer);
  put_view(j, layout.normals_at, 12 * nv, kArrayBuffer);
  put_view(j, layout.triangles_at, 3 * layout.triangles * layout.index_size, kElementArrayBuffer);
  if (layout.segments > 0)
    put_view(j, layout.lines_at, 2 * layout.segments * layout.index_size, kElementArrayBuffer);
  j.end_array();
  j.key("buffers").begin_array(json::Layout::compact).begin_object(json::Layout::compact);
  j.field("byteLength", layout.bin_length).end_object().end_array();
}

// The JSON chunk's text, padded with spaces to a multiple of 4 bytes. An empty TIN is a scene
// whose node has no mesh (an accessor may not be empty).
std::string gltf_json(const Layout& layout, const TinWriteOptions& options) {
  json::Writer j(json::Numbers::plain, NonUtf8::replace);
  j.begin_object(json::Layout::compact);
  put_asset(j, options);
  j.field("scene", 0).key("scenes").begin_array(json::Layout::compact);
  j.begin_object(json::Layout::compact).key("nodes").begin_array(json::Layout::compact);
  j.value(0).end_array().end_object().end_array();
  j.key("nodes").begin_array(json::Layout::compact).begin_object(json::Layout::compact);
  j.field("name", "tin");
  if (layout.triangles > 0) {
    j.field("mesh", 0).key("translation").begin_array(json::Layout::compact);
    // 0 - y, not -y: a centre on the axis is written 0, not -0.
    j.value(layout.centre.x).value(layout.centre.z).value(0.0 - layout.centre.y).end_array();
  }
  j.end_object().end_array();
  if (layout.triangles > 0) {
    put_mesh(j, layout);
    put_buffers(j, layout);
  }
  j.end_object();
  std::string text = j.str();
  text.resize(padded4(text.size()), ' ');
  return text;
}

void put_padding(BlockWriter& w, std::uint64_t bytes) {
  for (std::uint64_t i = bytes; i % 4 != 0; ++i) w.put('\0');
}

template <class Index>
void put_indices(BlockWriter& w, const mesh::Triangulation& tin, const VertexNumbering& number,
                 const Layout& layout, bool kept_only, Progress& progress, std::uint64_t& done) {
  tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& c) {
    progress.tick(done++);
    for (const VertexId v : c) w.put_le(static_cast<Index>(number(v)));
  });
  put_padding(w, 3 * layout.triangles * sizeof(Index));
  for_each_constrained_segment(tin, kept_only, [&](VertexId a, VertexId b) {
    progress.tick(done++);
    w.put_le(static_cast<Index>(number(a)));
    w.put_le(static_cast<Index>(number(b)));
  });
  put_padding(w, 2 * layout.segments * sizeof(Index));
}

}  // namespace

TinWriteStats write_gltf(OutputFile& out, const mesh::Triangulation& tin,
                         const TinWriteOptions& options) {
  const std::string& path = out.path();
  const TriangleCounts counts = count_triangles(tin);
  const bool compact = counts.removed > 0;
  const VertexNumbering number(tin, compact);
  Layout layout;
  layout.vertices = number.count();
  layout.triangles = counts.kept;
  layout.segments = counts.kept > 0 ? count_constrained_segments(tin, compact) : 0;
  // The largest index value of each type is reserved (primitive restart).
  if (layout.vertices > std::numeric_limits<std::uint32_t>::max())
    throw OutputError(path, "", "more than 2^32 - 1 vertices do not fit in a glTF mesh");
  if (layout.vertices <= std::numeric_limits<std::uint16_t>::max()) {
    layout.index_type = kUnsignedShort;
    layout.index_size = 2;
  }
  const std::uint64_t nv = layout.vertices;
  layout.normals_at = 12 * nv;
  layout.triangles_at = 24 * nv;
  layout.lines_at = layout.triangles_at + padded4(3 * layout.triangles * layout.index_size);
  layout.bin_length = layout.lines_at + padded4(2 * layout.segments * layout.index_size);

  const auto refuse_beyond_4gib = [&path](std::uint64_t bytes) {
    if (bytes > std::numeric_limits<std::uint32_t>::max())
      throw OutputError(path, "",
                        "the mesh needs " + count_text(bytes) +
                            " bytes; a GLB file holds at most 4 GiB (2^32 - 1 bytes)");
  };
  refuse_beyond_4gib(28 + layout.bin_length);  // before the work; the JSON is added below

  Progress progress(options.progress, "write", 2 * (nv + layout.triangles) + layout.segments);
  std::uint64_t done = 0;
  std::vector<double> normals;
  if (layout.triangles > 0) {
    find_bounds(path, tin, number, options, layout, progress, done);
    normals = normal_sums(path, tin, number, options, progress, done);
  }
  const std::string json = gltf_json(layout, options);
  const std::uint64_t bin_chunk = layout.triangles > 0 ? 8 + layout.bin_length : 0;
  const std::uint64_t total = 12 + 8 + json.size() + bin_chunk;
  refuse_beyond_4gib(total);

  BlockWriter w(out);
  w.put_le(kMagic);
  w.put_le(std::uint32_t{2});
  w.put_le(static_cast<std::uint32_t>(total));
  w.put_le(static_cast<std::uint32_t>(json.size()));
  w.put_le(kJsonChunk);
  w.put(json);
  if (layout.triangles > 0) {
    w.put_le(static_cast<std::uint32_t>(layout.bin_length));
    w.put_le(kBinChunk);
    for (std::size_t i = 0; i < nv; ++i) {
      progress.tick(done++);
      const Float3 q =
          gltf_position(shifted_vertex(path, tin, number.vertex(i), options.offset), layout.centre);
      w.put_le(q.x);
      w.put_le(q.y);
      w.put_le(q.z);
    }
    for (std::size_t i = 0; i < nv; ++i) {
      const Float3 n = gltf_normal(&normals[3 * i]);
      w.put_le(n.x);
      w.put_le(n.y);
      w.put_le(n.z);
    }
    if (layout.index_size == 2)
      put_indices<std::uint16_t>(w, tin, number, layout, compact, progress, done);
    else
      put_indices<std::uint32_t>(w, tin, number, layout, compact, progress, done);
  }
  w.flush();
  progress.finish();
  return {layout.triangles > 0 ? nv : 0, layout.triangles, 0};
}

}  // namespace tincdt::io::detail
