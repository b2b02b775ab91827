// XYZ reader: any bytes, read both ways it reads (a mapped file, and a pipe like stdin), which
// must agree on every point or on the error. A finding is a crash, a sanitizer report, a
// disagreement, a -0 or a coordinate out of range.
#include <fcntl.h>
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/coordinates.hpp"
#include "core/error.hpp"
#include "fuzz/fuzz_support.hpp"
#include "io/points/point_reader.hpp"

namespace {

struct Result {
  std::vector<tincdt::Point3> points;
  std::string error;  // where and detail: the file names differ
};

Result read(const std::string& path) {
  Result r;
  try {
    tincdt::io::read_xyz(path, r.points);
  } catch (const tincdt::Error& e) {
    tincdt::fuzz::check_not_internal(e);
    r.points.clear();
    r.error = e.where() + ": " + e.detail();
  }
  return r;
}

// The same bytes through a pipe: the reader streams them as it does stdin. Empty when the pipe
// cannot hold them all (the writer would block).
bool read_piped(const std::uint8_t* data, std::size_t size, Result& out) {
  int fds[2];
  if (::pipe(fds) != 0) std::abort();
  const int capacity = ::fcntl(fds[1], F_SETPIPE_SZ, 1 << 20);
  bool ok = capacity > 0 && size <= static_cast<std::size_t>(capacity);
  if (ok) {
    std::size_t done = 0;
    while (done < size) {
      const ssize_t n = ::write(fds[1], data + done, size - done);
      if (n <= 0) std::abort();
      done += static_cast<std::size_t>(n);
    }
  }
  ::close(fds[1]);
  if (ok) out = read("/proc/self/fd/" + std::to_string(fds[0]));
  ::close(fds[0]);
  return ok;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tincdt;
  static fuzz::MemFile file("xyz_fuzz");
  const Result mapped = read(file.fill(data, size));
  for (const Point3& p : mapped.points) {
    for (const double v : {p.x, p.y, p.z})
      if (!coordinate_in_range(v) || (v == 0 && std::signbit(v))) std::abort();
  }
  Result piped;
  // An empty file and an empty stream are refused in different words ("empty file", "input").
  if (size > 0 && read_piped(data, size, piped)) {
    if (piped.error != mapped.error || piped.points != mapped.points) {
      std::fprintf(stderr, "mapped: %zu points, '%s'\npiped: %zu points, '%s'\n",
                   mapped.points.size(), mapped.error.c_str(), piped.points.size(),
                   piped.error.c_str());
      std::abort();
    }
  }
  return 0;
}
