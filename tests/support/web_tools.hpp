// The test-only web tools (tests/web: npm packages that read tincdt's web outputs
// independently), installed by cmake/setup_web_tools.sh. A user's clone may have neither Node.js
// nor them: tests that need them skip, saying how to install them.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace tincdt::test {

// The node_modules folder of tests/web: $TINCDT_WEB_TOOLS when set, else the configured one.
inline std::filesystem::path web_tools() {
  const char* env = std::getenv("TINCDT_WEB_TOOLS");
  return env != nullptr && *env != '\0' ? std::filesystem::path(env)
                                        : std::filesystem::path(TINCDT_WEB_TOOLS_DEFAULT);
}

}  // namespace tincdt::test

// Skips the current test unless Node.js and the npm package PACKAGE of tests/web are installed.
#define TINCDT_REQUIRE_WEB_TOOL(package)                                                          \
  do {                                                                                            \
    if (std::system("node --version >/dev/null 2>&1") != 0 ||                                     \
        !std::filesystem::is_directory(::tincdt::test::web_tools() / (package))) {                \
      GTEST_SKIP() << "Node.js or the npm package " << (package) << " not found under "           \
                   << ::tincdt::test::web_tools() << " (install them: cmake/setup_web_tools.sh)"; \
    }                                                                                             \
  } while (false)
