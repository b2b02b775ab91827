// File helpers shared by the tests: whole files in and out, folder listings, scratch folders.
// Header-only; every test target has tests/ on its include path and defines TINCDT_TEST_TMP.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

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

}  // namespace tincdt::test
