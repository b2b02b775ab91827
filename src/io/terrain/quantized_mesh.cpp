// The byte layout of a quantized-mesh-1.0 tile.
#include "io/terrain/quantized_mesh.hpp"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cstring>
#include <optional>
#include <string_view>
#include <utility>

#include "core/json.hpp"
#include "io/terrain/layer_json.hpp"
#include "io/terrain/quantized_mesh_detail.hpp"

namespace tincdt::io::terrain {
namespace {

// The extension ids of the specification.
constexpr std::uint8_t kOctVertexNormalsId = 1;
constexpr std::uint8_t kMetadataId = 4;

// Appends little-endian values, whatever the host's byte order.
class Bytes {
 public:
  template <class T>
  void put(T v) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &v, sizeof(T));
    if constexpr (std::endian::native == std::endian::big) std::reverse(bytes, bytes + sizeof(T));
    out_.append(bytes, sizeof(T));
  }
  void put(const Point3& p) {
    put(p.x);
    put(p.y);
    put(p.z);
  }
  void append(std::string_view bytes) { out_.append(bytes); }
  // Zero bytes up to the next multiple of ALIGNMENT.
  void pad_to(std::size_t alignment) {
    out_.append((alignment - out_.size() % alignment) % alignment, '\0');
  }
  std::size_t size() const { return out_.size(); }
  std::string take() { return std::move(out_); }

 private:
  std::string out_;
};

void write_header(Bytes& out, const QuantizedMeshHeader& h) {
  out.put(h.center);
  out.put(h.minimum_height);
  out.put(h.maximum_height);
  out.put(h.bounding_sphere_center);
  out.put(h.bounding_sphere_radius);
  out.put(h.horizon_occlusion_point);
  assert(out.size() == 88);
}

// The vertices in the order the triangles first use them, then the unused ones: ORDER[new] is
// the old index. The high-water-mark code can only name a vertex no later than the next new one.
std::vector<std::uint32_t> first_use_order(const TileMesh& mesh) {
  const std::size_t n = mesh.vertices.size();
  std::vector<bool> placed(n, false);
  std::vector<std::uint32_t> order;
  order.reserve(n);
  for (const auto& t : mesh.triangles) {
    for (const std::uint32_t c : t) {
      if (!placed[c]) {
        placed[c] = true;
        order.push_back(c);
      }
    }
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    if (!placed[i]) order.push_back(i);
  }
  return order;
}

// The renumbering ORDER gives: RENUMBER[old] is the new index.
std::vector<std::uint32_t> renumbering(const std::vector<std::uint32_t>& order) {
  std::vector<std::uint32_t> renumber(order.size());
  for (std::uint32_t i = 0; i < order.size(); ++i) renumber[order[i]] = i;
  return renumber;
}

// Whether a high-water-mark code of MESH, its vertices in ORDER, would exceed 16 bits. Only a
// tile of exactly 65536 vertices can have one: once all are met, the code of vertex 0 is 65536.
bool needs_code_beyond_16_bits(const TileMesh& mesh, const std::vector<std::uint32_t>& order) {
  if (order.size() != kMaxVerticesFor16BitIndices) return false;
  const std::vector<std::uint32_t> renumber = renumbering(order);
  std::uint32_t highest = 0;
  for (const auto& t : mesh.triangles) {
    for (const std::uint32_t c : t) {
      if (highest - renumber[c] > 0xffff) return true;
      if (renumber[c] == highest) ++highest;
    }
  }
  return false;
}

// MESH with one more vertex, used by no triangle, when its codes would not fit in 16 bits: with
// 65537 vertices the tile takes 32-bit indices. The vertex stands at the rectangle's centre, on
// no side, at the height of vertex 0, within the height range.
std::optional<TileMesh> padded_for_indices(const TileMesh& mesh,
                                           const std::vector<std::uint32_t>& order) {
  if (!needs_code_beyond_16_bits(mesh, order)) return std::nullopt;
  TileMesh padded = mesh;
  const GeoRectangle& r = mesh.rectangle;
  padded.vertices.push_back(
      {(r.west + r.east) / 2, (r.south + r.north) / 2, mesh.vertices.front().z});
  return padded;
}

// Each value minus the one before (the first minus 0), zig-zag coded: 0, -1, 1, -2, 2, ... as
// 0, 1, 2, 3, 4, ... so that small steps either way are small numbers.
void put_zig_zag_deltas(Bytes& out, const std::vector<std::uint16_t>& values,
                        const std::vector<std::uint32_t>& order) {
  int previous = 0;
  for (const std::uint32_t old : order) {
    const int delta = values[old] - previous;
    previous = values[old];
    out.put(static_cast<std::uint16_t>(delta >= 0 ? 2 * delta : -2 * delta - 1));
  }
}

void write_vertices(Bytes& out, const detail::QuantizedVertices& q,
                    const std::vector<std::uint32_t>& order) {
  out.put(static_cast<std::uint32_t>(order.size()));
  put_zig_zag_deltas(out, q.u, order);
  put_zig_zag_deltas(out, q.v, order);
  put_zig_zag_deltas(out, q.height, order);
}

// The triangles, each corner as the count of vertices met so far less its index: 0 for the
// next new vertex (in first-use order the only new one a corner can be).
template <class Index>
void write_triangles(Bytes& out, const TileMesh& mesh, const std::vector<std::uint32_t>& renumber) {
  out.put(static_cast<std::uint32_t>(mesh.triangles.size()));
  std::uint32_t highest = 0;
  for (const auto& t : mesh.triangles) {
    for (const std::uint32_t c : t) {
      const std::uint32_t index = renumber[c];
      assert(index <= highest);
      out.put(static_cast<Index>(highest - index));
      if (index == highest) ++highest;
    }
  }
}

// The four side lists in file order: west, south, east, north. Each holds the (renumbered)
// vertices lying exactly on its side, sorted as Cesium walks them.
std::array<std::vector<std::uint32_t>, 4> side_lists(const TileMesh& mesh,
                                                     const detail::QuantizedVertices& q,
                                                     const std::vector<std::uint32_t>& order) {
  const GeoRectangle& r = mesh.rectangle;
  std::array<std::vector<std::uint32_t>, 4> sides;
  for (std::uint32_t i = 0; i < order.size(); ++i) {
    const Point3& p = mesh.vertices[order[i]];
    if (p.x == r.west) sides[0].push_back(i);
    if (p.y == r.south) sides[1].push_back(i);
    if (p.x == r.east) sides[2].push_back(i);
    if (p.y == r.north) sides[3].push_back(i);
  }
  // By KEY of the vertex, increasing or not; ties by index, for the same bytes every time.
  const auto sort_by = [&](std::vector<std::uint32_t>& side, const std::vector<std::uint16_t>& key,
                           bool increasing) {
    std::sort(side.begin(), side.end(), [&](std::uint32_t a, std::uint32_t b) {
      const std::uint16_t ka = key[order[a]], kb = key[order[b]];
      if (ka != kb) return increasing ? ka < kb : ka > kb;
      return a < b;
    });
  };
  sort_by(sides[0], q.v, true);   // west: south to north
  sort_by(sides[1], q.u, false);  // south: east to west
  sort_by(sides[2], q.v, false);  // east: north to south
  sort_by(sides[3], q.u, true);   // north: west to east
  return sides;
}

template <class Index>
void write_sides(Bytes& out, const std::array<std::vector<std::uint32_t>, 4>& sides) {
  for (const auto& side : sides) {
    out.put(static_cast<std::uint32_t>(side.size()));
    for (const std::uint32_t i : side) out.put(static_cast<Index>(i));
  }
}

template <class Index>
void write_indices(Bytes& out, const TileMesh& mesh, const detail::QuantizedVertices& q,
                   const std::vector<std::uint32_t>& order) {
  out.pad_to(sizeof(Index));
  write_triangles<Index>(out, mesh, renumbering(order));
  write_sides<Index>(out, side_lists(mesh, q, order));
}

// {"available":[[{"startX":..,"startY":..,"endX":..,"endY":..},...],...]}, one line.
std::string metadata_json(const std::vector<std::vector<TileRange>>& available) {
  json::Writer w;
  w.begin_object(json::Layout::compact).key("available").begin_array();
  for (const auto& level : available) {
    w.begin_array();
    for (const TileRange& range : level) write_tile_range(w, range);
    w.end_array();
  }
  w.end_array().end_object();
  return w.str();
}

void write_extensions(Bytes& out, const TileMesh& mesh, const std::vector<std::uint32_t>& order,
                      const QuantizedMeshOptions& options) {
  if (options.vertex_normals) {
    const auto normals = detail::oct_vertex_normals(mesh);
    out.put(kOctVertexNormalsId);
    out.put(static_cast<std::uint32_t>(2 * order.size()));
    for (const std::uint32_t old : order) {
      out.put(normals[old][0]);
      out.put(normals[old][1]);
    }
  }
  if (options.metadata) {
    const std::string json = metadata_json(options.available);
    out.put(kMetadataId);
    out.put(static_cast<std::uint32_t>(4 + json.size()));
    out.put(static_cast<std::uint32_t>(json.size()));
    out.append(json);
  }
}

}  // namespace

QuantizedMeshHeader quantized_mesh_header(const TileMesh& mesh) {
  detail::check_tile_mesh(mesh);
  const std::optional<TileMesh> padded = padded_for_indices(mesh, first_use_order(mesh));
  const TileMesh& m = padded ? *padded : mesh;
  return detail::header_of(m, detail::quantize_vertices(m));
}

std::string encode_quantized_mesh(const TileMesh& mesh, const QuantizedMeshOptions& options) {
  detail::check_tile_mesh(mesh);
  std::vector<std::uint32_t> order = first_use_order(mesh);
  const std::optional<TileMesh> padded = padded_for_indices(mesh, order);
  const TileMesh& m = padded ? *padded : mesh;
  if (padded) order.push_back(static_cast<std::uint32_t>(mesh.vertices.size()));
  const detail::QuantizedVertices q = detail::quantize_vertices(m);
  Bytes out;
  write_header(out, detail::header_of(m, q));
  write_vertices(out, q, order);
  if (order.size() > kMaxVerticesFor16BitIndices)
    write_indices<std::uint32_t>(out, m, q, order);
  else
    write_indices<std::uint16_t>(out, m, q, order);
  write_extensions(out, m, order, options);
  return out.take();
}

}  // namespace tincdt::io::terrain
