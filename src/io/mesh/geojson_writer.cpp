// GeoJSON: a FeatureCollection of one 3D Polygon per triangle (closed ring, counter-clockwise,
// as RFC 7946 asks), written directly with to_chars (building it through OGR is far too slow for
// millions of triangles). The CRS member and vertex positions defined here are shared with the
// constraint-line writer (constraint_writer.cpp). The CRS is written the way GDAL's
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

// Feature ID, the triangle with corners P: ",\n" before it but for the first.
void put_feature(BlockWriter& w, std::uint64_t id, const std::array<Point3, 3>& p) {
  if (id > 0) w.put(std::string_view(",\n"));
  w.put(std::string_view("{\"type\":\"Feature\",\"properties\":{\"id\":"));
  w.put_uint(id);
  w.put(std::string_view("},\"geometry\":{\"type\":\"Polygon\",\"coordinates\":[["));
  for (const Point3& q : p) {
    put_position(w, q);
    w.put(',');
  }
  put_position(w, p[0]);
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
  const std::string crs = crs_member(path, options.crs_wkt);
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

TinWriteStats write_geojson(OutputFile& out, const mesh::Triangulation& tin,
                            const TinWriteOptions& options) {
  const std::string& path = out.path();
  const WrittenTin written(tin, options.threads);
  const Point3& offset = options.offset;

  BlockWriter w(out);
  const std::size_t slots = tin.triangle_slots();
  Progress progress(options.progress, "write", slots);
  put_feature_collection_start(w, path, options);
  const std::vector<std::uint64_t> first_id =
      kept_before_blocks(tin, records_per_block(kFeatureBytes), options.threads);
  write_blocks(
      w, options.threads, slots, kFeatureBytes, progress, 0,
      [&](BlockWriter& b, std::size_t begin, std::size_t end) {
        std::uint64_t id = first_id[begin / records_per_block(kFeatureBytes)];
        for_each_triangle_in(tin, begin, end, [&](TriangleId, const std::array<VertexId, 3>& c) {
          // A braced list evaluates in order: the first bad corner is the one reported.
          put_feature(
              b, id++,
              {shifted_vertex(path, tin, c[0], offset), shifted_vertex(path, tin, c[1], offset),
               shifted_vertex(path, tin, c[2], offset)});
        });
      });
  w.put(std::string_view("\n]\n}\n"));
  w.flush();
  progress.finish();
  return {written.number.count(), written.triangles, 0};
}

}  // namespace tincdt::io::detail
