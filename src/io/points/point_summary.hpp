// What a point file holds, from its header alone: for planning tiled jobs without reading the
// points (LAS and LAZ keep their count and bounds in the public header block).
#pragma once

#include <cstdint>
#include <string>

#include "core/types.hpp"

namespace tincdt::io {

struct PointFileSummary {
  std::string format;        // "las 1.2", "laz 1.4", "xyz"
  std::uint64_t points = 0;  // as the header states (XYZ: as counted)
  BBox bounds;               // x, y; empty when the file holds no point
  // How far a point may lie outside `bounds` and still belong to the file: a LAS header's bounds
  // are rounded by its writer, so one scale unit either way; 0 for bounds measured here (XYZ).
  double tolerance = 0;
};

// LAS / LAZ: the public header block only (signature, version, counts, scale, bounds), checked
// for sense. XYZ text has no header: the file is read whole and measured. Throws InputError
// naming the file for an unreadable or malformed header, or bounds that are not finite.
PointFileSummary summarize_point_file(const std::string& path);

}  // namespace tincdt::io
