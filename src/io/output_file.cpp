#include "io/output_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <optional>
#include <system_error>
#include <utility>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "core/parallel.hpp"
#include "io/temporary_registry.hpp"

namespace tincdt::io {
namespace {

constexpr std::size_t kStreamBuffer = std::size_t{4} << 20;

// A file past kDirectFrom bytes goes on with O_DIRECT in aligned blocks, sparing the copy into the
// page cache on the writing thread and the write-out at fsync (docs/design.md).
constexpr std::size_t kDirectFrom = std::size_t{64} << 20;
constexpr std::size_t kDirectBlock = std::size_t{8} << 20;
constexpr std::size_t kDirectAlign = 4096;

std::string error_text(int err) {
  return std::generic_category().message(err);
}

// The process umask, read without changing it (umask(2) can only set it, which races with other
// threads creating files). Linux reports it in /proc/self/status since 4.7; 022 otherwise.
mode_t current_umask() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("Umask:", 0) == 0)
      return static_cast<mode_t>(std::strtoul(line.c_str() + 6, nullptr, 8) & 0777);
  }
  return 022;
}

// Makes the rename durable; failure here cannot undo the rename and changes nothing the user
// can act on, so it is not reported.
void sync_folder(const std::string& dir) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  (void)::fsync(fd);
  (void)::close(fd);
}

std::string folder_of(const std::string& path) {
  const auto slash = path.rfind('/');
  if (slash == std::string::npos) return ".";
  if (slash == 0) return "/";
  return path.substr(0, slash);
}

// What SQLite (GeoPackage) may leave beside a database while it is open.
constexpr const char* kSideSuffixes[] = {"-journal", "-wal", "-shm"};

// ---- the registry of temporaries (temporary_registry.hpp) ---------------------------------------
//
// Each slot is written by one thread at a time (a spin lock among writers) and read by a signal
// handler at any moment: the sequence number is odd while a slot changes, and the handler skips a
// slot whose number moved while it copied the name.

constexpr int kSlots = 64;
constexpr std::size_t kMaxPath = 4096;

struct Slot {
  std::atomic<std::uint32_t> seq{0};
  std::atomic<bool> used{false};
  char path[kMaxPath];
};

Slot g_slots[kSlots];
std::atomic_flag g_writer = ATOMIC_FLAG_INIT;
std::atomic<bool> g_committing{false};

class WriterLock {
 public:
  WriterLock() noexcept {
    while (g_writer.test_and_set(std::memory_order_acquire)) {
    }
  }
  ~WriterLock() { g_writer.clear(std::memory_order_release); }
  WriterLock(const WriterLock&) = delete;
  WriterLock& operator=(const WriterLock&) = delete;
};

}  // namespace

namespace detail {

int track_temporary(const std::string& path) noexcept {
  if (path.empty() || path.size() >= kMaxPath) return -1;
  const WriterLock lock;
  for (int i = 0; i < kSlots; ++i) {
    Slot& s = g_slots[i];
    if (s.used.load(std::memory_order_relaxed)) continue;
    s.seq.fetch_add(1, std::memory_order_acq_rel);
    std::memcpy(s.path, path.c_str(), path.size() + 1);
    s.used.store(true, std::memory_order_relaxed);
    s.seq.fetch_add(1, std::memory_order_acq_rel);
    return i;
  }
  return -1;
}

void untrack_temporary(int& slot) noexcept {
  if (slot < 0 || slot >= kSlots) return;
  const WriterLock lock;
  Slot& s = g_slots[slot];
  s.seq.fetch_add(1, std::memory_order_acq_rel);
  s.used.store(false, std::memory_order_relaxed);
  s.seq.fetch_add(1, std::memory_order_acq_rel);
  slot = -1;
}

int move_without_replacing(const std::string& from, const std::string& to) noexcept {
  if (::renameat2(AT_FDCWD, from.c_str(), AT_FDCWD, to.c_str(), RENAME_NOREPLACE) == 0) return 0;
  const int err = errno;
  if (err != EINVAL && err != ENOSYS) return err;
  // The file system cannot rename without replacing: link() refuses an existing target.
  if (::link(from.c_str(), to.c_str()) != 0) return errno;
  (void)::unlink(from.c_str());
  return 0;
}

void sync_folder_of(const std::string& path) noexcept {
  sync_folder(folder_of(path));
}

void set_committing(bool on) noexcept {
  g_committing.store(on, std::memory_order_seq_cst);
}

}  // namespace detail

bool remove_temporaries_for_exit() noexcept {
  if (g_committing.load(std::memory_order_seq_cst)) return false;
  char name[kMaxPath];
  for (Slot& s : g_slots) {
    const std::uint32_t before = s.seq.load(std::memory_order_acquire);
    if ((before & 1u) != 0 || !s.used.load(std::memory_order_relaxed)) continue;
    std::size_t n = 0;
    while (n + 1 < kMaxPath && s.path[n] != '\0') {
      name[n] = s.path[n];
      ++n;
    }
    name[n] = '\0';
    std::atomic_thread_fence(std::memory_order_acquire);
    if (s.seq.load(std::memory_order_relaxed) != before) continue;
    (void)::unlink(name);
  }
  return true;
}

// ---- large files, past the page cache -----------------------------------------------------------

namespace detail {

PositionalWrite& direct_write() {
  static PositionalWrite write = ::pwrite;
  return write;
}

// The part of a large file past kDirectFrom, written through a second descriptor opened with
// O_DIRECT in two aligned blocks: one is filled while the other is written in the background.
// A file system that opens with O_DIRECT but refuses the write (EINVAL) gets that block, and the
// rest of the file, through the stream instead.
class DirectBlocks {
 public:
  // Null when the file cannot be opened with O_DIRECT. The first block starts with the bytes of
  // the last partial aligned block the (flushed) stream wrote, read back.
  static std::unique_ptr<DirectBlocks> open(const std::string& path, const std::string& temp_path,
                                            std::FILE* stream, std::size_t bytes);
  ~DirectBlocks();  // waits for the write under way
  DirectBlocks(const DirectBlocks&) = delete;
  DirectBlocks& operator=(const DirectBlocks&) = delete;

  void put(const char* data, std::size_t n);
  // Writes the last block padded to the alignment (the caller cuts the file to its size) and
  // waits for it.
  void finish();

 private:
  struct FreeAligned {
    void operator()(char* p) const { std::free(p); }
  };
  struct Write {
    std::size_t offset = 0;
    std::size_t bytes = 0;  // aligned: what is written
    std::size_t fill = 0;   // of which the file's
    int error = 0;          // errno of the write, once waited for
  };

  DirectBlocks(const std::string& path, std::FILE* stream, int fd,
               std::unique_ptr<char, FreeAligned> blocks, std::size_t tail, std::size_t offset)
      : path_(path),
        stream_(stream),
        fd_(fd),
        blocks_(std::move(blocks)),
        fill_(tail),
        offset_(offset) {}
  char* block(int i) const { return blocks_.get() + i * kDirectBlock; }
  void write_block(std::size_t n);
  void wait();
  void write_through_stream(std::size_t offset, const char* data, std::size_t n);

  std::string path_;
  std::FILE* stream_;
  int fd_;  // -1 once O_DIRECT was refused: the stream takes the rest
  std::unique_ptr<char, FreeAligned> blocks_;
  int filling_ = 0;         // the block being filled
  std::size_t fill_ = 0;    // its bytes in use
  std::size_t offset_ = 0;  // where it goes in the file
  Write written_;           // the other block's write, while writing_ runs
  std::optional<BackgroundJob> writing_;
};

std::unique_ptr<DirectBlocks> DirectBlocks::open([[maybe_unused]] const std::string& path,
                                                 [[maybe_unused]] const std::string& temp_path,
                                                 [[maybe_unused]] std::FILE* stream,
                                                 [[maybe_unused]] std::size_t bytes) {
#ifdef O_DIRECT
  const int fd = ::open(temp_path.c_str(), O_WRONLY | O_DIRECT | O_CLOEXEC);
  if (fd < 0) return nullptr;
  std::unique_ptr<char, FreeAligned> blocks(
      static_cast<char*>(std::aligned_alloc(kDirectAlign, 2 * kDirectBlock)));
  const std::size_t tail = bytes % kDirectAlign;
  const auto offset = static_cast<off_t>(bytes - tail);
  if (!blocks ||
      ::pread(::fileno(stream), blocks.get(), tail, offset) != static_cast<ssize_t>(tail)) {
    (void)::close(fd);
    return nullptr;
  }
  return std::unique_ptr<DirectBlocks>(
      new DirectBlocks(path, stream, fd, std::move(blocks), tail, bytes - tail));
#else
  return nullptr;
#endif
}

DirectBlocks::~DirectBlocks() {
  writing_.reset();
  if (fd_ >= 0) (void)::close(fd_);
}

void DirectBlocks::put(const char* data, std::size_t n) {
  while (n > 0 && fd_ >= 0) {
    const std::size_t part = std::min(n, kDirectBlock - fill_);
    std::memcpy(block(filling_) + fill_, data, part);
    fill_ += part;
    data += part;
    n -= part;
    if (fill_ == kDirectBlock) write_block(kDirectBlock);
  }
  if (n == 0) return;
  // O_DIRECT was refused on the way: the stream is at the end of the file.
  if (std::fwrite(data, 1, n, stream_) != n) {
    const int err = errno;
    throw OutputError(path_, "byte " + count_text(offset_), "write failed: " + error_text(err));
  }
  offset_ += n;
}

// Hands the first N bytes of the block being filled (N a multiple of kDirectAlign) to a
// background write at offset_, once the other block's write is done, and fills the other.
void DirectBlocks::write_block(std::size_t n) {
  assert(n % kDirectAlign == 0 && n >= fill_);
  wait();
  if (fd_ < 0) {  // the other block's write was refused
    write_through_stream(offset_, block(filling_), fill_);
  } else {
    written_ = {offset_, n, fill_, 0};
    const auto write = [this, data = block(filling_)] {
      for (std::size_t done = 0; done < written_.bytes;) {
        const ssize_t w = direct_write()(fd_, data + done, written_.bytes - done,
                                         static_cast<off_t>(written_.offset + done));
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) {
          written_.error = w < 0 ? errno : ENOSPC;
          return;
        }
        done += static_cast<std::size_t>(w);
      }
    };
    try {
      writing_.emplace(true, write);
    } catch (const std::system_error&) {  // no thread to be had: write it now
      writing_.emplace(false, write);
    }
    filling_ ^= 1;
  }
  offset_ += fd_ < 0 ? fill_ : n;
  fill_ = 0;
}

void DirectBlocks::wait() {
  if (!writing_) return;
  writing_.reset();
  const Write w = std::exchange(written_, {});
  if (w.error == 0) return;
  if (w.error != EINVAL)
    throw OutputError(path_, "byte " + count_text(w.offset),
                      "write failed: " + error_text(w.error));
  (void)::close(std::exchange(fd_, -1));
  write_through_stream(w.offset, block(filling_ ^ 1), w.fill);
}

void DirectBlocks::write_through_stream(std::size_t offset, const char* data, std::size_t n) {
  if (::fseeko(stream_, static_cast<off_t>(offset), SEEK_SET) != 0 ||
      std::fwrite(data, 1, n, stream_) != n) {
    const int err = errno;
    throw OutputError(path_, "byte " + count_text(offset), "write failed: " + error_text(err));
  }
}

void DirectBlocks::finish() {
  if (fd_ >= 0) {
    const std::size_t padded = (fill_ + kDirectAlign - 1) / kDirectAlign * kDirectAlign;
    std::memset(block(filling_) + fill_, 0, padded - fill_);
    if (padded > 0) write_block(padded);
  }
  wait();
}

}  // namespace detail

OutputFile::OutputFile(std::string path, bool overwrite)
    : path_(std::move(path)), overwrite_(overwrite) {
  if (path_.empty()) throw OutputError("", "", "the output path is empty");
  const auto slash = path_.rfind('/');
  const std::string name = slash == std::string::npos ? path_ : path_.substr(slash + 1);
  if (name.empty() || name == "." || name == "..") throw OutputError(path_, "", "is a folder");

  struct stat st {};
  if (::stat(path_.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) throw OutputError(path_, "", "is a folder");
    if (!overwrite_) throw OutputError(path_, "", "already exists", Remedy::overwrite);
    if (!S_ISREG(st.st_mode))
      throw OutputError(path_, "", "is not a regular file and cannot be replaced");
  }

  const std::string dir = folder_of(path_);
  temp_path_ = dir + "/." + name + ".tmp-XXXXXX";
  const int fd = ::mkostemp(temp_path_.data(), O_CLOEXEC);
  if (fd < 0) {
    const int err = errno;
    temp_path_.clear();
    throw OutputError(path_, "",
                      "cannot create a file in folder '" + dir + "': " + error_text(err));
  }
  temp_slot_ = detail::track_temporary(temp_path_);
  // mkostemp creates 0600; give the output the mode a plain open(O_CREAT) would.
  mode_ = static_cast<mode_t>(0666 & ~current_umask());
  const auto fail = [&](const char* what) {
    const int err = errno;
    (void)::close(fd);
    (void)::unlink(temp_path_.c_str());
    forget_temporary();
    throw OutputError(path_, "", what + error_text(err));
  };
  if (::fchmod(fd, mode_) != 0) fail("cannot set the permissions of the new file: ");
  file_ = ::fdopen(fd, "wb");
  if (file_ == nullptr) fail("cannot open the new file: ");
  // Not zeroed: a small file (a web-terrain tile) touches a page of it, not all 4 MiB.
  buffer_ = std::make_unique_for_overwrite<char[]>(kStreamBuffer);
  if (std::setvbuf(file_, buffer_.get(), _IOFBF, kStreamBuffer) != 0) {
    // Not fatal: the stream keeps its default buffer, which it owns.
    buffer_.reset();
  }
}

OutputFile::~OutputFile() {
  direct_.reset();  // waits for its write before the stream closes
  if (file_ != nullptr) (void)std::fclose(file_);
  if (!committed_) {
    if (!temp_path_.empty()) (void)::unlink(temp_path_.c_str());
    if (!taken_path_.empty()) {
      (void)::unlink(taken_path_.c_str());
      for (const char* suffix : kSideSuffixes) (void)::unlink((taken_path_ + suffix).c_str());
    }
  }
  forget_temporary();
}

void OutputFile::forget_temporary() {
  detail::untrack_temporary(temp_slot_);
  for (int& slot : taken_slots_) detail::untrack_temporary(slot);
}

void OutputFile::write(const void* data, std::size_t n) {
  if (n == 0) return;
  if (file_ == nullptr) throw OutputError(path_, "", "write after the file was closed");
  failed_ = true;  // until this write is through: a file missing bytes is never closed
  if (!direct_tried_ && bytes_ + n > kDirectFrom) start_direct();
  if (direct_) {
    direct_->put(static_cast<const char*>(data), n);
  } else if (std::fwrite(data, 1, n, file_) != n) {
    const int err = errno;
    throw OutputError(path_, "byte " + count_text(bytes_), "write failed: " + error_text(err));
  }
  bytes_ += n;
  failed_ = false;
}

// From here on the file is written through a second descriptor opened with O_DIRECT, where the
// file system takes it.
void OutputFile::start_direct() {
  direct_tried_ = true;
  if (std::fflush(file_) != 0) {
    const int err = errno;
    throw OutputError(path_, "byte " + count_text(bytes_), "write failed: " + error_text(err));
  }
  direct_ = detail::DirectBlocks::open(path_, temp_path_, file_, bytes_);
}

const std::string& OutputFile::take_path() {
  if (!taken_path_.empty() || closed_ || file_ == nullptr || bytes_ != 0)
    throw OutputError(path_, "", "the new file cannot be handed to another writer");
  (void)std::fclose(std::exchange(file_, nullptr));
  const std::string name = path_.substr(path_.rfind('/') + 1);
  const auto dot = name.rfind('.');
  taken_path_ = temp_path_ + (dot == std::string::npos || dot == 0 ? ".tmp" : name.substr(dot));
  taken_slots_[0] = detail::track_temporary(taken_path_);
  for (int i = 0; i < 3; ++i)
    taken_slots_[i + 1] = detail::track_temporary(taken_path_ + kSideSuffixes[i]);
  struct stat st {};
  if (::lstat(taken_path_.c_str(), &st) == 0)
    throw OutputError(path_, "", "the temporary file '" + taken_path_ + "' exists already");
  return taken_path_;
}

// The file a library made at taken_path_: given the usual mode, flushed to disk and moved over
// the reserved temporary.
void OutputFile::finish_taken() {
  const int fd = ::open(taken_path_.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    const int err = errno;
    throw OutputError(path_, "", "cannot reopen the new file: " + error_text(err));
  }
  struct stat st {};
  const bool ok = ::fchmod(fd, mode_) == 0 && ::fsync(fd) == 0 && ::fstat(fd, &st) == 0;
  const int err = errno;
  (void)::close(fd);
  if (!ok) throw OutputError(path_, "", "cannot flush the new file to disk: " + error_text(err));
  bytes_ = static_cast<std::size_t>(st.st_size);
  if (std::rename(taken_path_.c_str(), temp_path_.c_str()) != 0) {
    const int rename_err = errno;
    throw OutputError(path_, "", "cannot move the new file into place: " + error_text(rename_err));
  }
  for (const char* suffix : kSideSuffixes) (void)::unlink((taken_path_ + suffix).c_str());
  taken_path_.clear();
  for (int& slot : taken_slots_) detail::untrack_temporary(slot);
}

void OutputFile::close() {
  if (closed_) return;
  if (!taken_path_.empty()) {
    finish_taken();
    closed_ = true;
    return;
  }
  if (file_ == nullptr) throw OutputError(path_, "", "the file is not open");
  if (failed_) throw OutputError(path_, "", "an earlier write failed: the file is incomplete");
  failed_ = true;  // until the file is complete on disk
  if (direct_) {
    direct_->finish();
    direct_.reset();
  }
  if (std::fflush(file_) != 0 ||
      (direct_tried_ && ::ftruncate(::fileno(file_), static_cast<off_t>(bytes_)) != 0)) {
    const int err = errno;
    throw OutputError(path_, "", "write failed: " + error_text(err));
  }
  if (sync_on_close_ && ::fsync(::fileno(file_)) != 0) {
    const int err = errno;
    throw OutputError(path_, "", "cannot flush to disk: " + error_text(err));
  }
  std::FILE* f = std::exchange(file_, nullptr);
  if (std::fclose(f) != 0) {
    const int err = errno;
    throw OutputError(path_, "", "cannot close: " + error_text(err));
  }
  buffer_.reset();  // a job may hold thousands of closed outputs (web-terrain tiles)
  failed_ = false;
  closed_ = true;
}

void OutputFile::commit() {
  if (committed_) return;
  close();
  if (overwrite_) {
    if (std::rename(temp_path_.c_str(), path_.c_str()) != 0) {
      const int err = errno;
      throw OutputError(path_, "", "cannot replace the file: " + error_text(err));
    }
  } else if (const int err = detail::move_without_replacing(temp_path_, path_); err != 0) {
    // Never replace a file that appeared since the constructor looked.
    if (err == EEXIST) throw OutputError(path_, "", "already exists", Remedy::overwrite);
    throw OutputError(path_, "", "cannot create the file: " + error_text(err));
  }
  committed_ = true;
  forget_temporary();
  detail::sync_folder_of(path_);
}

}  // namespace tincdt::io
