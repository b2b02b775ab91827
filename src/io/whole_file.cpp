#include "io/whole_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <system_error>

#include "core/error.hpp"

namespace tincdt::io {

void write_whole_file(const std::string& path, std::string_view bytes) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!parent.empty() && !std::filesystem::is_directory(parent, ec)) {
    std::filesystem::create_directories(parent, ec);
    if (ec) throw OutputError(parent.string(), "", "cannot create the folder: " + ec.message());
  }
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  const auto fail = [&](const char* what) {
    const int err = errno;
    if (fd >= 0) (void)::close(fd);
    throw OutputError(path, "", what + std::generic_category().message(err));
  };
  if (fd < 0) fail("cannot create the file: ");
  for (std::size_t done = 0; done < bytes.size();) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail("write failed: ");
    done += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) fail("cannot flush to disk: ");
  if (::close(fd) != 0) {
    const int err = errno;
    throw OutputError(path, "", "cannot close: " + std::generic_category().message(err));
  }
}

}  // namespace tincdt::io
