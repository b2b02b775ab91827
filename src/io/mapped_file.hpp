// Private to src/io: a read-only, copy-on-write memory map of a whole file, for the readers.
// Header-only so that it needs no entry in the module's source list.
#pragma once

#include "core/memory.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"

namespace tincdt::io::detail {

// "no such file" for ENOENT, else the C library's message.
inline std::string open_error_text(int err) {
  if (err == ENOENT) return "no such file";
  return std::string("cannot open: ") + std::strerror(err);
}

// An open file descriptor, closed on scope exit.
class FileHandle {
 public:
  // Opens PATH read-only; throws InputError(path, "", "no such file" / strerror).
  explicit FileHandle(const std::string& path) : fd_(::open(path.c_str(), O_RDONLY | O_CLOEXEC)) {
    if (fd_ < 0) throw InputError(path, "", open_error_text(errno));
  }
  FileHandle(const FileHandle&) = delete;
  FileHandle& operator=(const FileHandle&) = delete;
  ~FileHandle() {
    if (fd_ >= 0) ::close(fd_);
  }
  int fd() const { return fd_; }

 private:
  int fd_;
};

// The whole of a regular file mapped MAP_PRIVATE / PROT_READ. Pages already consumed can be
// handed back with release() so that resident memory stays small for multi-GB inputs (the data
// is re-read from the page cache or the disk if touched again, never lost).
class MappedFile {
 public:
  // Maps PATH, which must be a regular file; throws InputError naming it. An empty file gives
  // size() == 0 and data() == nullptr.
  explicit MappedFile(const std::string& path) {
    FileHandle file(path);
    struct stat st {};
    if (::fstat(file.fd(), &st) != 0) {
      throw InputError(path, "", std::string("cannot stat: ") + std::strerror(errno));
    }
    if (S_ISDIR(st.st_mode)) throw InputError(path, "", "is a directory, not a file");
    if (!S_ISREG(st.st_mode)) throw InputError(path, "", "not a regular file");
    size_ = static_cast<std::size_t>(st.st_size);
    if (size_ == 0) return;
    void* p = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, file.fd(), 0);
    if (p == MAP_FAILED) {
      throw InputError(path, "", std::string("cannot map into memory: ") + std::strerror(errno));
    }
    data_ = static_cast<const std::uint8_t*>(p);
  }
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  ~MappedFile() {
    if (data_ != nullptr) ::munmap(const_cast<std::uint8_t*>(data_), size_);
  }

  const std::uint8_t* data() const { return data_; }
  const char* chars() const { return reinterpret_cast<const char*>(data_); }
  std::size_t size() const { return size_; }

  // Tells the kernel the bytes [from, to) will be read front to back (more read-ahead).
  void advise_sequential(std::size_t from, std::size_t to) const {
    advise(from, to, MADV_SEQUENTIAL);
  }

  // Drops the pages lying wholly inside [from, to) from this process's resident set.
  void release(std::size_t from, std::size_t to) const { advise(from, to, MADV_DONTNEED); }

 private:
  void advise(std::size_t from, std::size_t to, int advice) const {
    if (data_ == nullptr) return;
    const auto page = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
    if (to > size_) to = size_;
    // madvise needs a page-aligned start; round the range inwards so that neighbours are kept.
    const std::size_t first = (from + page - 1) / page * page;
    const std::size_t last = (advice == MADV_DONTNEED && to != size_) ? to / page * page : to;
    if (first >= last) return;
    // Advice is only a hint: a failure changes speed or memory use, never the data read.
    (void)::madvise(const_cast<std::uint8_t*>(data_) + first, last - first, advice);
  }

  const std::uint8_t* data_ = nullptr;
  std::size_t size_ = 0;
};

using tincdt::advise_huge_pages;

}  // namespace tincdt::io::detail
