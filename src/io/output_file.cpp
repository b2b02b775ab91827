#include "io/output_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <system_error>
#include <utility>

#include "core/error.hpp"

namespace tincdt::io {
namespace {

constexpr std::size_t kStreamBuffer = std::size_t{4} << 20;

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

}  // namespace

OutputFile::OutputFile(std::string path, bool overwrite)
    : path_(std::move(path)), overwrite_(overwrite) {
  if (path_.empty()) throw OutputError("", "", "the output path is empty");
  const auto slash = path_.rfind('/');
  const std::string name = slash == std::string::npos ? path_ : path_.substr(slash + 1);
  if (name.empty() || name == "." || name == "..") throw OutputError(path_, "", "is a folder");

  struct stat st {};
  if (::stat(path_.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) throw OutputError(path_, "", "is a folder");
    if (!overwrite_) throw OutputError(path_, "", "already exists (use --overwrite to replace it)");
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
  // mkostemp creates 0600; give the output the mode a plain open(O_CREAT) would.
  if (::fchmod(fd, static_cast<mode_t>(0666 & ~current_umask())) != 0) {
    const int err = errno;
    (void)::close(fd);
    (void)::unlink(temp_path_.c_str());
    temp_path_.clear();
    throw OutputError(path_, "", "cannot set the permissions of the new file: " + error_text(err));
  }
  file_ = ::fdopen(fd, "wb");
  if (file_ == nullptr) {
    const int err = errno;
    (void)::close(fd);
    (void)::unlink(temp_path_.c_str());
    temp_path_.clear();
    throw OutputError(path_, "", "cannot open the new file: " + error_text(err));
  }
  buffer_ = std::make_unique<char[]>(kStreamBuffer);
  if (std::setvbuf(file_, buffer_.get(), _IOFBF, kStreamBuffer) != 0) {
    // Not fatal: the stream keeps its default buffer, which it owns.
    buffer_.reset();
  }
}

OutputFile::~OutputFile() {
  if (file_ != nullptr) (void)std::fclose(file_);
  if (!committed_ && !temp_path_.empty()) (void)::unlink(temp_path_.c_str());
}

void OutputFile::write(const void* data, std::size_t n) {
  if (n == 0) return;
  if (file_ == nullptr) throw OutputError(path_, "", "write after the file was closed");
  if (std::fwrite(data, 1, n, file_) != n) {
    const int err = errno;
    throw OutputError(path_, "byte " + std::to_string(bytes_), "write failed: " + error_text(err));
  }
  bytes_ += n;
}

void OutputFile::close() {
  if (closed_) return;
  if (file_ == nullptr) throw OutputError(path_, "", "the file is not open");
  if (std::fflush(file_) != 0) {
    const int err = errno;
    throw OutputError(path_, "", "write failed: " + error_text(err));
  }
  if (::fsync(::fileno(file_)) != 0) {
    const int err = errno;
    throw OutputError(path_, "", "cannot flush to disk: " + error_text(err));
  }
  std::FILE* f = std::exchange(file_, nullptr);
  if (std::fclose(f) != 0) {
    const int err = errno;
    throw OutputError(path_, "", "cannot close: " + error_text(err));
  }
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
  } else {
    // Never replace a file that appeared since the constructor looked.
    if (::renameat2(AT_FDCWD, temp_path_.c_str(), AT_FDCWD, path_.c_str(), RENAME_NOREPLACE) != 0) {
      const int err = errno;
      if (err == EEXIST)
        throw OutputError(path_, "", "already exists (use --overwrite to replace it)");
      if (err != EINVAL && err != ENOSYS)
        throw OutputError(path_, "", "cannot create the file: " + error_text(err));
      // The file system cannot rename without replacing: link() refuses an existing target.
      if (::link(temp_path_.c_str(), path_.c_str()) != 0) {
        const int link_err = errno;
        if (link_err == EEXIST)
          throw OutputError(path_, "", "already exists (use --overwrite to replace it)");
        throw OutputError(path_, "", "cannot create the file: " + error_text(link_err));
      }
      (void)::unlink(temp_path_.c_str());
    }
  }
  committed_ = true;
  sync_folder(folder_of(path_));
}

}  // namespace tincdt::io
