// The point readers as the reading tests call them: one thread, the points and the stats, or the
// InputError a file gets.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "io/points/point_reader.hpp"
#include "support/errors.hpp"

namespace tincdt::test {

inline std::vector<Point3> points_of(const std::string& path, const io::PointFilter& filter = {},
                                     io::PointReadStats* stats = nullptr) {
  std::vector<Point3> pts;
  const io::PointReadStats s = io::read_points(path, filter, pts, 1);
  if (stats != nullptr) *stats = s;
  return pts;
}

inline std::optional<InputError> input_error(const std::string& path,
                                             const io::PointFilter& filter = {}) {
  return thrown<InputError>([&] { points_of(path, filter); });
}

}  // namespace tincdt::test
