// LAS reader: any bytes, read without filters or (when the last byte is odd) with a class and a
// return filter. A finding is a crash, a sanitizer report, an internal error, or a point
// outside the coordinate range the reader promises.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "core/coordinates.hpp"
#include "core/error.hpp"
#include "fuzz/fuzz_support.hpp"
#include "io/points/point_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tincdt;
  static fuzz::MemFile file("las_fuzz");
  const std::string& path = file.fill(data, size);
  io::PointFilter filter;
  if (size > 0 && (data[size - 1] & 1) != 0) {
    filter.keep_classes = {2, 8};
    filter.first_return_only = true;
  }
  std::vector<Point3> points;
  try {
    const io::PointReadStats stats = io::read_las(path, filter, points);
    if (stats.points_kept != points.size() || stats.points_kept > stats.points_read) std::abort();
    for (const Point3& p : points)
      if (!coordinate_in_range(p.x) || !coordinate_in_range(p.y) || !coordinate_in_range(p.z))
        std::abort();
  } catch (const Error& e) {
    fuzz::check_not_internal(e);
  }
  return 0;
}
