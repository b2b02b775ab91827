// The real test data beside the clone (see its PROVENANCE.md): tests that need it skip with a
// message when it is absent, so that a user's clone, which has none, passes the suite.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace tincdt::test {

// The folder of the shared data: $TINCDT_SHARED_DATA when set (CI sets it to a missing folder to
// run the suite as a user's clone does), else the one configured at build time.
inline std::string shared_data() {
  const char* env = std::getenv("TINCDT_SHARED_DATA");
  return env != nullptr && *env != '\0' ? std::string(env)
                                        : std::string(TINCDT_SHARED_DATA_DEFAULT);
}

// The path of RELATIVE (e.g. "laz/simple.laz") in the shared data.
inline std::string shared_file(const std::string& relative) {
  return (std::filesystem::path(shared_data()) / relative).string();
}

}  // namespace tincdt::test

// Skips the current test unless the shared data's folder SUBFOLDER is there.
#define TINCDT_REQUIRE_SHARED_DATA(subfolder)                                             \
  do {                                                                                    \
    const std::filesystem::path tincdt_shared_folder_ =                                   \
        std::filesystem::path(::tincdt::test::shared_data()) / (subfolder);               \
    if (!std::filesystem::is_directory(tincdt_shared_folder_)) {                          \
      GTEST_SKIP() << "shared test data not found at " << tincdt_shared_folder_           \
                   << " (the project's real-data tests need the shared data folder; see " \
                      "PROVENANCE.md there)";                                             \
    }                                                                                     \
  } while (false)
