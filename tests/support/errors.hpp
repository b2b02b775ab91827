// Error helpers shared by the tests.
#pragma once

#include <functional>
#include <string>

#include "core/error.hpp"

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

}  // namespace tincdt::test
