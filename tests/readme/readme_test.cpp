// The README is what users copy and what CI runs: its quick-start block must hold the two
// commands, and cmake/readme_commands.sh must refuse every way a formatter or an edit has broken
// it (each broken copy below is made from the real README). The README stays a front door of at
// most 300 lines; the manual behind it is docs/, whose options.md must document every option of
// `tincdt --help`, `tincdt plan --help` and `tincdt merge --help`. Neither may link outside the
// clone, nor to a file that is not there.

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

// Every long option the help of COMMAND lists ("--stats", "--z-from-m", ...), examples left out.
std::set<std::string> help_options(const std::string& command) {
  const Outcome r = run(quoted(TINCDT_EXE) + command + " --help");
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

// The section of docs/options.md under the heading "## TITLE", up to the next "## ".
std::string options_section(const std::string& title) {
  const std::string text = test::slurp(kSource / "docs" / "options.md");
  const std::string heading = "\n## " + title + "\n";
  const std::size_t start = text.find(heading);
  if (start == std::string::npos) {
    ADD_FAILURE() << "docs/options.md has no heading '## " << title << "'";
    return {};
  }
  const std::size_t end = text.find("\n## ", start + heading.size());
  return text.substr(start, end == std::string::npos ? std::string::npos : end - start);
}

struct HelpPage {
  std::string command;  // after "tincdt": "", " plan", " merge"
  std::string section;  // its heading in docs/options.md
};

std::ostream& operator<<(std::ostream& os, const HelpPage& page) {
  return os << "tincdt" << page.command << " --help";
}

class OptionsDoc : public ::testing::TestWithParam<HelpPage> {};

TEST_P(OptionsDoc, DocumentsEveryOptionOfTheHelp) {
  const HelpPage& page = GetParam();
  const std::set<std::string> options = help_options(page.command);
  ASSERT_GT(options.size(), 5u);
  const std::string doc = options_section(page.section);
  ASSERT_FALSE(doc.empty());
  for (const std::string& o : options) {
    const std::regex documented("`" + o + "[ `]");
    EXPECT_TRUE(std::regex_search(doc, documented))
        << o << " is not under '## " << page.section << "' in docs/options.md";
  }
}

INSTANTIATE_TEST_SUITE_P(Help, OptionsDoc,
                         ::testing::Values(HelpPage{"", "tincdt"}, HelpPage{" plan", "tincdt plan"},
                                           HelpPage{" merge", "tincdt merge"}),
                         [](const ::testing::TestParamInfo<HelpPage>& p) {
                           return p.param.command.empty() ? std::string("tincdt")
                                                          : p.param.command.substr(1);
                         });

// The check above is only as good as help_options(): it must see the options of every group.
TEST(HelpOptions, SeesTheOptionsOfEveryGroup) {
  const std::set<std::string> options = help_options("");
  EXPECT_GT(options.size(), 40u);
  for (const char* o : {"--a-srs", "--contours", "--max-error", "--dem-co", "--plan", "--threads"})
    EXPECT_TRUE(options.count(o)) << o;
}

// ---- the README and docs/ as documents ----

// README.md and every Markdown file under docs/.
std::vector<fs::path> documents() {
  std::vector<fs::path> files = {kSource / "README.md"};
  for (const auto& entry : fs::recursive_directory_iterator(kSource / "docs"))
    if (entry.is_regular_file() && entry.path().extension() == ".md") files.push_back(entry.path());
  return files;
}

TEST(ReadmeDocuments, TheReadmeIsAFrontDoorOfAtMost300Lines) {
  const std::vector<std::string> lines = lines_of(test::slurp(kSource / "README.md"));
  EXPECT_LE(lines.size(), 300u) << "move the long parts of README.md into docs/";
}

TEST(ReadmeDocuments, DocsHoldsTheManual) {
  for (const char* page : {"manual.md", "options.md", "formats.md", "products.md", "tiling.md",
                           "benchmarks.md", "design.md", "algorithm.md", "development.md"})
    EXPECT_TRUE(fs::is_regular_file(kSource / "docs" / page)) << "docs/" << page;
}

// The shared test data lies beside a developer's clone, not in a user's: no document may point
// into it.
TEST(ReadmeDocuments, NoDocumentLinksOutsideTheClone) {
  for (const fs::path& file : documents()) {
    const std::vector<std::string> lines = lines_of(test::slurp(file));
    for (std::size_t i = 0; i < lines.size(); ++i)
      EXPECT_EQ(lines[i].find("../shared"), std::string::npos)
          << file.string() << ":" << i + 1 << ": " << lines[i];
  }
}

// Every relative link, [text](target) with no scheme, names a file or folder of the clone.
TEST(ReadmeDocuments, EveryRelativeLinkNamesAFileThatIsThere) {
  const std::regex link(R"(\]\(([^)\s]+)\))");
  std::size_t checked = 0;
  for (const fs::path& file : documents()) {
    const std::string text = test::slurp(file);
    for (std::sregex_iterator it(text.begin(), text.end(), link), end; it != end; ++it) {
      std::string target = (*it)[1];
      if (target.find("://") != std::string::npos || target.rfind("mailto:", 0) == 0) continue;
      target = target.substr(0, target.find('#'));
      if (target.empty()) continue;  // a heading of the same page
      const fs::path resolved = (file.parent_path() / target).lexically_normal();
      EXPECT_TRUE(fs::exists(resolved)) << file.string() << " links to " << target;
      const fs::path inside = resolved.lexically_relative(kSource.lexically_normal());
      EXPECT_TRUE(!inside.empty() && *inside.begin() != "..")
          << file.string() << " links outside the clone: " << target;
      ++checked;
    }
  }
  EXPECT_GT(checked, 10u);
}

}  // namespace
}  // namespace tincdt
