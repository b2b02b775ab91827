// Safe output: write to "<dir>/.<name>.tmp-XXXXXX" beside the target, rename over it on commit().
// Destroyed without commit() the temporary is removed, so a failed run leaves nothing behind and
// the target is always either its old content or the complete new one.
#pragma once

#include <cstddef>
#include <cstdio>
#include <memory>
#include <string>

namespace tincdt::io {

class OutputFile {
 public:
  // Throws OutputError if the target exists and !overwrite, or the folder is not writable.
  OutputFile(std::string path, bool overwrite);
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  void write(const void* data, std::size_t n);  // buffered; throws OutputError on failure
  void write(const std::string& s) { write(s.data(), s.size()); }
  const std::string& path() const { return path_; }
  const std::string& temp_path() const { return temp_path_; }
  std::size_t bytes_written() const { return bytes_; }
  // Flush, fsync and close the temporary without renaming it yet, so several outputs (a mesh
  // and its .prj) can all be complete on disk before the first rename. Optional.
  void close();
  void commit();  // close() if not done yet, then rename over the target

 private:
  std::string path_;
  std::string temp_path_;
  std::FILE* file_ = nullptr;
  std::unique_ptr<char[]> buffer_;  // the stream's buffer (setvbuf)
  std::size_t bytes_ = 0;
  bool overwrite_ = false;
  bool closed_ = false;
  bool committed_ = false;
};

}  // namespace tincdt::io
