// The real data beside the clone (TINCDT_SHARED_DATA, see its PROVENANCE.md): tests that need
// it skip with a message when it is absent.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>

namespace tincdt::test {
inline const std::filesystem::path kSharedData = TINCDT_SHARED_DATA;
}  // namespace tincdt::test

// Skips the current test unless the shared data's folder SUBFOLDER is there.
#define TINCDT_REQUIRE_SHARED_DATA(subfolder)                                              \
  do {                                                                                     \
    if (!std::filesystem::is_directory(::tincdt::test::kSharedData / (subfolder))) {       \
      GTEST_SKIP() << "shared test data not found at "                                     \
                   << ::tincdt::test::kSharedData / (subfolder) << " (see PROVENANCE.md)"; \
    }                                                                                      \
  } while (false)
