// Ctrl-C in the middle of a long stage: tincdt started on generated points big enough that the
// stage takes seconds, SIGINT sent once its progress line shows it well begun; the process dies
// of SIGINT (a shell reports 130) within a second, the stage unfinished, and the folder holds the
// inputs only (no output, no temporary).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "support/files.hpp"
#include "support/splitmix.hpp"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// The bound on the time from the signal to the process's end: the stages look for a request to
// stop at least every 1/200 of their work and every 2^16 inner steps. AddressSanitizer slows
// every step (and the unwinding) several times over, so it gets more.
#if defined(__SANITIZE_ADDRESS__)
constexpr double kBoundSeconds = 3;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr double kBoundSeconds = 3;
#else
constexpr double kBoundSeconds = 1;
#endif
#else
constexpr double kBoundSeconds = 1;
#endif

// COUNT random points over a 2 km square on a rolling surface (slopes every way), as x y z lines.
void write_points(const fs::path& path, std::size_t count, std::uint64_t seed) {
  tincdt::test::SplitMix64 random{seed};
  std::string text;
  text.reserve(count * 28);
  char line[96];
  for (std::size_t i = 0; i < count; ++i) {
    const double x = random.unit() * 2000, y = random.unit() * 2000;
    const double z = 50 + 20 * std::sin(x / 97) * std::cos(y / 61) + 0.01 * x;
    const int n = std::snprintf(line, sizeof line, "%.3f %.3f %.3f\n", x, y, z);
    text.append(line, static_cast<std::size_t>(n));
  }
  tincdt::test::spit(path, text);
}

struct Interrupted {
  bool signalled = false;  // SIGINT was sent (the stage was seen far enough)
  int exit_code = -1;      // -1 when ended by a signal
  int signal = 0;          // the signal that ended it
  double seconds = -1;     // from the signal to the end
  std::string messages;    // standard error, whole
};

// Whether MESSAGES show the stage titled TITLE PERCENT done: "title 0...10...20...", or with
// log lines between its marks ("title 0..", a line, "title .10", a line, "title 20."); a slow
// start shows "title 0" alone before the stage's first lines.
bool reached(const std::string& messages, const std::string& title, int percent) {
  const std::string start = title + " 0";
  std::size_t at = messages.find(start);
  while (at != std::string::npos && at + start.size() < messages.size() &&
         messages[at + start.size()] != '.' && messages[at + start.size()] != '\n')
    at = messages.find(start, at + 1);
  if (at == std::string::npos) return false;
  const std::string mark = std::to_string(percent);
  const auto apart = [](char c) { return c == '.' || c == ' ' || c == '\n'; };
  for (std::size_t i = messages.find(mark, at); i != std::string::npos;
       i = messages.find(mark, i + 1)) {
    const std::size_t end = i + mark.size();
    if (apart(messages[i - 1]) && end < messages.size() && apart(messages[end])) return true;
  }
  return false;
}

// tincdt ARGS with --progress, its standard error read as it comes; SIGINT once the stage
// TITLE is PERCENT done; then waits for the end.
Interrupted interrupt_in(const std::vector<std::string>& args, const std::string& title,
                         int percent) {
  Interrupted r;
  int pipe_fds[2];
  if (::pipe(pipe_fds) != 0) {
    ADD_FAILURE() << "pipe: " << std::strerror(errno);
    return r;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], 2);
  posix_spawn_file_actions_addclose(&actions, pipe_fds[0]);
  std::vector<std::string> argv{TINCDT_EXE};
  argv.insert(argv.end(), args.begin(), args.end());
  argv.emplace_back("--progress");
  std::vector<char*> words;
  for (std::string& a : argv) words.push_back(a.data());
  words.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, TINCDT_EXE, &actions, nullptr, words.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(pipe_fds[1]);
  if (rc != 0) {
    ::close(pipe_fds[0]);
    ADD_FAILURE() << "cannot run tincdt: " << std::strerror(rc);
    return r;
  }
  // Read until the stage shows, or the run ends (the pipe closes), or a minute passes.
  const Clock::time_point give_up = Clock::now() + std::chrono::seconds(60);
  Clock::time_point sent{};
  char buffer[4096];
  while (true) {
    pollfd p{pipe_fds[0], POLLIN, 0};
    if (::poll(&p, 1, 100) < 0 && errno != EINTR) break;
    if (p.revents != 0) {
      const ssize_t n = ::read(pipe_fds[0], buffer, sizeof buffer);
      if (n <= 0) break;
      r.messages.append(buffer, static_cast<std::size_t>(n));
    }
    if (!r.signalled && reached(r.messages, title, percent)) {
      sent = Clock::now();
      ::kill(pid, SIGINT);
      r.signalled = true;
    }
    if (Clock::now() > give_up) {
      ::kill(pid, SIGKILL);
      break;
    }
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (r.signalled) r.seconds = std::chrono::duration<double>(Clock::now() - sent).count();
  // What the process wrote after the signal (its last words) is still in the pipe.
  for (ssize_t n; (n = ::read(pipe_fds[0], buffer, sizeof buffer)) > 0;)
    r.messages.append(buffer, static_cast<std::size_t>(n));
  ::close(pipe_fds[0]);
  if (WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) r.signal = WTERMSIG(status);
  return r;
}

// Generated inputs, in a folder of each test's own (ctest runs tests side by side): many points
// for the stages whose work grows with the TIN (triangulating, writing), fewer for those that
// take seconds on a small TIN (a fine DEM, simplification), so that reaching the stage is quick.
class InterruptMidStage : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = tincdt::test::scratch_dir("interrupt_mid_stage"); }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);
  }

  std::string many_points() { return input("many.xyz", 600'000); }
  std::string few_points() { return input("few.xyz", 200'000); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  // ARGS interrupted once the stage TITLE is PERCENT done: killed by SIGINT within the bound,
  // before the stage ended, and nothing but the input left in the folder.
  void expect_interrupted(const std::vector<std::string>& args, const std::string& title,
                          int percent = 10) {
    const Interrupted r = interrupt_in(args, title, percent);
    ASSERT_TRUE(r.signalled) << "the stage \"" << title << "\" never showed:\n" << r.messages;
    EXPECT_EQ(r.signal, SIGINT) << "exit " << r.exit_code << "\n" << r.messages;
    EXPECT_LE(r.seconds, kBoundSeconds) << r.messages;
    const std::size_t stage = r.messages.find(title + " 0..");
    EXPECT_EQ(r.messages.find("100 - done.", stage), std::string::npos)
        << "the stage ended before the signal:\n"
        << r.messages;
    EXPECT_NE(r.messages.find("interrupted; no file was changed"), std::string::npos) << r.messages;
    EXPECT_EQ(tincdt::test::names_in(dir_), inputs_);
    std::printf("%s at %d%%: ended %.3f s after SIGINT\n", title.c_str(), percent, r.seconds);
  }

 private:
  std::string input(const std::string& name, std::size_t count) {
    write_points(dir_ / name, count, count);
    inputs_.insert(name);
    return path(name);
  }

  fs::path dir_;
  std::set<std::string> inputs_;
};

TEST_F(InterruptMidStage, Triangulating) {
  expect_interrupted({many_points(), "-o", path("t.ply")}, "triangulating");
}

// OBJ is text: the slowest of the TIN writers, so the stage lasts long enough to be caught.
TEST_F(InterruptMidStage, WritingTheTin) {
  expect_interrupted({many_points(), "-o", path("t.obj")}, "writing the TIN");
}

// 4,000 x 4,000 cells. The stage's first half is the rasterization, its second GDAL writing the
// COG (through GDAL's progress callback): a signal in each.
TEST_F(InterruptMidStage, MakingTheDem) {
  const std::vector<std::string> args = {few_points(),  "-o",           path("t.ply"), "--dem",
                                         path("d.tif"), "--resolution", "0.5"};
  expect_interrupted(args, "making the DEM", 10);
  expect_interrupted(args, "making the DEM", 70);
}

// 2,000 x 2,000 pixels. The stage's thirds: the rasterization, the shading and edges, GDAL
// writing the PNG (through GDAL's progress callback): a signal in the last two.
TEST_F(InterruptMidStage, DrawingThePreview) {
  const std::vector<std::string> args = {
      few_points(), "-o", path("t.ply"), "--preview", path("p.png"), "--preview-size", "2000"};
  expect_interrupted(args, "drawing the preview", 50);
  expect_interrupted(args, "drawing the preview", 80);
}

// About 14,000 lines into a GeoPackage; the signal in the second half, OGR writing them (the
// lines written are dropped, not indexed, before the file is discarded).
TEST_F(InterruptMidStage, WritingContourLines) {
  expect_interrupted(
      {few_points(), "-o", path("t.ply"), "--contour-lines", path("c.gpkg"), "--interval", "0.1"},
      "tracing contour lines", 80);
}

// The coarse tiles' greedy insertion runs over every vertex: the signal comes within one, early,
// and again later among the finer levels' many tiles.
TEST_F(InterruptMidStage, MakingTheWebTerrain) {
  const std::vector<std::string> args = {many_points(), "--a-srs",   "EPSG:32632",   "-o",
                                         path("t.ply"), "--terrain", path("terrain")};
  expect_interrupted(args, "making the web terrain", 10);
  expect_interrupted(args, "making the web terrain", 60);
}

TEST_F(InterruptMidStage, Simplifying) {
  expect_interrupted({few_points(), "-o", path("t.ply"), "--max-error", "0.01"}, "simplifying");
}

}  // namespace
