// File helpers shared by the tests: whole files in and out, folder listings, scratch folders,
// the mode a new file gets, a file-size limit (a full disk, simulated).
// Header-only; every test target has tests/ on its include path and defines TINCDT_TEST_TMP.
#pragma once

#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/stat.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>
#include <string>
#include <utility>

namespace tincdt::test {

// The whole file, as bytes; "" when it cannot be read.
inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Replaces the file with BYTES; a failed write fails the test.
inline void spit(const std::filesystem::path& p, const std::string& bytes) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out << bytes;
  ASSERT_TRUE(out.good()) << p;
}

// The names of the entries of DIR.
inline std::set<std::string> names_in(const std::filesystem::path& dir) {
  std::set<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    names.insert(e.path().filename().string());
  }
  return names;
}

// BYTES written to TINCDT_TEST_TMP/FOLDER/NAME (the folder made when missing); its path.
inline std::string scratch_file(const std::string& folder, const std::string& name,
                                const std::string& bytes) {
  const std::filesystem::path dir = std::filesystem::path(TINCDT_TEST_TMP) / folder;
  std::filesystem::create_directories(dir);
  spit(dir / name, bytes);
  return (dir / name).string();
}

// A test file's scratch folder: scratch("name", bytes) writes a file there and gives its path.
class ScratchFolder {
 public:
  explicit ScratchFolder(std::string folder) : folder_(std::move(folder)) {}
  std::string operator()(const std::string& name, const std::string& bytes) const {
    return scratch_file(folder_, name, bytes);
  }
  std::filesystem::path path() const { return std::filesystem::path(TINCDT_TEST_TMP) / folder_; }

 private:
  std::string folder_;
};

// DIR, emptied (and created when missing).
inline std::filesystem::path fresh_dir(const std::filesystem::path& dir) {
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// A fresh, empty scratch folder for the current test: TINCDT_TEST_TMP/FOLDER/Suite.Name.
inline std::string scratch_dir(const std::string& folder) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  return fresh_dir(std::filesystem::path(TINCDT_TEST_TMP) / folder /
                   (std::string(info->test_suite_name()) + "." + info->name()))
      .string();
}

// The permission bits of PATH once CREATE made it under umask 022: a new output must get the
// usual 0644, not the 0600 of a temporary file.
inline unsigned mode_when_created(const std::string& path, const std::function<void()>& create) {
  const mode_t old = ::umask(022);
  create();
  ::umask(old);
  struct stat st {};
  EXPECT_EQ(::stat(path.c_str(), &st), 0) << path;
  return st.st_mode & 0777;
}

// While it lives, files this process writes may not grow beyond BYTES: write(2) then fails with
// EFBIG, as a full disk fails with ENOSPC (SIGXFSZ is ignored meanwhile).
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) : old_handler_(std::signal(SIGXFSZ, SIG_IGN)) {
    EXPECT_EQ(::getrlimit(RLIMIT_FSIZE, &old_limit_), 0);
    rlimit small = old_limit_;
    small.rlim_cur = bytes;
    EXPECT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
  }
  ~FileSizeLimit() {
    ::setrlimit(RLIMIT_FSIZE, &old_limit_);
    std::signal(SIGXFSZ, old_handler_);
  }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;

 private:
  void (*old_handler_)(int);
  rlimit old_limit_{};
};

}  // namespace tincdt::test
