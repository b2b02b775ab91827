// GeoJSON: a FeatureCollection of one 3D Polygon per triangle (closed ring, counter-clockwise,
// as RFC 7946 asks), written directly with to_chars (building it through OGR is far too slow for
// millions of triangles). The CRS member, vertex positions and reprojection defined here are
// shared with the constraint-line writer (constraint_writer.cpp). The CRS is written the way GDAL's
// GeoJSON driver writes it:
//   "crs": { "type": "name", "properties": { "name": "urn:ogc:def:crs:EPSG::2949" } }
// and left out for WGS 84 (EPSG:4326 / CRS84), RFC 7946's only CRS. A CRS without an EPSG code,
// which GDAL would drop, is written as one-line WKT in the same member; GDAL reads it back.
#include <algorithm>
#include <vector>

#include "io/crs.hpp"
#include "io/gdal_support.hpp"
#include "io/mesh/writer_detail.hpp"

namespace tincdt::io::detail {
namespace {

bool is_wgs84(const OGRSpatialReference& srs) {
  OGRSpatialReference wgs84;
  wgs84.SetWellKnownGeogCS("WGS84");
  const char* const options[] = {"IGNORE_DATA_AXIS_TO_SRS_AXIS_MAPPING=YES",
                                 "CRITERION=EQUIVALENT_EXCEPT_AXIS_ORDER_GEOGCRS", nullptr};
  return srs.IsSame(&wgs84, options) != 0;
}

// The top-level "crs" member (with its trailing ",\n"), or "" for WGS 84 and an unknown CRS.
std::string crs_member(const std::string& path, const std::string& wkt) {
  if (wkt.empty()) return {};
  const GdalQuiet quiet;
  if (is_wgs84(parse_crs(path, wkt, "the output CRS"))) return {};
  const std::string code = crs_code(wkt);
  const std::string name =
      code.rfind("EPSG:", 0) == 0 ? "urn:ogc:def:crs:EPSG::" + code.substr(5) : one_line(wkt);
  return "\"crs\": { \"type\": \"name\", \"properties\": { \"name\": " + json_string(name) +
         " } },\n";
}

// Rough bytes of a feature, for the size of the blocks formatted apart.
constexpr std::size_t kFeatureBytes = 300;

// For each block of PER_BLOCK triangle slots, the triangles for_each_triangle() visits in the
// slots before it: the id of the block's first feature.
std::vector<std::uint64_t> kept_before_blocks(const mesh::Triangulation& tin, std::size_t per_block,
                                              unsigned threads) {
  const std::size_t slots = tin.triangle_slots();
  const std::size_t blocks = (slots + per_block - 1) / per_block;
  std::vector<std::uint64_t> first(blocks + 1, 0);
  auto count = [&](std::size_t block, std::size_t) {
    std::uint64_t n = 0;
    for_each_triangle_in(tin, block * per_block, std::min(slots, (block + 1) * per_block),
                         [&n](TriangleId, const std::array<VertexId, 3>&) { ++n; });
    first[block + 1] = n;
  };
  ThreadPool(std::min(thread_count(threads), std::max<std::size_t>(blocks, 1))).run(count, blocks);
  for (std::size_t b = 0; b < blocks; ++b) first[b + 1] += first[b];
  return first;
}

// Feature ID, the triangle with corners C: ",\n" before it but for the first.
void put_feature(BlockWriter& w, std::uint64_t id, const std::array<VertexId, 3>& c,
                 const GeoJsonPositions& position) {
  if (id > 0) w.put(std::string_view(",\n"));
  w.put(std::string_view("{\"type\":\"Feature\",\"properties\":{\"id\":"));
  w.put_uint(id);
  w.put(std::string_view("},\"geometry\":{\"type\":\"Polygon\",\"coordinates\":[["));
  const Point3 a = position(c[0]);
  put_position(w, a);
  w.put(',');
  put_position(w, position(c[1]));
  w.put(',');
  put_position(w, position(c[2]));
  w.put(',');
  put_position(w, a);
  w.put(std::string_view("]]}}"));
}

}  // namespace

OGRSpatialReference parse_crs(const std::string& path, const std::string& wkt, const char* what) {
  OGRSpatialReference srs;
  if (srs.SetFromUserInput(wkt.c_str()) != OGRERR_NONE)
    throw OutputError(
        path, "",
        std::string("cannot read ") + what + ": " + last_gdal_message("not a CRS OSR understands"));
  srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  return srs;
}

void put_position(BlockWriter& w, const Point3& p) {
  w.put('[');
  w.put_xyz(p, ',');
  w.put(']');
}

void put_feature_collection_start(BlockWriter& w, const std::string& path,
                                  const TinWriteOptions& options) {
  const bool reprojecting = !options.target_crs_wkt.empty();
  const std::string crs = crs_member(path, reprojecting ? options.target_crs_wkt : options.crs_wkt);
  w.put(std::string_view("{\n\"type\": \"FeatureCollection\",\n"));
  w.put(crs);
  // A foreign member (RFC 7946 section 6.1): the offset subtracted from every position. GDAL
  // ignores it.
  if (!is_zero(options.offset)) {
    w.put(std::string_view("\"tincdt_offset\": "));
    put_position(w, options.offset);
    w.put(std::string_view(",\n"));
  }
  w.put(std::string_view("\"features\": [\n"));
}

GeoJsonPositions::GeoJsonPositions(const std::string& path, const mesh::Triangulation& tin,
                                   const TinWriteOptions& options,
                                   const std::vector<VertexId>* only)
    : path_(path), tin_(tin), offset_(options.offset) {
  if (options.target_crs_wkt.empty()) return;
  const std::string& target_wkt = options.target_crs_wkt;
  std::string target_name = crs_label(target_wkt);
  if (target_name.empty()) target_name = "the target CRS";
  if (options.crs_wkt.empty())
    throw OutputError(path, "",
                      "cannot reproject to " + target_name + ": the CRS of the TIN is unknown");
  const GdalQuiet quiet;
  const OGRSpatialReference source = parse_crs(path, options.crs_wkt, "the CRS of the TIN");
  const OGRSpatialReference target = parse_crs(path, target_wkt, "the target CRS");
  if (source.IsSame(&target)) return;
  CPLErrorReset();
  const OgrTransform ct(OGRCreateCoordinateTransformation(&source, &target));
  if (!ct)
    throw OutputError(
        path, "",
        "no transformation to " + target_name + ": " + last_gdal_message("unknown reason"));

  // The vertices to transform, in separate x, y, z arrays as OSR wants them; ids[i] is the
  // vertex of entry i.
  std::vector<VertexId> ids;
  if (only != nullptr) {
    slot_.assign(tin.vertex_count(), kNoId);
    for (const VertexId v : *only) {
      if (slot_[v] != kNoId) continue;
      slot_[v] = static_cast<VertexId>(ids.size());
      ids.push_back(v);
    }
  }
  const std::size_t n = only != nullptr ? ids.size() : tin.vertex_count();
  const auto vertex = [&](std::size_t i) {
    return only != nullptr ? ids[i] : static_cast<VertexId>(i);
  };
  x_.resize(n);
  y_.resize(n);
  z_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const VertexId v = vertex(i);
    const Point2 p = tin.point(v);
    x_[i] = p.x;
    y_[i] = p.y;
    z_[i] = tin.z(v);
  }
  constexpr std::size_t kChunk = 1 << 16;
  std::vector<int> ok(kChunk);
  for (std::size_t first = 0; first < n; first += kChunk) {
    const std::size_t count = std::min(kChunk, n - first);
    std::fill(ok.begin(), ok.end(), 0);
    ct->Transform(static_cast<int>(count), x_.data() + first, y_.data() + first, z_.data() + first,
                  nullptr, ok.data());
    for (std::size_t i = 0; i < count; ++i)
      if (!ok[i])
        throw OutputError(path, "vertex " + std::to_string(vertex(first + i)),
                          "cannot be reprojected to " + target_name);
  }
  reprojected_ = true;
}

Point3 GeoJsonPositions::operator()(VertexId v) const {
  if (!reprojected_) return shifted_vertex(path_, tin_, v, offset_);
  const VertexId i = slot_.empty() ? v : slot_[v];
  const Point3 q{x_[i], y_[i], z_[i]};
  if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z))
    throw OutputError(path_, "vertex " + std::to_string(v), "coordinate is not a finite number");
  return q;
}

TinWriteStats write_geojson(OutputFile& out, const mesh::Triangulation& tin,
                            const TinWriteOptions& options) {
  const std::string& path = out.path();
  // With removed triangles, only the vertices of kept triangles are reprojected (and counted):
  // one outside the kept part may lie where the target CRS has no valid coordinates.
  const WrittenTin written(tin, options.threads);
  const VertexNumbering& used = written.number;
  // Position of vertex v as written: reprojected, or shifted by the offset (write_tin() refuses
  // the two together).
  const GeoJsonPositions position(path, tin, options,
                                  used.compacted() ? &used.vertices() : nullptr);

  BlockWriter w(out);
  const std::size_t slots = tin.triangle_slots();
  Progress progress(options.progress, "write", slots);
  put_feature_collection_start(w, path, options);
  const std::vector<std::uint64_t> first_id =
      kept_before_blocks(tin, records_per_block(kFeatureBytes), options.threads);
  write_blocks(w, options.threads, slots, kFeatureBytes, progress, 0,
               [&](BlockWriter& b, std::size_t begin, std::size_t end) {
                 std::uint64_t id = first_id[begin / records_per_block(kFeatureBytes)];
                 for_each_triangle_in(tin, begin, end,
                                      [&](TriangleId, const std::array<VertexId, 3>& c) {
                                        put_feature(b, id++, c, position);
                                      });
               });
  w.put(std::string_view("\n]\n}\n"));
  w.flush();
  progress.finish();
  return {used.count(), written.triangles, 0};
}

}  // namespace tincdt::io::detail
