// Private to the parallel Delaunay path: where the points split into a left and a right half.
#pragma once

#include <optional>
#include <vector>

#include "core/types.hpp"

namespace tincdt::delaunay::detail {

// Left of the pivot: lexicographically (x, then y) smaller. A pivot y of -inf or +inf puts a
// whole column of equal x on one side.
struct LeftOfPivot {
  Point2 pivot;
  bool operator()(const Point3& p) const {
    return p.x < pivot.x || (p.x == pivot.x && p.y < pivot.y);
  }
};

// The lexicographic median of a sample of the points, moved to a gap between two x values when
// that costs little balance; nothing if the sample is empty. The sample is drawn by a hash of the
// coordinates, so the split (and with it the vertex numbering and every triangle slot) is a rule
// of the points alone, not of their order in the input.
std::optional<LeftOfPivot> choose_pivot(const std::vector<Point3>& input, bool concurrent);

// Whether each side has two distinct points and not all points are collinear.
bool can_split(const std::vector<Point3>& input, LeftOfPivot is_left);

}  // namespace tincdt::delaunay::detail
