// Shared by the fuzz targets: inputs as files without touching the disk, and the one rule for
// what counts as a finding besides crashes and sanitizer reports.
#pragma once

#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "core/error.hpp"

namespace tincdt::fuzz {

// An in-memory regular file (memfd) reachable by path, refilled for every input: the readers
// open, stat and map it like any file.
class MemFile {
 public:
  explicit MemFile(const char* name) : fd_(::memfd_create(name, 0)) {
    if (fd_ < 0) std::abort();
    path_ = "/proc/self/fd/" + std::to_string(fd_);
  }
  MemFile(const MemFile&) = delete;
  MemFile& operator=(const MemFile&) = delete;
  ~MemFile() { ::close(fd_); }

  const std::string& fill(const std::uint8_t* data, std::size_t size) {
    if (::ftruncate(fd_, 0) != 0) std::abort();
    std::size_t done = 0;
    while (done < size) {
      const ssize_t n = ::pwrite(fd_, data + done, size - done, static_cast<off_t>(done));
      if (n <= 0) std::abort();
      done += static_cast<std::size_t>(n);
    }
    return path_;
  }

 private:
  int fd_;
  std::string path_;
};

// A tincdt::Error is the expected answer to bad input, unless it reports a broken invariant:
// that is a bug, and the fuzzer must stop on it. (An InternalError, or from the throw sites that
// predate it, a GeometryError whose text starts with "internal".)
inline void check_not_internal(const Error& e) {
  if (dynamic_cast<const InternalError*>(&e) != nullptr || e.detail().rfind("internal", 0) == 0) {
    std::fprintf(stderr, "%s\n", e.what());
    std::abort();
  }
}

}  // namespace tincdt::fuzz
