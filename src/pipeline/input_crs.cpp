#include "pipeline/input_crs.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <utility>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "io/crs.hpp"
#include "io/raster/dem_writer.hpp"

namespace tincdt::pipeline::detail {

InputCrs::InputCrs(Job& job, std::vector<std::string> order)
    : job_(job), order_(std::move(order)) {}

void InputCrs::add(const std::string& path, const std::string& own, bool implied) {
  if (!added_.insert(path).second) return;
  CrsNames& names = job_.crs_names;
  std::string taken = own;
  if (!job_.override_crs_wkt.empty()) {
    taken = job_.override_crs_wkt;
    if (!own.empty() && !io::same_crs(own, taken))
      job_.debug(path + ": its CRS " + names.name(own) + " replaced by " + names.name(taken));
  } else if (own.empty() || implied) {
    taken = job_.assign_crs_wkt;
    if (taken.empty() && implied) {
      implied_.push_back({path, own});
      return;
    }
  } else if (const std::string why = io::crs_unusable_reason(own); !why.empty()) {
    throw InputError(path, "", "its CRS " + names.name(own) + " cannot be used: " + why,
                     Remedy::override_crs);
  }
  if (taken.empty() && !target().empty())
    throw InputError(path, "",
                     "no CRS in the file, so it cannot be transformed into the target CRS " +
                         names.name(target()),
                     Remedy::assign_crs);
  if (taken.empty()) {
    without_crs_.push_back(path);
    return;
  }
  if (job_.options.filter.box && !target().empty() && !io::same_crs(target(), taken)) {
    const std::string mine = names.name(taken), theirs = names.name(target());
    throw InputError(path, "",
                     "CRS " + mine + " differs from the target CRS " + theirs +
                         (mine == theirs ? " (same name, different definition)" : "") +
                         ": a job that reads its points by a box reads them in the box's CRS, "
                         "its inputs'",
                     Remedy::target_after_merge);
  }
  if (job_.options.filter.box && !crs_.empty() && !io::same_crs(crs_, taken)) {
    const std::string mine = names.name(taken), theirs = names.name(crs_);
    throw InputError(path, "",
                     "CRS " + mine + " differs from " + theirs + " of " + source_ +
                         (mine == theirs ? " (same name, different definition)" : "") +
                         " (a job that reads its points by a box takes them in one CRS: "
                         "reproject one of them)",
                     Remedy::override_crs);
  }
  taken_[path] = std::move(taken);
  settle_first();
}

void InputCrs::settle_first() {
  for (const std::string& path : order_) {
    const auto it = taken_.find(path);
    if (it == taken_.end()) continue;
    crs_ = it->second;
    source_ = path;
    return;
  }
  assert(taken_.empty() && "every input is in the reading order");
}

const std::string& InputCrs::transform_from(const std::string& path) const {
  static const std::string none;
  if (!target().empty()) return transform_to_target_from(path);
  const auto it = taken_.find(path);
  if (it == taken_.end() || path == source_ || io::same_crs(crs_, it->second)) return none;
  return it->second;
}

const std::string& InputCrs::transform_to_target_from(const std::string& path) const {
  static const std::string none;
  const std::string* from = nullptr;
  if (const auto it = taken_.find(path); it != taken_.end()) from = &it->second;
  for (const Implied& implied : implied_) {
    if (implied.path != path) continue;
    check_none_without();  // its format's default counts only when no input names its CRS
    if (const std::string why = misfit(path, implied); !why.empty())
      throw InputError(path, "",
                       why + ", so it cannot be transformed into the target CRS " +
                           job_.crs_names.name(target()),
                       Remedy::assign_crs);
    from = &implied.wkt;
  }
  assert(from != nullptr && "with a target CRS, add() refuses an input without a CRS");
  return from == nullptr || io::same_crs(target(), *from) ? none : *from;
}

void InputCrs::check_none_without() const {
  if (crs_.empty()) return;
  const std::string known = source_ + " is in " + job_.crs_names.name(crs_);
  if (!without_crs_.empty())
    throw InputError(without_crs_.front(), "",
                     "no CRS in the file, while " + known + " (a file's CRS is not guessed)",
                     Remedy::assign_crs);
  if (!implied_.empty())
    throw InputError(implied_.front().path, "",
                     "the file names no CRS (GeoJSON's default would be " +
                         job_.crs_names.name(implied_.front().wkt) + "), while " + known +
                         " (a file's CRS is not guessed)",
                     Remedy::assign_crs);
}

void InputCrs::read_extent(const std::string& path, std::span<const Point3> points) {
  BBox& box = extents_[path];
  for (const Point3& p : points) box.add(p.x, p.y);
}

std::string InputCrs::misfit(const std::string& path, const Implied& implied) const {
  if (!io::is_geographic(implied.wkt)) return {};
  const auto it = extents_.find(path);
  if (it == extents_.end()) return {};
  const BBox& b = it->second;
  if (!(b.min_x <= b.max_x)) return {};  // nothing read
  if (b.min_x >= -180 && b.max_x <= 360 && b.min_y >= -90 && b.max_y <= 90) return {};
  return "no CRS in the file, and its coordinates (x " + number_text(b.min_x) + " to " +
         number_text(b.max_x) + ", y " + number_text(b.min_y) + " to " + number_text(b.max_y) +
         ") are not longitudes and latitudes: " +
         (path == implied.path ? "its format's default "
                               : "the default of " + implied.path + ", ") +
         job_.crs_names.name(implied.wkt) + ", is not assumed";
}

std::string InputCrs::implied_misfit() const {
  for (const std::string& path : order_) {
    if (taken_.contains(path)) continue;
    if (const std::string why = misfit(path, implied_.front()); !why.empty())
      return path + ": " + why + ", and the TIN has no CRS";
  }
  return {};
}

void InputCrs::finish() {
  check_none_without();
  if (!crs_.empty() || implied_.empty()) return;
  if (const std::string why = implied_misfit(); !why.empty()) {
    job_.warn(why);
    return;
  }
  crs_ = implied_.front().wkt;
  source_ = implied_.front().path;
  for (const Implied& other : implied_) {
    if (io::same_crs(other.wkt, crs_)) continue;
    throw InputError(other.path, "",
                     "its default CRS " + job_.crs_names.name(other.wkt) + " differs from " +
                         job_.crs_names.name(crs_) + " of " + source_,
                     Remedy::assign_crs);
  }
  for (const std::string& path : without_crs_)
    job_.warn(path + ": no CRS in the file; assuming " + job_.crs_names.name(crs_) + " of " +
              source_ + ", which names none either (its format's default)");
}

InputTransform::InputTransform(Job& job, const InputCrs& crs, const std::string& path)
    : job_(job), path_(path) {
  const std::string& from = crs.transform_from(path);
  if (from.empty()) return;
  transform_ = std::make_unique<io::CrsTransform>(from, crs.crs(), path);
  to_wkt_ = crs.crs();
  from_ = job.crs_names.name(from);
  to_ = job.crs_names.name(crs.crs());
  std::string heights;
  if (transform_->z_factor() != 1)
    heights = "; heights converted from " + transform_->from_height_unit() + " to " +
              transform_->to_height_unit();
  const std::string whose = crs.target().empty() ? "the CRS of " + crs.source() : "the target CRS";
  job.info(path + ": transformed from " + from_ + " to " + to_ + " (" + whose +
           (from_ == to_ ? ", same name, different definition" : "") + ")" + heights);
  if (!transform_->vertical_mismatch().empty())
    job.warn(path + ": heights are not transformed between the vertical CRSs (" +
             transform_->vertical_mismatch() + "), only converted in unit");
}

std::optional<std::size_t> InputTransform::apply(std::span<Point3> points) const {
  if (!transform_) return std::nullopt;
  return transform_->apply(points, job_.options.threads);
}

std::string InputTransform::failure(const Point3& at) const {
  char where[64];
  std::snprintf(where, sizeof where, "%.12g %.12g", at.x, at.y);
  return std::string("at ") + where + ": cannot be transformed from " + from_ + " to " + to_;
}

void InputTransform::apply_to_points(std::vector<Point3>& points, std::size_t before) const {
  if (!transform_) return;
  const std::span<Point3> mine = std::span(points).subspan(before);
  if (const std::optional<std::size_t> bad = apply(mine))
    throw InputError(path_, "point " + std::to_string(*bad), failure(mine[*bad]));
  warn_if_far({std::span<const Point3>(points).first(before)}, mine);
}

namespace {

BBox extent_of(std::initializer_list<std::span<const Point3>> spans) {
  BBox box;
  for (const std::span<const Point3> points : spans)
    for (const Point3& p : points) box.add(p.x, p.y);
  return box;
}

double diagonal(const BBox& b) {
  return std::hypot(b.max_x - b.min_x, b.max_y - b.min_y);
}

}  // namespace

void InputTransform::warn_if_far(std::initializer_list<std::span<const Point3>> others,
                                 std::span<const Point3> mine) const {
  const BBox a = extent_of(others), b = extent_of({mine});
  if (!(a.min_x <= a.max_x) || !(b.min_x <= b.max_x)) return;  // one is empty
  const double gap_x = std::max({0.0, a.min_x - b.max_x, b.min_x - a.max_x});
  const double gap_y = std::max({0.0, a.min_y - b.max_y, b.min_y - a.max_y});
  const double gap = std::hypot(gap_x, gap_y);
  if (!(gap > std::max(diagonal(a), diagonal(b)))) return;
  const std::string unit = io::crs_unit_name(to_wkt_);
  job_.warn(path_ + ": transformed from " + from_ + " to " + to_ + ", it lies " + number_text(gap) +
            (unit.empty() ? "" : " (in " + unit + ")") +
            " from the inputs before it, farther than their size or its own: is its CRS right?");
}

InputTransform::Marks InputTransform::marks(const io::LineData& lines) {
  return {lines.vertices.size(), lines.features.size(), lines.skipped.size(), lines.dropped.size()};
}

InputTransform::Marks InputTransform::marks(const io::ShapeData& shapes) {
  return {0, shapes.features.size(), shapes.skipped.size(), shapes.dropped.size()};
}

void InputTransform::fail(const std::string& layer, std::int64_t fid, const Point3& at) const {
  throw InputError(path_, "layer " + layer + ", feature " + std::to_string(fid), failure(at));
}

void InputTransform::apply_to_places(std::vector<io::LineSkip>& skipped,
                                     std::vector<io::LineDrop>& dropped, const Marks& before,
                                     const std::string& layer) const {
  std::vector<Point3> places;
  std::vector<std::int64_t> fids;
  for (std::size_t i = before.skipped; i < skipped.size(); ++i) {
    places.push_back(skipped[i].at);
    fids.push_back(skipped[i].fid);
  }
  for (std::size_t i = before.dropped; i < dropped.size(); ++i) {
    if (!dropped[i].has_at) continue;
    places.push_back(dropped[i].at);
    fids.push_back(dropped[i].fid);
  }
  if (const std::optional<std::size_t> bad = apply(places)) fail(layer, fids[*bad], places[*bad]);
  std::size_t next = 0;
  for (std::size_t i = before.skipped; i < skipped.size(); ++i) skipped[i].at = places[next++];
  for (std::size_t i = before.dropped; i < dropped.size(); ++i)
    if (dropped[i].has_at) dropped[i].at = places[next++];
}

void InputTransform::apply_to_lines(io::LineData& lines, const Marks& before,
                                    const std::string& layer) const {
  if (!transform_) return;
  const std::span<Point3> vertices = std::span(lines.vertices).subspan(before.vertices);
  if (const std::optional<std::size_t> bad = apply(vertices)) {
    const std::size_t vertex = before.vertices + *bad;
    std::int64_t fid = -1;
    for (const io::LineData::Segment& s : lines.segments)
      if (s.a == vertex || s.b == vertex) {
        fid = lines.features[s.feature].fid;
        break;
      }
    fail(layer, fid, vertices[*bad]);
  }
  for (std::size_t f = before.features; f < lines.features.size(); ++f)
    lines.features[f].z *= transform_->z_factor();  // NaN (no level) stays NaN
  apply_to_places(lines.skipped, lines.dropped, before, layer);
  warn_if_far({job_.points, std::span<const Point3>(lines.vertices).first(before.vertices)},
              vertices);
}

void InputTransform::apply_to_shapes(io::ShapeData& shapes, const Marks& before,
                                     const std::string& layer) const {
  if (!transform_) return;
  // Every point of the new features in one list, so that PROJ is set up once, not per part.
  std::vector<Point3> points;
  for (std::size_t f = before.features; f < shapes.features.size(); ++f)
    for (const io::ShapePart& part : shapes.features[f].parts)
      points.insert(points.end(), part.points.begin(), part.points.end());
  if (const std::optional<std::size_t> bad = apply(points)) {
    std::size_t seen = 0;
    for (std::size_t f = before.features; f < shapes.features.size(); ++f)
      for (const io::ShapePart& part : shapes.features[f].parts) {
        seen += part.points.size();
        if (*bad < seen) fail(layer, shapes.features[f].fid, points[*bad]);
      }
  }
  std::size_t next = 0;
  for (std::size_t f = before.features; f < shapes.features.size(); ++f) {
    io::ShapeFeature& feature = shapes.features[f];
    feature.z *= transform_->z_factor();
    for (io::ShapePart& part : feature.parts)
      for (Point3& p : part.points) p = points[next++];
  }
  apply_to_places(shapes.skipped, shapes.dropped, before, layer);
  warn_if_far({job_.points}, points);
}

}  // namespace tincdt::pipeline::detail
