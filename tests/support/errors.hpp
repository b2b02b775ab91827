// Error helpers shared by the tests.
#pragma once

#include <gtest/gtest.h>

#include <functional>
#include <optional>
#include <string>

#include "core/error.hpp"
#include "support/files.hpp"

namespace tincdt::test {

// The message of the tincdt::Error that F throws, or "no error".
inline std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

// The error of type E that F throws; a test failure, and nullopt, when F throws none.
template <class E>
std::optional<E> thrown(const std::function<void()>& f) {
  try {
    f();
  } catch (const E& e) {
    return e;
  }
  ADD_FAILURE() << "no exception";
  return std::nullopt;
}

// WRITE, aimed at PATH where a file already is, must refuse with an OutputError naming PATH
// ("already exists", and replacing it as the way out) and leave that file as it was.
inline void expect_no_overwrite(const std::string& path, const std::function<void()>& write) {
  spit(path, "precious");
  if (const auto e = thrown<OutputError>(write)) {
    EXPECT_EQ(e->file(), path);
    EXPECT_NE(e->detail().find("already exists"), std::string::npos) << e->what();
    EXPECT_EQ(e->remedy(), Remedy::overwrite) << e->what();
  }
  EXPECT_EQ(slurp(path), "precious");
}

}  // namespace tincdt::test
