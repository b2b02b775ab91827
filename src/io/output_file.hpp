// Safe output: write to "<dir>/.<name>.tmp-XXXXXX" beside the target, rename over it on commit().
// Destroyed without commit() the temporary is removed, so a failed run leaves nothing behind and
// the target is always either its old content or the complete new one. Several outputs that must
// appear together go through an OutputSet (output_set.hpp) instead of commit().
#pragma once

#include <sys/types.h>

#include <cstddef>
#include <cstdio>
#include <memory>
#include <string>

namespace tincdt::io {

namespace detail {
class DirectBlocks;
}

class OutputFile {
 public:
  // Throws OutputError if the target exists and !overwrite, or the folder is not writable.
  OutputFile(std::string path, bool overwrite);
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  // Buffered, past 64 MB with O_DIRECT where the file system takes it; throws OutputError on
  // failure, after which the file cannot be closed or committed.
  void write(const void* data, std::size_t n);
  void write(const std::string& s) { write(s.data(), s.size()); }
  const std::string& path() const { return path_; }
  const std::string& temp_path() const { return temp_path_; }
  // Bytes written through write(), or the size of the file a library made at take_path().
  std::size_t bytes_written() const { return bytes_; }

  // For a writer that must create the file itself (GDAL refuses to open an existing GeoPackage):
  // returns a fresh name beside the temporary, ending in the target's extension, at which the
  // caller creates the file, once. close() moves it over the temporary; until then it and its
  // SQLite side files ("-journal", "-wal", "-shm") are removed with the temporary. write() is
  // not allowed afterwards.
  const std::string& take_path();

  // Flush, fsync and close the temporary without renaming it yet, so several outputs (a mesh
  // and its .prj) can all be complete on disk before the first rename. Optional.
  void close();
  void commit();  // close() if not done yet, then rename over the target
  // For one of an OutputSet's many small files (web-terrain tiles): close() leaves the fsync to
  // the set, which flushes the file system once before its first rename; an fsync a file costs
  // more than the file.
  void defer_sync() { sync_on_close_ = false; }
  bool sync_deferred() const { return !sync_on_close_; }

 private:
  friend class OutputSet;
  void finish_taken();
  void forget_temporary();  // the temporary is gone (renamed or removed): stop tracking it
  void start_direct();      // a large file goes on past the page cache (output_file.cpp)

  std::string path_;
  std::string temp_path_;
  std::string taken_path_;  // take_path(): where the library writes
  int temp_slot_ = -1;      // temporary_registry slots (signal-safe clean-up)
  int taken_slots_[4] = {-1, -1, -1, -1};
  std::FILE* file_ = nullptr;
  std::unique_ptr<char[]> buffer_;                // the stream's buffer (setvbuf)
  std::unique_ptr<detail::DirectBlocks> direct_;  // null: everything goes through file_
  bool direct_tried_ = false;
  std::size_t bytes_ = 0;
  mode_t mode_ = 0644;
  bool overwrite_ = false;
  bool failed_ = false;  // a write() failed
  bool closed_ = false;
  bool committed_ = false;
  bool sync_on_close_ = true;
};

// Removes every temporary file of the outputs this process has under way, for a signal handler
// that is about to end the process (a second Ctrl-C): async-signal-safe, no allocation, no lock.
// Returns false, and removes nothing, while an OutputSet is renaming its files into place; the
// handler should then let the few renames finish (they run with the usual termination signals
// blocked, so the signal is delivered right after).
bool remove_temporaries_for_exit() noexcept;

namespace detail {
// The pwrite(2) of the O_DIRECT blocks; tests put another in its place to refuse writes.
using PositionalWrite = ssize_t (*)(int fd, const void* data, std::size_t n, off_t offset);
PositionalWrite& direct_write();
}  // namespace detail

}  // namespace tincdt::io
