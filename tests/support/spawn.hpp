// A program run word for word (no shell), its standard output and error captured, for the tests
// of the command line.
#pragma once

#include <fcntl.h>
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "support/files.hpp"

extern char** environ;

namespace tincdt::test {

struct Spawned {
  int exit_code = -1;  // -1 when killed by a signal
  std::string out;
  std::string err;
};

// Runs ARGV (ARGV[0] the program, found on PATH) in folder DIR, standard input from STDIN_PATH;
// its output goes through files in the folder CAPTURE.
inline Spawned spawn_captured(std::vector<std::string> argv, const std::filesystem::path& dir,
                              const std::filesystem::path& capture,
                              const std::string& stdin_path = "/dev/null") {
  const std::string out_path = (capture / "stdout").string();
  const std::string err_path = (capture / "stderr").string();
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, stdin_path.c_str(), O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                   0644);
  posix_spawn_file_actions_addopen(&actions, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                   0644);
  std::vector<char*> words;
  for (std::string& a : argv) words.push_back(a.data());
  words.push_back(nullptr);
  const std::filesystem::path here = std::filesystem::current_path();
  std::filesystem::current_path(dir);
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, words[0], &actions, nullptr, words.data(), environ);
  std::filesystem::current_path(here);
  posix_spawn_file_actions_destroy(&actions);
  Spawned r;
  if (rc != 0) {
    ADD_FAILURE() << "cannot run " << argv[0] << ": " << std::strerror(rc);
    return r;
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(out_path);
  r.err = slurp(err_path);
  return r;
}

}  // namespace tincdt::test
