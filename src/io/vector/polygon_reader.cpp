// Polygon and draped-line reader: see polygon_reader.hpp. Opening the source, choosing the layer
// and walking the geometries are shared with the contour reader (ogr_source.hpp), so that both
// accept the same specs and say the same things about them.
#include "io/vector/polygon_reader.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/coordinates.hpp"
#include "io/vector/ogr_source.hpp"

namespace tincdt::io {
namespace {

using detail::ZSource;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

enum class Kind { polygons, lines };

constexpr detail::DropReasons kPolygonDropReasons{"degenerate: no ring with 3 distinct vertices",
                                                  " geometry: only polygons are used",
                                                  "no usable geometry"};
constexpr detail::DropReasons kLineDropReasons{"degenerate: no line with 2 distinct vertices",
                                               " geometry: only lines and polygon rings are used",
                                               "no usable geometry"};

// Reads the features of one layer.
class LayerReader : public detail::FeatureReader {
 public:
  // Z_SOURCE: where each feature's one z comes from; none when it needs none.
  LayerReader(Kind kind, const detail::OgrLayer& layer, std::optional<ZSource> z_source,
              int z_field, std::uint32_t file_index, ShapeData& out, ShapeReadStats& stats)
      : FeatureReader(layer, z_field, file_index, kind == Kind::lines,
                      kind == Kind::polygons ? kPolygonDropReasons : kLineDropReasons, out.skipped,
                      out.dropped, stats.degenerate_parts),
        z_source_(z_source),
        out_(out),
        stats_(stats) {}

  void read_feature(const OGRFeature& feature, std::int64_t fid) {
    ++stats_.features;
    current_ = ShapeFeature{file_index(), fid, kNaN, {}};
    z_min_ = std::numeric_limits<double>::infinity();
    z_max_ = -z_min_;
    const OGRGeometry* geometry = walk(feature, fid);
    if (current_.parts.empty()) {
      ++stats_.empty_features;
      drop(geometry);
      return;
    }
    if (z_source_) current_.z = feature_z(feature);
    for (const ShapePart& part : current_.parts) {
      ++stats_.parts;
      stats_.vertices += part.points.size();
      stats_.segments += part.closed ? part.points.size() : part.points.size() - 1;
    }
    out_.features.push_back(std::move(current_));
  }

 private:
  void add_part(const Part& part) override {
    const std::size_t n = part.count;
    const bool has_z = part.has_z;
    const bool has_m = part.has_m;
    std::vector<Point3> p(n, Point3{0, 0, kNaN});
    std::vector<double> m(has_m ? n : 0);
    constexpr int kStride = static_cast<int>(sizeof(Point3));
    part.line.getPoints(&p[0].x, kStride, &p[0].y, kStride, has_z ? &p[0].z : nullptr, kStride,
                        has_m ? m.data() : nullptr, static_cast<int>(sizeof(double)));
    check_coordinates(p.data(), n, has_z);
    if (z_source_) note_heights(has_z, has_m, p, m);

    const Collapsed run = collapse(p.data(), n, part.ring);
    stats_.repeated_vertices += run.repeats;
    if (run.kept < (part.ring ? 3u : 2u)) {
      note_degenerate(p[0]);
      return;
    }
    p.resize(run.kept);
    current_.parts.push_back({std::move(p), run.closed});
  }

  // Remembers the range of the values a feature z could come from (M or Z).
  void note_heights(bool has_z, bool has_m, const std::vector<Point3>& p,
                    const std::vector<double>& m) {
    if (*z_source_ == ZSource::kField) return;
    check_z(*z_source_, has_z, has_m, "2D polygon has no z to replace with");
    if (*z_source_ == ZSource::kMeasure) {
      for (const double v : m) {
        if (!coordinate_in_range(v)) fail("an M value is not finite or beyond +-1e15");
        z_min_ = std::min(z_min_, v);
        z_max_ = std::max(z_max_, v);
      }
      return;
    }
    for (const Point3& q : p) {
      z_min_ = std::min(z_min_, q.z);
      z_max_ = std::max(z_max_, q.z);
    }
  }

  double feature_z(const OGRFeature& feature) const {
    if (*z_source_ == ZSource::kField) return field_z(feature);
    if (z_min_ != z_max_) {
      char range[96];
      std::snprintf(range, sizeof range, "%.17g to %.17g", z_min_, z_max_);
      fail(std::string("a replace polygon has one z, but its ") +
               (*z_source_ == ZSource::kMeasure ? "M values" : "vertices' z") + " range from " +
               range,
           Remedy::z_field);
    }
    return z_min_;
  }

  const std::optional<ZSource> z_source_;
  ShapeData& out_;
  ShapeReadStats& stats_;

  ShapeFeature current_;
  double z_min_ = 0, z_max_ = 0;
};

ShapeReadStats read_layer(Kind kind, const std::string& spec, const ShapeReadOptions& options,
                          ShapeData& out) {
  if (options.feature_z) detail::check_z_options(spec, options.z_field, options.z_from_m);
  detail::OgrLayer layer(spec, options.layer, out.files.size());
  ShapeReadStats stats;
  stats.layer = layer.name();
  stats.crs_wkt = layer.crs_wkt();
  int z_field = -1;
  std::optional<ZSource> z_source;
  if (options.feature_z) z_source = layer.choose_z(options.z_field, options.z_from_m, &z_field);
  layer.ignore_fields_except(z_field);  // only the geometry and the z field are needed

  const auto file_index = static_cast<std::uint32_t>(out.files.size());
  const std::size_t features_before = out.features.size(), dropped_before = out.dropped.size();
  LayerReader reader(kind, layer, z_source, z_field, file_index, out, stats);
  layer.read_features([&reader](const OGRFeature& feature, std::int64_t fid) {
    reader.read_feature(feature, fid);
  });

  out.files.push_back(layer.spec());
  layer.add_warnings(reader.curves(), stats.warnings);
  const bool polygons = kind == Kind::polygons;
  layer.check_usable({stats.features, out.features.size() - features_before, stats.degenerate_parts,
                      polygons ? "a polygon" : "a line", polygons ? "ring" : "line"},
                     out.dropped, dropped_before, stats.warnings);
  return stats;
}

ShapeReadStats read(Kind kind, const std::string& path, const ShapeReadOptions& options,
                    ShapeData& out) {
  const std::size_t features = out.features.size(), files = out.files.size(),
                    skipped = out.skipped.size(), dropped = out.dropped.size();
  try {
    return read_layer(kind, path, options, out);
  } catch (...) {
    out.features.resize(features);
    out.files.resize(files);
    out.skipped.resize(skipped);
    out.dropped.resize(dropped);
    throw;
  }
}

}  // namespace

ShapeReadStats read_polygons(const std::string& path, const ShapeReadOptions& options,
                             ShapeData& out) {
  return read(Kind::polygons, path, options, out);
}

ShapeReadStats read_shape_lines(const std::string& path, const ShapeReadOptions& options,
                                ShapeData& out) {
  return read(Kind::lines, path, options, out);
}

}  // namespace tincdt::io
