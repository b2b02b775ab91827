// Progress as a person at a terminal and a batch log see it: on a terminal one line redrawn in
// place ('\r'), each stage numbered and named for a person, percentages that never go back; on a
// pipe or a file GDAL's "0...10...100 - done." per stage; -q silent; --progress forces it.
#include <gtest/gtest.h>

#include <stdlib.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <regex>
#include <string>
#include <vector>

#include "support/files.hpp"
#include "support/pseudo_terminal.hpp"
#include "support/spawn.hpp"

namespace {

const std::string kSample = std::string(TINCDT_SOURCE_DIR) + "/data/sample.las";
const std::string kContours = std::string(TINCDT_SOURCE_DIR) + "/data/sample_contours.shp";

// The sample with its contours and every product that reports in phases (the DEM: rasterize,
// then write, fine enough for GDAL to report its writing; the contour lines: trace, then write).
std::vector<std::string> full_job(const std::string& dir) {
  return {kSample,
          "--contours",
          kContours,
          "-o",
          dir + "/t.ply",
          "--dem",
          dir + "/d.tif",
          "--resolution",
          "0.1",
          "--contour-lines",
          dir + "/c.gpkg",
          "--interval",
          "1",
          "--overwrite"};
}

// The internal stage names, which a person should not have to read.
const std::vector<std::string> kInternalNames = {"read", "delaunay", "constraints", "contour_lines",
                                                 "dem",  "write",    "commit",      "stats"};

struct Drawn {
  int number, count, percent;
  std::string title;
};

// Each redraw of the progress line: "\r\x1b[K" then "[k/n] title [bar] pp% ...".
std::vector<Drawn> redraws(const std::string& screen) {
  const std::regex line(R"(^\[(\d+)/(\d+)\] (.+?) \[[#-]{20}\] +(\d+)%  )");
  std::vector<Drawn> out;
  const std::string erase = "\r\x1b[K";
  for (std::size_t at = screen.find(erase); at != std::string::npos;
       at = screen.find(erase, at + 1)) {
    const std::string rest = screen.substr(at + erase.size(), 200);
    std::smatch m;
    if (std::regex_search(rest, m, line))
      out.push_back({std::stoi(m[1]), std::stoi(m[2]), std::stoi(m[4]), m[3]});
  }
  return out;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  for (std::size_t nl = text.find('\n'); nl != std::string::npos; nl = text.find('\n', start)) {
    lines.push_back(text.substr(start, nl - start));
    start = nl + 1;
  }
  if (start < text.size()) lines.push_back(text.substr(start));
  return lines;
}

class ProgressCli : public ::testing::Test {
 protected:
  ProgressCli()
      : dir_(tincdt::test::scratch_dir("progress")),
        capture_(tincdt::test::scratch_dir("progress-capture")) {}

  tincdt::test::Spawned run_piped(std::vector<std::string> args) const {
    args.insert(args.begin(), TINCDT_EXE);
    return tincdt::test::spawn_captured(args, dir_, capture_);
  }
  tincdt::test::TerminalRun run_on_terminal(std::vector<std::string> args) const {
    args.insert(args.begin(), TINCDT_EXE);
    return tincdt::test::run_on_terminal(args, dir_);
  }

  std::string dir_;
  std::string capture_;
};

// tincdt data/sample.las --contours data/sample_contours.shp -o t.ply --dem d.tif --resolution 0.1
//   --contour-lines c.gpkg --interval 1 --overwrite      (stderr a terminal)
TEST_F(ProgressCli, OnATerminalOneLineRedrawnWithHumanNamesNeverGoingBack) {
  const tincdt::test::TerminalRun r = run_on_terminal(full_job(dir_));
  ASSERT_EQ(r.exit_code, 0) << r.screen;
  const std::vector<Drawn> drawn = redraws(r.screen);
  ASSERT_GE(drawn.size(), 6u) << r.screen;
  std::vector<std::string> titles;
  for (std::size_t i = 0; i < drawn.size(); ++i) {
    const Drawn& d = drawn[i];
    SCOPED_TRACE(d.title);
    EXPECT_EQ(d.count, drawn.front().count);
    EXPECT_GE(d.number, 1);
    EXPECT_LE(d.number, d.count);
    for (const std::string& internal : kInternalNames) EXPECT_NE(d.title, internal);
    if (titles.empty() || titles.back() != d.title) titles.push_back(d.title);
    if (i == 0) continue;
    const Drawn& before = drawn[i - 1];
    EXPECT_GE(d.number, before.number) << "the stages run in order";
    if (d.number == before.number) {
      EXPECT_EQ(d.title, before.title);
      EXPECT_GE(d.percent, before.percent) << "a stage's percent never goes back";
    }
  }
  for (const char* title : {"reading the inputs", "triangulating", "inserting breaklines",
                            "writing the TIN", "making the DEM", "tracing contour lines"})
    EXPECT_NE(std::find(titles.begin(), titles.end(), title), titles.end()) << title;
  EXPECT_EQ(drawn.back().number, drawn.back().count);
  EXPECT_NE(r.screen.find(" elapsed"), std::string::npos) << r.screen;
  // The line is erased before the summary, which is plain lines.
  const std::size_t summary = r.screen.find("tincdt: read ");
  ASSERT_NE(summary, std::string::npos) << r.screen;
  ASSERT_GE(summary, 4u);
  EXPECT_EQ(r.screen.substr(summary - 4, 4), "\r\x1b[K") << r.screen;
  EXPECT_EQ(r.screen.find('\r', summary), std::string::npos) << r.screen;
}

// N x N points, a jittered grid (a fixed sequence), as XYZ text at PATH.
void write_jittered_grid(const std::string& path, int n) {
  std::string text;
  text.reserve(static_cast<std::size_t>(n) * static_cast<std::size_t>(n) * 24);
  std::uint64_t state = 0x9E3779B97F4A7C15ULL;
  const auto jitter = [&state] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<int>((state >> 33) % 500);
  };
  char line[64];
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      std::snprintf(line, sizeof line, "%d.%03d %d.%03d 0.%03d\n", i, jitter(), j, jitter(),
                    jitter());
      text += line;
    }
  tincdt::test::spit(path, text);
}

// A stage that runs for seconds: its line shows the rate (points a second) and the time left.
// tincdt grid.xyz -o t.ply --threads 1      (2.56 million points; stderr a terminal)
// Long is the machine's to say: the grid grows until triangulating takes 2 s (a stage that
// ends within a second of its last report never shows a time left).
TEST_F(ProgressCli, OnATerminalALongStageShowsItsRateAndTimeLeft) {
  const std::regex triangulating(
      R"(\[2/3\] triangulating \[[#-]{20}\] +\d+%  [0-9.]+[kM]? points/s  \d+:\d\d elapsed  )"
      R"(\d+:\d\d left)");
  const std::regex delaunay_time(R"(delaunay ([0-9.]+) s)");
  for (const int side : {1600, 2400, 3200}) {
    write_jittered_grid(dir_ + "/grid.xyz", side);
    const tincdt::test::TerminalRun r = run_on_terminal(
        {dir_ + "/grid.xyz", "-o", dir_ + "/t.ply", "--threads", "1", "--overwrite"});
    std::filesystem::remove(dir_ + "/grid.xyz");
    std::filesystem::remove(dir_ + "/t.ply");
    ASSERT_EQ(r.exit_code, 0) << r.screen;
    if (std::regex_search(r.screen, triangulating)) return;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(r.screen, m, delaunay_time)) << r.screen;
    ASSERT_LT(std::stod(m[1]), 2.0) << "a long stage without a time left\n"
                                    << r.screen.substr(0, 4000);
  }
  FAIL() << "triangulating a 3200 x 3200 grid took less than 2 s on this machine";
}

// The same job with stderr a file: one GDAL line per stage, every stage in order, no '\r'.
TEST_F(ProgressCli, ElsewhereGdalLinesPerStage) {
  const tincdt::test::Spawned r = run_piped(full_job(dir_));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find('\r'), std::string::npos) << r.err;
  const std::regex stage_line(
      R"(^tincdt: \[(\d+)/(\d+)\] (.+) 0\.\.\.10\.\.\.20\.\.\.30\.\.\.40\.\.\.50\.\.\.60\.\.\.70)"
      R"(\.\.\.80\.\.\.90\.\.\.100 - done\.$)");
  int expected = 1, count = 0;
  for (const std::string& line : lines_of(r.err)) {
    std::smatch m;
    if (!std::regex_match(line, m, stage_line)) continue;
    EXPECT_EQ(std::stoi(m[1]), expected) << line;
    count = std::stoi(m[2]);
    for (const std::string& internal : kInternalNames) EXPECT_NE(m[3].str(), internal);
    ++expected;
  }
  EXPECT_GE(count, 6) << r.err;
  EXPECT_EQ(expected, count + 1) << "every stage has its line\n" << r.err;
  EXPECT_NE(r.err.find("tincdt: [2/" + std::to_string(count) + "] triangulating 0..."),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("tincdt: TIN: "), std::string::npos) << "the summary follows";
}

// tincdt -q data/sample.las -o t.ply: nothing at all.
TEST_F(ProgressCli, QuietPrintsNoProgress) {
  const tincdt::test::Spawned piped = run_piped({"-q", kSample, "-o", dir_ + "/t.ply"});
  EXPECT_EQ(piped.exit_code, 0) << piped.err;
  EXPECT_EQ(piped.err, "");
  const tincdt::test::TerminalRun shown =
      run_on_terminal({"-q", kSample, "-o", dir_ + "/t.ply", "--overwrite"});
  EXPECT_EQ(shown.exit_code, 0) << shown.screen;
  EXPECT_EQ(shown.screen, "");
}

// tincdt -q --progress data/sample.las -o t.ply: the progress alone, in either form.
TEST_F(ProgressCli, ProgressFlagForcesItPastQuiet) {
  const tincdt::test::Spawned piped =
      run_piped({"-q", "--progress", kSample, "-o", dir_ + "/t.ply"});
  ASSERT_EQ(piped.exit_code, 0) << piped.err;
  const std::vector<std::string> lines = lines_of(piped.err);
  ASSERT_FALSE(lines.empty());
  for (const std::string& line : lines)
    EXPECT_TRUE(
        std::regex_match(line, std::regex(R"(tincdt: \[\d+/\d+\] .+ 0\.\.\..*100 - done\.)")))
        << line;
  const tincdt::test::TerminalRun shown =
      run_on_terminal({"-q", "--progress", kSample, "-o", dir_ + "/t.ply", "--overwrite"});
  ASSERT_EQ(shown.exit_code, 0) << shown.screen;
  EXPECT_FALSE(redraws(shown.screen).empty()) << shown.screen;
  EXPECT_EQ(shown.screen.find("tincdt: TIN"), std::string::npos) << shown.screen;
}

// Ctrl-C at the Delaunay stage, on a terminal: the job stops by the progress callback, the line
// is erased and the message says so; no file is written. (TINCDT_TEST_SIGNAL raises SIGINT as
// the stage starts.)
TEST_F(ProgressCli, CtrlCOnATerminalErasesTheLineAndStops) {
  ::setenv("TINCDT_TEST_SIGNAL", "delaunay:INT", 1);
  const tincdt::test::TerminalRun r = run_on_terminal({kSample, "-o", dir_ + "/stopped.ply"});
  ::unsetenv("TINCDT_TEST_SIGNAL");
  EXPECT_EQ(r.exit_code, -1) << "ends by the signal\n" << r.screen;
  EXPECT_NE(r.screen.find("[2/3] triangulating"), std::string::npos) << r.screen;
  EXPECT_NE(r.screen.find("\r\x1b[Ktincdt: error: interrupted; no file was changed\n"),
            std::string::npos)
      << r.screen;
  EXPECT_FALSE(std::filesystem::exists(dir_ + "/stopped.ply"));
}

// An error before any progress is still the only line: tincdt missing.las -o t.ply.
TEST_F(ProgressCli, AnErrorAtOnceIsTheOnlyLine) {
  const tincdt::test::Spawned r = run_piped({dir_ + "/missing.las", "-o", dir_ + "/t.ply"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(lines_of(r.err).size(), 1u) << r.err;
  EXPECT_EQ(r.err.rfind("tincdt: error: ", 0), 0u) << r.err;
}

}  // namespace
