#include "io/points/point_reader.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstddef>
#include <cstring>
#include <string>

#include "core/error.hpp"
#include "io/mapped_file.hpp"

namespace tincdt::io {
namespace {

// Case-insensitive test of the end of PATH against EXT (".laz").
bool has_extension(const std::string& path, const char* ext) {
  const std::size_t n = std::strlen(ext);
  if (path.size() < n) return false;
  return std::equal(
      path.end() - static_cast<std::ptrdiff_t>(n), path.end(), ext,
      [](char a, char b) { return std::tolower(static_cast<unsigned char>(a)) == b; });
}

// Keeps the points of out[first, end) inside BOX, in order, and measures the extent of all.
void keep_inside(const BBox& box, std::size_t first, std::vector<Point3>& out,
                 PointReadStats& stats) {
  std::size_t kept = first;
  for (std::size_t i = first; i < out.size(); ++i) {
    const Point3 p = out[i];
    stats.extent.add(p.x, p.y);
    if (p.x >= box.min_x && p.x <= box.max_x && p.y >= box.min_y && p.y <= box.max_y)
      out[kept++] = p;
  }
  stats.points_kept -= out.size() - kept;
  out.resize(kept);
}

PointReadStats read_any(const std::string& path, const PointFilter& filter,
                        std::vector<Point3>& out, unsigned threads) {
  if (path == "-") return read_xyz(path, out, threads);
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw InputError(path, "", detail::open_error_text(errno));
  if (S_ISDIR(st.st_mode)) throw InputError(path, "", "is a directory, not a file");
  // Pipes and devices cannot be peeked at without consuming them: they can only be XYZ text.
  if (!S_ISREG(st.st_mode)) return read_xyz(path, out, threads);
  if (st.st_size == 0) throw InputError(path, "", "empty file");

  char signature[4] = {};
  {
    const detail::FileHandle file(path);
    const ssize_t n = ::pread(file.fd(), signature, sizeof signature, 0);
    if (n < 0) throw InputError(path, "", std::string("read failed: ") + std::strerror(errno));
  }
  if (std::memcmp(signature, "LASF", 4) == 0) return read_las(path, filter, out, threads);
  // A .las or .laz name without the signature is a damaged or mislabelled file, not text.
  if (has_extension(path, ".las") || has_extension(path, ".laz")) {
    return read_las(path, filter, out, threads);
  }
  return read_xyz(path, out, threads);
}

}  // namespace

PointReadStats read_points(const std::string& path, const PointFilter& filter,
                           std::vector<Point3>& out, unsigned threads) {
  const std::size_t first = out.size();
  PointReadStats stats = read_any(path, filter, out, threads);
  if (filter.box) keep_inside(*filter.box, first, out, stats);
  return stats;
}

}  // namespace tincdt::io
