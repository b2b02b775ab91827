// The README is what users copy and what CI runs: its quick-start block must hold the two
// commands, and cmake/readme_commands.sh must refuse every way a formatter or an edit has broken
// it (each broken copy below is made from the real README). It must also document every option
// of `tincdt --help`.

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <regex>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "support/files.hpp"

namespace tincdt {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const fs::path kSource = TINCDT_SOURCE_DIR;
const fs::path kScript = kSource / "cmake" / "readme_commands.sh";
const fs::path kTmp = fs::path(TINCDT_TEST_TMP) / "readme";

struct Outcome {
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

// Runs COMMAND with sh; its output, stderr included.
Outcome run(const std::string& command) {
  Outcome r;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) {
    ADD_FAILURE() << "cannot run " << command;
    return r;
  }
  char buf[4096];
  for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, pipe)) > 0;) r.output.append(buf, n);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

std::string quoted(const fs::path& p) {
  std::string q = "'";  // appended, not '+': GCC 12's -Wrestrict misfires on "'" + string
  q += p.string();
  q += '\'';
  return q;
}

Outcome readme_commands(const fs::path& readme, const std::string& action) {
  return run("bash " + quoted(kScript) + " --readme " + quoted(readme) + " " + action);
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  for (std::size_t end; (end = text.find('\n', start)) != std::string::npos; start = end + 1)
    lines.push_back(text.substr(start, end - start));
  if (start < text.size()) lines.push_back(text.substr(start));
  return lines;
}

// ---- the real README ----

TEST(ReadmeCommands, TheRealReadmeHoldsInstallBuildRunAndTest) {
  const Outcome r = readme_commands(kSource / "README.md", "check");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::vector<std::string> commands = lines_of(r.output);
  ASSERT_EQ(commands.size(), 2u) << r.output;
  EXPECT_THAT(commands[0], HasSubstr("cmake/setup.sh"));
  EXPECT_THAT(commands[0], HasSubstr("--preset release"));
  EXPECT_THAT(commands[0], HasSubstr("tincdt data/sample.las"));
  EXPECT_THAT(commands[1], HasSubstr("cmake/setup.sh"));
  EXPECT_THAT(commands[1], HasSubstr("--preset test"));
  for (const int n : {1, 2}) {
    const Outcome one = readme_commands(kSource / "README.md", "print " + std::to_string(n));
    EXPECT_EQ(one.exit_code, 0) << one.output;
    EXPECT_EQ(one.output, commands[static_cast<std::size_t>(n - 1)] + "\n");
  }
}

TEST(ReadmeCommands, RefusesACommandNumberOtherThanOneOrTwo) {
  const Outcome r = readme_commands(kSource / "README.md", "print 3");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("no command '3'"));
}

TEST(ReadmeCommands, RefusesAMissingFile) {
  const Outcome r = readme_commands(kTmp / "no_such_readme.md", "check");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_THAT(r.output, HasSubstr("no such file"));
}

// ---- broken copies of it ----

// A way to break the README: each edit replaces the first FROM with TO; the script must fail
// with MESSAGE. The quick-start block is the README's first, so "--preset test\n```" is its end.
struct Breakage {
  std::string name;
  std::vector<std::pair<std::string, std::string>> edits;
  std::string message;
};

std::ostream& operator<<(std::ostream& os, const Breakage& b) {
  return os << b.name;
}

const std::string kCommand2 = "cmake/setup.sh && cmake --workflow --preset test";
const std::string kBlockEnd = "--preset test\n```\n";

const std::vector<Breakage> kBreakages = {
    // What a code formatter does to Markdown.
    {"formatter_heading", {{"# tincdt\n", "#tincdt\n"}}, "heading without a space after '#'"},
    {"formatter_torn_options",
     {{"cmake --workflow --preset", "cmake-- workflow-- preset"}},
     "'-- word'"},
    {"formatter_torn_path",
     {{"```sh\ncmake/setup.sh", "```sh\ncmake / setup.sh"}},
     "path torn apart"},
    {"formatter_torn_short_option",
     {{" -o sample_tin.ply", " - o sample_tin.ply"}},
     "'word - word'"},
    {"formatter_text_on_the_fence",
     {{"```sh\ncmake/setup.sh", "```sh cmake/setup.sh"}},
     "must open alone on its line"},
    // What an edit does.
    {"missing_heading",
     {{"## Quick start\n", "## Getting started\n"}},
     "no '## Quick start' heading"},
    {"missing_block",
     {{"```sh\ncmake/setup.sh", "cmake/setup.sh"}, {kBlockEnd, "--preset test\n"}},
     "no fenced block under '## Quick start'"},
    {"one_command", {{"\n" + kCommand2 + "\n```", "\n```"}}, "holds 1 commands, not 2"},
    {"three_commands",
     {{kBlockEnd, "--preset test\nctest --preset test\n```\n"}},
     "holds 3 commands, not 2"},
    {"unparsable_command",
     {{kCommand2, "cmake/setup.sh && && cmake --workflow --preset test"}},
     "command 2 does not parse as shell"},
    {"unclosed_block", {{kBlockEnd, "--preset test\n"}}, "never closed"},
    {"second_block",
     {{kBlockEnd, kBlockEnd + "\n```sh\nctest --preset test\n```\n"}},
     "a second fenced block"},
};

class BrokenReadme : public ::testing::TestWithParam<Breakage> {};

TEST_P(BrokenReadme, FailsNamingTheProblem) {
  const Breakage& b = GetParam();
  std::string text = test::slurp(kSource / "README.md");
  ASSERT_FALSE(text.empty());
  for (const auto& [from, to] : b.edits) {
    const std::size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << "the README has no '" << from << "' to break";
    text.replace(at, from.size(), to);
  }
  fs::create_directories(kTmp);
  const fs::path copy = kTmp / (b.name + ".md");
  test::spit(copy, text);
  for (const std::string action : {"check", "print 1"}) {
    const Outcome r = readme_commands(copy, action);
    EXPECT_EQ(r.exit_code, 1) << action << ": " << r.output;
    EXPECT_THAT(r.output, HasSubstr(b.message)) << action;
    EXPECT_THAT(r.output, HasSubstr(copy.string())) << action;
  }
}

INSTANTIATE_TEST_SUITE_P(Formatter, BrokenReadme, ::testing::ValuesIn(kBreakages),
                         [](const ::testing::TestParamInfo<Breakage>& p) { return p.param.name; });

// ---- the options ----

// Every long option `tincdt --help` lists ("--stats", "--z-from-m", ...).
std::set<std::string> help_options() {
  const Outcome r = run(quoted(TINCDT_EXE) + " --help");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  std::set<std::string> options;
  const std::regex option(R"((^|[\s,])(--[a-z][a-z0-9-]*))");
  for (const std::string& line : lines_of(r.output)) {
    if (line.rfind("  ", 0) != 0 || line.rfind("    tincdt", 0) == 0) continue;  // not examples
    for (std::sregex_iterator it(line.begin(), line.end(), option), end; it != end; ++it)
      options.insert((*it)[2]);
  }
  return options;
}

TEST(ReadmeOptions, DocumentsEveryOptionOfHelp) {
  const std::set<std::string> options = help_options();
  ASSERT_GT(options.size(), 20u);
  const std::string readme = test::slurp(kSource / "README.md");
  for (const std::string& o : options) {
    const std::regex documented("`" + o + "[ `]");
    EXPECT_TRUE(std::regex_search(readme, documented)) << o << " is not in README.md";
  }
}

}  // namespace
}  // namespace tincdt
