// The CRS a job's inputs are taken in. Each input's own CRS must be one a terrain TIN can be built
// in; the override CRS replaces every input's own, the default CRS is given to inputs without
// one; then every input has a CRS, or none has: a file's CRS is never guessed from the others'.
// The job's CRS is the target CRS when one is given (every input must then have a CRS), else the
// first input's; an input in another is transformed into it when read.
#pragma once

#include <initializer_list>
#include <map>
#include <memory>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "io/crs_transform.hpp"
#include "io/vector/line_reader.hpp"
#include "io/vector/polygon_reader.hpp"
#include "pipeline/job.hpp"

namespace tincdt::pipeline::detail {

class InputCrs {
 public:
  // Takes the override and default CRSs from JOB (--override-srs, --a-srs); messages go to its
  // log with its CRS names. ORDER: every input in reading order (point files, then vector
  // sources); the job's CRS is that of the first with a CRS in this order, whatever order the
  // inputs are added in (a LAS file's CRS is known before an XYZ file's before it).
  InputCrs(Job& job, std::vector<std::string> order);

  // Input PATH, whose own CRS is OWN ("" for none); IMPLIED: OWN is only its format's default
  // (a GeoJSON file that names no CRS), which counts as none beside inputs that name theirs. An
  // input added before is skipped (its header was read before its points). Throws InputError
  // (Remedy::override_crs) when OWN is not usable and nothing replaces it, and in a job that reads
  // its points by a box when the CRS it is taken in differs from the inputs' CRS found
  // so far or from the target CRS: the box is in one CRS. With a target CRS, throws InputError
  // (Remedy::assign_crs) when the input has no CRS: it cannot be transformed.
  void add(const std::string& path, const std::string& own, bool implied = false);

  // Throws InputError (Remedy::assign_crs) naming the first input without a CRS when another
  // has one.
  void check_none_without() const;

  // The x, y extent of input PATH's coordinates as read (POINTS), for finish() to check against
  // a CRS its format implies.
  void read_extent(const std::string& path, std::span<const Point3> points);

  // After every input: check_none_without(); then, when no input names a CRS, the one implied
  // (if any) is the inputs', and the inputs without a CRS take it, with a warning each; unless
  // the coordinates of one cannot be in it (projected metres in GeoJSON's default longitude and
  // latitude): then the job has no CRS, with a warning naming that input.
  void finish();

  // The job's CRS: the target CRS, else that of the inputs added so far, "" when none has one.
  // Final for an input once every input before it in reading order is added, as it is when the
  // input is read.
  const std::string& crs() const { return target().empty() ? crs_ : target(); }
  // The target CRS (the job's --t-srs), "" when none is given.
  const std::string& target() const { return job_.target_crs_wkt; }
  // The input the inputs' CRS comes from.
  const std::string& source() const { return source_; }
  // The CRS input PATH is taken in when it is not crs() (its points are to be transformed from
  // it), else "".
  const std::string& transform_from(const std::string& path) const;

 private:
  struct Implied {
    std::string path;
    std::string wkt;
  };
  // crs_ and source_ from taken_: the first input in order_ with a CRS.
  void settle_first();
  // Why input PATH, which names no CRS, cannot be in IMPLIED's: its coordinates are not
  // longitudes and latitudes; "" when they can be.
  std::string misfit(const std::string& path, const Implied& implied) const;
  // finish()'s warning when an input without a CRS of its own lies where the first implied CRS
  // cannot hold it, "" when none does.
  std::string implied_misfit() const;
  // transform_from() with a target CRS: from the CRS PATH is taken in, its format's default when
  // no input names its CRS (check_none_without() throws otherwise).
  const std::string& transform_to_target_from(const std::string& path) const;

  Job& job_;
  std::vector<std::string> order_;
  std::string crs_;
  std::string source_;  // the input the CRS comes from
  std::set<std::string> added_;
  std::map<std::string, std::string> taken_;  // path -> the CRS it is taken in, when it has one
  std::vector<std::string> without_crs_;
  std::vector<Implied> implied_;
  std::map<std::string, BBox> extents_;  // read_extent()
};

// The transformation of one input into the job's CRS, when InputCrs takes it in another: its
// points, line vertices and heights go through it.
class InputTransform {
 public:
  // For input PATH (after CRS.add(PATH, ...)): when it is in another CRS than the job's, logs one
  // info line naming both (and how heights are converted), and a warning when both CRSs have a
  // vertical part and they differ. Throws InputError when PROJ has no transformation.
  InputTransform(Job& job, const InputCrs& crs, const std::string& path);
  InputTransform(const InputTransform&) = delete;
  InputTransform& operator=(const InputTransform&) = delete;

  // Whether the input is in another CRS: false = nothing to do.
  bool active() const { return transform_ != nullptr; }
  // The heights' factor (1 when inactive).
  double z_factor() const { return transform_ ? transform_->z_factor() : 1.0; }
  // Transforms POINTS in place (on the job's threads); returns the index of the first that cannot
  // be transformed, whose coordinates are left as read, nullopt when all were.
  std::optional<std::size_t> apply(std::span<Point3> points) const;
  // apply() to POINTS from BEFORE on (the input's; those before are the inputs' before it), and
  // an InputError naming the file and "point N" for the first that fails, N counted from BEFORE.
  void apply_to_points(std::vector<Point3>& points, std::size_t before) const;

  // The sizes of a LineData's or ShapeData's lists before a source is read into it: what the
  // source appended comes after.
  struct Marks {
    std::size_t vertices = 0;  // LineData::vertices
    std::size_t features = 0;
    std::size_t skipped = 0;
    std::size_t dropped = 0;
  };
  static Marks marks(const io::LineData& lines);
  static Marks marks(const io::ShapeData& shapes);
  // What the source read from layer LAYER appended since BEFORE: vertices, the places of skipped
  // vertices and dropped features, and the features' levels. Throws InputError naming the file,
  // the layer and the feature of the first vertex that cannot be transformed. Each apply_to_*
  // warns when the input, transformed, lies far from the inputs read before it (the job's
  // points, and the lines before it): farther than the larger one's size, as an input whose CRS
  // is wrong does.
  void apply_to_lines(io::LineData& lines, const Marks& before, const std::string& layer) const;
  void apply_to_shapes(io::ShapeData& shapes, const Marks& before, const std::string& layer) const;

 private:
  // The text of an error for the point AT that cannot be transformed.
  std::string failure(const Point3& at) const;
  // Transforms the places of skipped vertices and dropped features from BEFORE on.
  void apply_to_places(std::vector<io::LineSkip>& skipped, std::vector<io::LineDrop>& dropped,
                       const Marks& before, const std::string& layer) const;
  // The warning of apply_to_*: MINE against the extent of every span of OTHERS.
  void warn_if_far(std::initializer_list<std::span<const Point3>> others,
                   std::span<const Point3> mine) const;
  [[noreturn]] void fail(const std::string& layer, std::int64_t fid, const Point3& at) const;

  const Job& job_;
  std::string path_;
  std::string from_, to_;  // the CRSs' names
  std::string to_wkt_;
  std::unique_ptr<io::CrsTransform> transform_;
};

}  // namespace tincdt::pipeline::detail
