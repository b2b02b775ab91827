// GeoPackage through OGR: one layer "tin" of POLYGON Z features, one per kept triangle (closed
// ring, counter-clockwise seen from above), with the CRS; or, with TinWriteOptions::ogr_tin, one
// TIN Z feature per triangle (GDAL writes GeoPackage TINs as an extension type, which not every
// reader knows). The features go in through one OGR feature and geometry reused for all, in
// transactions of kBatch features, then their spatial index is packed in one pass
// (gpkg_rtree.hpp). GDAL builds the GeoPackage at the OutputFile's take_path(),
// so it moves into place with the run's other outputs. A GeoPackage keeps real coordinates: a
// non-zero offset is refused (write_tin).
#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "core/number_text.hpp"
#include "io/gdal_support.hpp"
#include "io/mesh/gpkg_rtree.hpp"
#include "io/mesh/writer_detail.hpp"

namespace tincdt::io::detail {
namespace {

// Features per transaction: SQLite keeps a transaction's pages in its cache until the commit.
constexpr std::uint64_t kBatch = 200000;

}  // namespace

TinWriteStats write_gpkg(OutputFile& out, const mesh::Triangulation& tin,
                         const TinWriteOptions& options) {
  const std::string& path = out.path();
  const TriangleCounts counts = count_triangles(tin);
  const VertexNumbering number(tin, counts.removed > 0);  // only to count the vertices used
  const GdalQuiet quiet;
  register_gdal_drivers();
  std::optional<OGRSpatialReference> srs;
  if (!options.crs_wkt.empty()) srs.emplace(parse_crs(path, options.crs_wkt, "the CRS"));
  const auto fail = [&path](const std::string& where, const std::string& what) {
    throw OutputError(path, where, what + ": " + last_gdal_message("GDAL gave no reason"));
  };

  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GPKG");
  if (driver == nullptr) throw OutputError(path, "", "GDAL has no GeoPackage driver");
  {
    GdalDataset ds(driver->Create(out.take_path().c_str(), 0, 0, 0, GDT_Unknown, nullptr));
    if (!ds) fail("", "cannot create the GeoPackage");
    const char* const layer_options[] = {"DESCRIPTION=TIN triangles written by tincdt",
                                         "SPATIAL_INDEX=NO", nullptr};  // packed below
    OGRLayer* layer =
        ds->CreateLayer("tin", srs ? &*srs : nullptr, options.ogr_tin ? wkbTINZ : wkbPolygon25D,
                        const_cast<char**>(layer_options));
    if (layer == nullptr) fail("", "cannot create the layer");

    const OgrFeature feature(OGRFeature::CreateFeature(layer->GetLayerDefn()));
    OGRPolygon polygon;
    OGRTriangulatedSurface surface;
    OGRLinearRing ring;
    ring.setNumPoints(4);
    std::uint64_t written = 0;
    if (ds->StartTransaction(FALSE) != OGRERR_NONE) fail("", "cannot start a transaction");
    // In the order of their lowest corner, which follows the vertices' spatial (Hilbert) order:
    // neighbours in the table are neighbours on the ground, and consecutive rows make the
    // leaves of the spatial index.
    std::vector<std::uint32_t> first(tin.vertex_count() + 1, 0);
    tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& c) {
      ++first[std::min({c[0], c[1], c[2]}) + 1];
    });
    for (std::size_t v = 0; v < tin.vertex_count(); ++v) first[v + 1] += first[v];
    std::vector<TriangleId> order(first.back());
    tin.for_each_triangle([&](TriangleId t, const std::array<VertexId, 3>& c) {
      order[first[std::min({c[0], c[1], c[2]})]++] = t;
    });
    std::vector<std::uint32_t>().swap(first);
    Progress progress(options.progress, "write", order.size());
    for (const TriangleId t : order) {
      progress.tick(written);
      const auto c = tin.triangle(t);
      for (int i = 0; i < 3; ++i) {
        const Point3 p = shifted_vertex(path, tin, c[i], options.offset);
        ring.setPoint(i, p.x, p.y, p.z);
        if (i == 0) ring.setPoint(3, p.x, p.y, p.z);
      }
      if (options.ogr_tin) {
        OGRTriangle triangle;
        triangle.addRing(&ring);
        surface.empty();
        surface.addGeometry(&triangle);
        feature->SetGeometry(&surface);
      } else {
        polygon.empty();
        polygon.addRing(&ring);
        feature->SetGeometry(&polygon);
      }
      feature->SetFID(OGRNullFID);
      if (layer->CreateFeature(feature.get()) != OGRERR_NONE)
        fail("triangle " + count_text(t), "cannot write the feature");
      if (++written % kBatch == 0 &&
          (ds->CommitTransaction() != OGRERR_NONE || ds->StartTransaction(FALSE) != OGRERR_NONE))
        fail("", "cannot commit a transaction");
    }
    if (ds->CommitTransaction() != OGRERR_NONE) fail("", "cannot commit the transaction");
    const auto envelope = [&](std::uint64_t k) {
      const auto c = tin.triangle(order[k]);
      Envelope e{INFINITY, -INFINITY, INFINITY, -INFINITY};
      for (const VertexId v : c) {
        const Point3 p = shifted_vertex(path, tin, v, options.offset);  // as written
        e = {std::min(e.min_x, p.x), std::max(e.max_x, p.x), std::min(e.min_y, p.y),
             std::max(e.max_y, p.y)};
      }
      return e;
    };
    if (!write_gpkg_rtree(*ds, "tin", layer->GetGeometryColumn(), written, envelope))
      fail("", "cannot write the spatial index");
    progress.finish();
    CPLErrorReset();
    ds.reset();
    if (CPLGetLastErrorType() == CE_Failure || CPLGetLastErrorType() == CE_Fatal)
      fail("", "cannot complete the GeoPackage");
  }
  out.close();  // moves GDAL's file over the temporary
  return {number.count(), counts.kept, out.bytes_written()};
}

}  // namespace tincdt::io::detail
