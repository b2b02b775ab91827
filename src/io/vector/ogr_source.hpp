// Private to the OGR readers (line_reader.cpp, polygon_reader.cpp): opening a vector source with
// GDAL's messages captured, splitting "FILE:LAYER", choosing the layer, resolving the z source,
// and walking a feature's lines and rings with the skipped / dropped records both keep. Both
// readers go through here so that they accept the same specs and say the same things about them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/types.hpp"
#include "io/gdal_support.hpp"
#include "io/vector/line_reader.hpp"

namespace tincdt::io::detail {

// Most files, features and vertices one LineData / ShapeData can index.
constexpr std::uint64_t kMaxIndex = std::numeric_limits<std::uint32_t>::max();

// Where a feature's z comes from.
enum class ZSource { kGeometry, kField, kMeasure };

// Throws InputError naming SPEC when both a z field and z from M values are asked for.
void check_z_options(const std::string& spec, const std::string& z_field, bool z_from_m);

// One layer of an OGR vector source, open for reading, with GDAL's messages captured for the
// object's life.
class OgrLayer {
 public:
  // SPEC is "FILE" or "FILE:LAYER", split at its last ':' only when the whole does not exist and
  // the part before the ':' does (so "C:\dir\a.shp" or "/vsicurl/https://..." stay whole);
  // LAYER_OPTION wins over a ":LAYER" when set. Without a layer name the source must have
  // exactly one layer. FILES_READ: how many files the caller's data already holds. Throws
  // InputError naming the file for an unreadable source, a missing or ambiguous layer, too many
  // files.
  OgrLayer(const std::string& spec, const std::string& layer_option, std::size_t files_read);
  OgrLayer(const OgrLayer&) = delete;
  OgrLayer& operator=(const OgrLayer&) = delete;

  OGRLayer& get() const { return *layer_; }
  const std::string& file() const { return spec_.file; }
  const std::string& name() const { return name_; }      // the layer's own name
  const std::string& fields() const { return fields_; }  // "a, b", or "none"
  std::string spec() const;                              // file, and ":layer" when one was named
  std::string crs_wkt() const;                           // WKT2 (WKT1 if OSR cannot); "" for none
  // The format's default CRS when the file names none (GeoJSON: WGS 84; crs_wkt() gives it too),
  // "" otherwise.
  std::string implied_crs_wkt() const;

  // The z source the options name: the field, else the M values, else the geometry's Z; *FIELD
  // is the field's index (-1 when none). Throws InputError for a missing field or one that holds
  // neither numbers nor text.
  ZSource choose_z(const std::string& z_field, bool z_from_m, int* field) const;

  // Lets the driver skip every attribute but field KEEP (-1: keep none).
  void ignore_fields_except(int keep) const;

  // READ(feature, fid) for each feature in order (fid: the OGR id, else the ordinal). Throws
  // InputError when the driver fails in the middle of the layer.
  template <class Read>
  void read_features(Read&& read) {
    layer_->ResetReading();
    messages_.reset_failure();
    std::int64_t ordinal = 0;
    std::int64_t last_fid = -1;
    for (;;) {
      const OgrFeature feature(layer_->GetNextFeature());
      if (!feature) break;
      const GIntBig fid = feature->GetFID();
      last_fid = fid != OGRNullFID ? static_cast<std::int64_t>(fid) : ordinal;
      ++ordinal;
      read(*feature, last_fid);
      if (messages_.failed()) break;
    }
    if (messages_.failed()) reading_failed(last_fid);
  }

  // GDAL's warnings, each naming the file, and one for CURVES geometries approximated.
  void add_warnings(std::uint64_t curves, std::vector<std::string>& warnings) const;

  // What the layer gave the reader, for check_usable.
  struct Yield {
    std::uint64_t features = 0;          // in the layer
    std::uint64_t used = 0;              // with at least one usable part
    std::uint64_t degenerate_parts = 0;  // skipped for too few distinct vertices
    const char* what = "";               // what a used feature gave: "a line", "a polygon"
    const char* part = "";               // "line", "ring"
  };
  // A layer that gave nothing usable is an InputError saying why (an empty layer, or the drop
  // reasons and their counts); one that lost features or parts adds a warning with the counts
  // (the features are listed by --diagnostics). DROPPED[FIRST, end): this layer's dropped ones.
  void check_usable(const Yield& yield, const std::vector<LineDrop>& dropped, std::size_t first,
                    std::vector<std::string>& warnings) const;

 private:
  struct Spec {
    std::string file;
    std::string layer;  // as named, "" when none
  };
  static Spec prepare(const std::string& spec, const std::string& layer_option,
                      std::size_t files_read);
  static GdalDataset open(const std::string& file);
  [[noreturn]] void reading_failed(std::int64_t last_fid) const;
  bool crs_implied() const;

  // In this order: the spec is split and the drivers registered before GDAL's messages are
  // captured, and the dataset is closed while they still are.
  const Spec spec_;
  GdalMessages messages_;
  const GdalDataset ds_;
  OGRLayer* layer_ = nullptr;
  std::string name_;
  OGRFeatureDefn* defn_ = nullptr;
  std::string fields_;
};

// The texts of a dropped feature's reason that depend on what the reader uses.
struct DropReasons {
  const char* degenerate;   // no usable part, e.g. "degenerate: no line with 2 distinct vertices"
  const char* unsupported;  // after a geometry name, e.g. " geometry: only polygons are used"
  const char* none;         // neither, e.g. "no usable geometry"
};

// What both layer readers do per feature: walk its geometry (linearizing curves) down to lines
// and rings, collapse repeated vertices into `skipped`, record a feature without a usable part
// in `dropped`, read the z field, and throw InputError naming the file, layer and feature.
class FeatureReader {
 public:
  FeatureReader(const FeatureReader&) = delete;
  FeatureReader& operator=(const FeatureReader&) = delete;

  std::uint64_t curves() const { return curves_; }  // curved geometries approximated

 protected:
  // Z_FIELD: the index of the z field, -1 when none. TAKE_LINES: LineStrings are parts too
  // (else only polygon rings are, and lines are unsupported geometries). DEGENERATE_PARTS: the
  // caller's count of parts without enough distinct vertices.
  FeatureReader(const OgrLayer& layer, int z_field, std::uint32_t file_index, bool take_lines,
                const DropReasons& reasons, std::vector<LineSkip>& skipped,
                std::vector<LineDrop>& dropped, std::uint64_t& degenerate_parts);
  virtual ~FeatureReader() = default;

  // One line (ring false) or polygon ring (ring true) of the feature being read.
  struct Part {
    const OGRSimpleCurve& line;
    std::size_t count;  // vertices, at least 1 (a part without any is degenerate already)
    bool has_z;
    bool has_m;
    bool ring;
  };
  virtual void add_part(const Part& part) = 0;

  // Starts feature FID: calls add_part for each of its lines and rings; returns its geometry.
  const OGRGeometry* walk(const OGRFeature& feature, std::int64_t fid);
  // Records the feature as dropped, with why (GEOMETRY: what walk returned).
  void drop(const OGRGeometry* geometry);

  [[noreturn]] void fail(const std::string& detail, Remedy remedy = Remedy::none) const;
  // Throws unless z can come from SOURCE for a part with(out) Z and M values; NO_Z_WHAT starts
  // the message for a 2D part that needs the geometry's Z ("2D geometry has no elevation").
  void check_z(ZSource source, bool has_z, bool has_m, const char* no_z_what) const;
  // The value of the z field in FEATURE; throws when it is NULL, not a complete number or not
  // finite.
  double field_z(const OGRFeature& feature) const;
  // Throws for an x or y (or z when CHECK_Z) that is not finite or beyond +-kMaxCoordinate
  // (core/coordinates.hpp), naming the vertex; makes every -0 a +0.
  void check_coordinates(Point3* p, std::size_t n, bool check_z) const;

  struct Collapsed {
    std::size_t kept;     // distinct vertices left in p[0, kept)
    std::size_t repeats;  // consecutive repeats collapsed
    bool closed;          // a ring, or a line that ends where it starts (never for 2 vertices)
  };
  // Collapses runs of the same x, y in p[0, n) (keeping the first z), recording each collapsed
  // vertex in `skipped`, and drops a last vertex equal to the first.
  Collapsed collapse(Point3* p, std::size_t n, bool ring);
  // A part without enough distinct vertices, the first at AT: counted, and remembered for the
  // dropped-feature record.
  void note_degenerate(const Point3& at);

  std::uint32_t file_index() const { return file_index_; }

 private:
  void add_geometry(const OGRGeometry& g);
  void take_part(const OGRSimpleCurve& g, bool ring);
  void note_location(const Point3& p);
  void note_unsupported(const OGRGeometry& g);
  std::string drop_reason(const OGRGeometry* geometry) const;

  const std::string file_;
  const std::string layer_;
  const std::string fields_;
  const int z_field_;
  const std::uint32_t file_index_;
  const bool take_lines_;
  const DropReasons reasons_;
  std::vector<LineSkip>& skipped_;
  std::vector<LineDrop>& dropped_;
  std::uint64_t& degenerate_parts_;

  std::int64_t fid_ = 0;
  std::uint64_t curves_ = 0;
  // What made the current feature useless, for `dropped`.
  std::string unsupported_;  // name of the first geometry type not read, "" when none
  bool degenerate_ = false;  // a part with too few distinct vertices
  bool has_at_ = false;
  Point3 at_{0, 0, 0};
};

}  // namespace tincdt::io::detail
