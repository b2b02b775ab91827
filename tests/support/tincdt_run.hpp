// The tincdt binary (TINCDT_EXE) run through the shell, as a user types it: ARGS is one string,
// quoted as in sh. For the CLI tests that look at the exit code and the messages only.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <ostream>
#include <set>
#include <span>
#include <string>
#include <utility>

#include "support/files.hpp"

namespace tincdt::test {

struct ShellRun {
  int exit_code;         // as the shell saw it (a signal S: 128 + S)
  std::string messages;  // standard error
};

inline std::ostream& operator<<(std::ostream& os, const ShellRun& r) {
  return os << "exit " << r.exit_code << "\n" << r.messages;
}

// tincdt ARGS in folder DIR, standard output discarded.
inline ShellRun run_tincdt(const std::string& dir, const std::string& args) {
  const std::string err = dir + "/stderr.txt";
  const int status = std::system(
      ("cd '" + dir + "' && '" TINCDT_EXE "' " + args + " 2> '" + err + "' > /dev/null").c_str());
  ShellRun r{WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(err)};
  std::filesystem::remove(err);
  return r;
}

// Whether R's messages hold TEXT.
inline bool has(const ShellRun& r, const std::string& text) {
  return r.messages.find(text) != std::string::npos;
}

// PATH quoted for the shell.
inline std::string quoted(const std::filesystem::path& path) {
  std::string q = "'";  // built in steps: GCC 12's -Wrestrict misfires on "'" + s + "'"
  q += path.string();
  q += "'";
  return q;
}

// tincdt ARGS in DIR succeeds (exit 0).
inline void expect_success(const std::filesystem::path& dir, const std::string& args) {
  const ShellRun r = run_tincdt(dir.string(), args);
  EXPECT_EQ(r.exit_code, 0) << args << ": " << r.messages;
}

// Each case {ARGS, TEXT}: `tincdt PREFIX ARGS` in DIR is a usage error (exit 2) whose message
// holds TEXT; and DIR stays empty (nothing written, no temporary left).
inline void expect_usage_errors(const std::string& dir, const std::string& prefix,
                                std::span<const std::pair<std::string, std::string>> cases) {
  for (const auto& [args, text] : cases) {
    SCOPED_TRACE(args);
    const ShellRun r = run_tincdt(dir, prefix + " " + args);
    EXPECT_EQ(r.exit_code, 2) << r.messages;
    EXPECT_NE(r.messages.find(text), std::string::npos) << r.messages;
  }
  EXPECT_EQ(names_in(dir), std::set<std::string>{});
}

}  // namespace tincdt::test
