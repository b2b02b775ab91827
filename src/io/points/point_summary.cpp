// The LAS public header fields are read at their offsets in the ASPRS LAS specification
// (1.0-1.4): the same block in LAS and LAZ files.
#include "io/points/point_summary.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "io/mapped_file.hpp"
#include "io/points/load_le.hpp"
#include "io/points/point_reader.hpp"

namespace tincdt::io {
namespace {

constexpr std::size_t kMinHeaderSize = 227;  // LAS 1.0-1.2
constexpr std::size_t kHeaderSize14 = 375;   // 1.4: the 64-bit point count at byte 247

PointFileSummary summarize_las(const std::string& path, const unsigned char* h, std::size_t n) {
  if (n < kMinHeaderSize)
    throw InputError(path, "header",
                     "truncated: a LAS header needs " + count_text(kMinHeaderSize) +
                         " bytes, the file has " + count_text(n));
  const unsigned major = h[24], minor = h[25];
  if (major != 1 || minor > 4)
    throw InputError(path, "header",
                     "unsupported LAS version " + std::to_string(major) + "." +
                         std::to_string(minor) + " (LAS 1.0 to 1.4 are supported)");
  const auto header_size = load_le<std::uint16_t>(h + 94);
  const bool compressed = (h[104] & 0xC0) != 0;
  std::uint64_t count = load_le<std::uint32_t>(h + 107);
  if (minor >= 4 && header_size >= kHeaderSize14 && n >= kHeaderSize14) {
    const auto count64 = load_le<std::uint64_t>(h + 247);
    if (count64 != 0) count = count64;  // the authority in 1.4; some writers fill only the legacy
  }
  const double scale_x = load_le<double>(h + 131), scale_y = load_le<double>(h + 139);
  const double max_x = load_le<double>(h + 179), min_x = load_le<double>(h + 187);
  const double max_y = load_le<double>(h + 195), min_y = load_le<double>(h + 203);
  PointFileSummary s;
  s.format = std::string(compressed ? "laz " : "las ") + std::to_string(major) + "." +
             std::to_string(minor);
  s.points = count;
  if (count == 0) return s;
  for (const double v : {scale_x, scale_y, max_x, min_x, max_y, min_y})
    if (!std::isfinite(v))
      throw InputError(path, "header", "the scale factors or bounds are not finite numbers");
  if (min_x > max_x || min_y > max_y)
    throw InputError(path, "header",
                     "the bounds are reversed (min x " + number_text(min_x) + ", max x " +
                         number_text(max_x) + ", min y " + number_text(min_y) + ", max y " +
                         number_text(max_y) + ")");
  s.bounds = {min_x, min_y, max_x, max_y};
  s.tolerance = std::max(std::fabs(scale_x), std::fabs(scale_y));
  return s;
}

}  // namespace

PointFileSummary summarize_point_file(const std::string& path) {
  unsigned char header[kHeaderSize14] = {};
  ssize_t n = 0;
  {
    const detail::FileHandle file(path);
    n = ::pread(file.fd(), header, sizeof header, 0);
    if (n < 0) throw InputError(path, "", std::string("read failed: ") + std::strerror(errno));
  }
  if (n >= 4 && std::memcmp(header, "LASF", 4) == 0)
    return summarize_las(path, header, static_cast<std::size_t>(n));
  std::vector<Point3> points;
  const PointReadStats read = read_points(path, {}, points);
  PointFileSummary s;
  s.format = read.format.empty() ? "xyz" : read.format;
  s.points = points.size();
  for (const Point3& p : points) s.bounds.add(p.x, p.y);
  return s;
}

}  // namespace tincdt::io
