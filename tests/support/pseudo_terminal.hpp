// A program run with its standard error on a pseudo-terminal, as a user at a terminal sees it:
// for the tests of what the command line draws there (isatty() is true for its stderr only).
#pragma once

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/ioctl.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace tincdt::test {

struct TerminalRun {
  int exit_code = -1;  // -1 when killed by a signal
  std::string screen;  // every byte written to the terminal, as written (no '\n' -> "\r\n")
};

// Runs ARGV (ARGV[0] a path) in folder DIR with standard error on a new pseudo-terminal of
// COLUMNS columns; standard input is /dev/null, standard output is discarded.
inline TerminalRun run_on_terminal(std::vector<std::string> argv, const std::string& dir,
                                   int columns = 120) {
  TerminalRun r;
  const int master = ::posix_openpt(O_RDWR | O_NOCTTY);
  if (master < 0 || ::grantpt(master) != 0 || ::unlockpt(master) != 0) {
    ADD_FAILURE() << "no pseudo-terminal: " << std::strerror(errno);
    return r;
  }
  // Opened here, before the fork, so that the terminal has a reader and a writer throughout.
  const int slave = ::open(::ptsname(master), O_RDWR | O_NOCTTY);
  if (slave < 0) {
    ADD_FAILURE() << "cannot open the pseudo-terminal: " << std::strerror(errno);
    ::close(master);
    return r;
  }
  termios mode{};
  ::tcgetattr(slave, &mode);
  mode.c_oflag &= ~static_cast<tcflag_t>(OPOST);  // bytes as the program writes them
  ::tcsetattr(slave, TCSANOW, &mode);
  const winsize size{24, static_cast<unsigned short>(columns), 0, 0};
  ::ioctl(slave, TIOCSWINSZ, &size);
  std::vector<char*> words;
  for (std::string& a : argv) words.push_back(a.data());
  words.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int null_in = ::open("/dev/null", O_RDONLY);
    const int null_out = ::open("/dev/null", O_WRONLY);
    if (null_in < 0 || null_out < 0 || ::chdir(dir.c_str()) != 0) ::_exit(120);
    ::dup2(null_in, 0);
    ::dup2(null_out, 1);
    ::dup2(slave, 2);
    ::close(master);
    ::close(slave);
    ::execv(words[0], words.data());
    ::_exit(127);
  }
  ::close(slave);
  char buffer[4096];
  while (true) {  // until the program's end closes the terminal's last writer (EIO)
    const ssize_t n = ::read(master, buffer, sizeof buffer);
    if (n > 0)
      r.screen.append(buffer, static_cast<std::size_t>(n));
    else if (n < 0 && errno == EINTR)
      continue;
    else
      break;
  }
  ::close(master);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

}  // namespace tincdt::test
