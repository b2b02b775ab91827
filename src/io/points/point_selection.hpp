// Private to src/io/points: the class and return filters of the LAS and LAZ readers, flattened
// for their inner loops, and the scale/offset that turns record integers into coordinates.
// Header-only so that it needs no entry in the module's source list.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

#include "core/coordinates.hpp"
#include "core/error.hpp"
#include "io/points/point_reader.hpp"

namespace tincdt::io::detail {

struct Selection {
  std::array<bool, 256> class_kept{};
  bool filter_classes = false;
  bool first_only = false;
  bool last_only = false;

  explicit Selection(const PointFilter& filter) {
    class_kept.fill(filter.keep_classes.empty());
    for (std::uint8_t c : filter.keep_classes) class_kept[c] = true;
    for (std::uint8_t c : filter.drop_classes) class_kept[c] = false;
    filter_classes = !filter.keep_classes.empty() || !filter.drop_classes.empty();
    first_only = filter.first_return_only;
    last_only = filter.last_return_only;
  }

  bool any() const { return filter_classes || first_only || last_only; }

  // Whether a point of class CLS, return RET of NRET passes.
  bool keeps(unsigned cls, unsigned ret, unsigned nret) const {
    if (!class_kept[cls & 0xFFu]) return false;
    // A record with return number or number of returns 0 (a writer that never filled them)
    // counts as a single return: both first and last.
    const bool single = ret == 0 || nret == 0;
    if (first_only && !single && ret != 1) return false;
    if (last_only && !single && ret < nret) return false;
    return true;
  }
};

// Record integers to coordinates: x = X * scale + offset, the same expression for every reader
// so that a LAZ file and its LAS twin give bit-identical points.
struct Transform {
  double sx, sy, sz, ox, oy, oz;
  Point3 apply(std::int32_t x, std::int32_t y, std::int32_t z) const {
    return {x * sx + ox, y * sy + oy, z * sz + oz};
  }

  // Whether every coordinate the scale and offset can give is in range, whatever the records
  // say: when false, each point must be checked (check_range).
  bool in_range_by_header() const {
    const double largest = 2147483648.0;  // |int32|
    return std::fabs(ox) + std::fabs(sx) * largest <= kMaxCoordinate &&
           std::fabs(oy) + std::fabs(sy) * largest <= kMaxCoordinate &&
           std::fabs(oz) + std::fabs(sz) * largest <= kMaxCoordinate;
  }

  // Throws for a coordinate of P beyond the range tincdt computes with, naming the header's
  // scale and offset that make it; WHERE names the record.
  void check_range(const Point3& p, const std::string& path, const std::string& where) const {
    const double v[3] = {p.x, p.y, p.z};
    for (int k = 0; k < 3; ++k) {
      if (coordinate_in_range(v[k])) continue;
      const double scale[3] = {sx, sy, sz}, offset[3] = {ox, oy, oz};
      char text[160];
      std::snprintf(text, sizeof text,
                    "%c = %g is beyond +-%s, the coordinate range tincdt computes with: check the "
                    "header's %c scale factor (%g) and offset (%g)",
                    "XYZ"[k], v[k], kMaxCoordinateText, "XYZ"[k], scale[k], offset[k]);
      throw InputError(path, where, text);
    }
  }
};

}  // namespace tincdt::io::detail
