// OGR line reader: see line_reader.hpp.
#include "io/vector/line_reader.hpp"

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "io/vector/ogr_source.hpp"

namespace tincdt::io {
namespace {

using detail::kMaxIndex;
using detail::ZSource;

constexpr detail::DropReasons kDropReasons{"degenerate: no line or ring with 2 distinct vertices",
                                           " geometry: only lines and polygon rings are used",
                                           "no line geometry"};

// Reads the features of one layer into LineData.
class LayerReader : public detail::FeatureReader {
 public:
  LayerReader(const detail::OgrLayer& layer, ZSource z_source, int z_field,
              std::uint32_t file_index, LineData& out, LineReadStats& stats)
      : FeatureReader(layer, z_field, file_index, true, kDropReasons, out.skipped, out.dropped,
                      stats.degenerate_parts),
        z_source_(z_source),
        out_(out),
        stats_(stats) {}

  void read_feature(const OGRFeature& feature, std::int64_t fid) {
    ++stats_.features;
    feature_ = &feature;
    have_z_ = false;
    const std::size_t segments_before = out_.segments.size();
    const OGRGeometry* geometry = walk(feature, fid);
    if (out_.segments.size() == segments_before) {
      ++stats_.empty_features;
      drop(geometry);
      return;
    }
    if (out_.features.size() >= kMaxIndex) fail("more than 2^32 - 1 features");
    out_.features.push_back(
        {file_index(), fid,
         z_source_ == ZSource::kField ? z_ : std::numeric_limits<double>::quiet_NaN()});
  }

 private:
  // The feature's z attribute, read once per feature and only when a line needs it.
  double feature_z() {
    if (!have_z_) {
      z_ = field_z(*feature_);
      have_z_ = true;
    }
    return z_;
  }

  void add_part(const Part& part) override {
    check_z(z_source_, part.has_z, part.has_m, "2D geometry has no elevation");
    const double z = z_source_ == ZSource::kField ? feature_z() : 0.0;

    std::vector<Point3>& v = out_.vertices;
    const std::size_t base = v.size();
    const std::size_t n = part.count;
    v.resize(base + n);
    Point3* p = v.data() + base;
    constexpr int kStride = static_cast<int>(sizeof(Point3));
    void* z_target = z_source_ == ZSource::kGeometry ? &p->z : nullptr;
    void* m_target = z_source_ == ZSource::kMeasure ? &p->z : nullptr;
    part.line.getPoints(&p->x, kStride, &p->y, kStride, z_target, kStride, m_target, kStride);
    if (z_source_ == ZSource::kField) {
      for (std::size_t i = 0; i < n; ++i) p[i].z = z;
    }
    check_coordinates(p, n, true);

    const Collapsed run = collapse(p, n, part.ring);
    stats_.repeated_vertices += run.repeats;
    stats_.zero_length_segments += run.repeats;
    const std::size_t k = run.kept;
    if (k < 2) {
      note_degenerate(p[0]);
      v.resize(base);
      return;
    }
    v.resize(base + k);
    if (v.size() - 1 > kMaxIndex) fail("more than 2^32 - 1 vertices");

    const auto first = static_cast<std::uint32_t>(base);
    const auto feature = static_cast<std::uint32_t>(out_.features.size());
    const std::size_t segment_count = run.closed ? k : k - 1;
    for (std::uint32_t i = 0; i + 1 < k; ++i) {
      out_.segments.push_back({first + i, first + i + 1, feature});
    }
    if (run.closed) {
      out_.segments.push_back({first + static_cast<std::uint32_t>(k - 1), first, feature});
      ++stats_.closed_parts;
    }
    stats_.vertices += k;
    stats_.segments += segment_count;
  }

  const ZSource z_source_;
  LineData& out_;
  LineReadStats& stats_;

  const OGRFeature* feature_ = nullptr;
  bool have_z_ = false;
  double z_ = 0.0;
};

LineReadStats read_layer(const std::string& spec, const LineReadOptions& options, LineData& out) {
  detail::check_z_options(spec, options.z_field, options.z_from_m);
  detail::OgrLayer layer(spec, options.layer, out.files.size());
  LineReadStats stats;
  stats.layer = layer.name();
  stats.crs_wkt = layer.crs_wkt();
  int z_field = -1;
  const ZSource z_source = layer.choose_z(options.z_field, options.z_from_m, &z_field);
  // Only the geometry and the z field are needed: the drivers may skip the rest.
  layer.ignore_fields_except(z_field);

  // No reserve() from the layer's feature count: a file may state any count (a GeoPackage's
  // gpkg_ogr_contents says what it likes), and the features arrive one by one anyway.
  const auto file_index = static_cast<std::uint32_t>(out.files.size());
  const std::size_t features_before = out.features.size(), dropped_before = out.dropped.size();
  LayerReader reader(layer, z_source, z_field, file_index, out, stats);
  layer.read_features([&reader](const OGRFeature& feature, std::int64_t fid) {
    reader.read_feature(feature, fid);
  });

  out.files.push_back(layer.spec());
  layer.add_warnings(reader.curves(), stats.warnings);
  layer.check_usable({stats.features, out.features.size() - features_before, stats.degenerate_parts,
                      "a line", "line"},
                     out.dropped, dropped_before, stats.warnings);
  return stats;
}

}  // namespace

LineReadStats read_lines(const std::string& path, const LineReadOptions& options, LineData& out) {
  const std::size_t vertices = out.vertices.size();
  const std::size_t segments = out.segments.size();
  const std::size_t features = out.features.size();
  const std::size_t files = out.files.size();
  const std::size_t skipped = out.skipped.size();
  const std::size_t dropped = out.dropped.size();
  try {
    return read_layer(path, options, out);
  } catch (...) {
    out.vertices.resize(vertices);
    out.segments.resize(segments);
    out.features.resize(features);
    out.files.resize(files);
    out.skipped.resize(skipped);
    out.dropped.resize(dropped);
    throw;
  }
}

}  // namespace tincdt::io
