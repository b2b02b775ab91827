// The command line's conventions, as users of GDAL, PDAL and LAStools expect them, each with the
// exact command: no arguments print the usage; "-" is standard output only for --stats; the GDAL
// spellings -a_srs, -t_srs and -co work and -of says what to use; a misspelt option names the
// one meant; the help's value names read as written; --validate says its verdict; numbers in
// messages are short.
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "support/files.hpp"
#include "support/spawn.hpp"
#include "support/stats_json.hpp"

extern char** environ;

namespace {

namespace fs = std::filesystem;

using tincdt::test::names_in;
using tincdt::test::slurp;

const std::string kSample = std::string(TINCDT_SOURCE_DIR) + "/data/sample.las";

struct Outcome {
  int exit_code = -1;  // -1 when killed by a signal
  std::string out;
  std::string err;
};

std::ostream& operator<<(std::ostream& os, const Outcome& r) {
  return os << "exit " << r.exit_code << "\n--- stdout\n" << r.out << "--- stderr\n" << r.err;
}

// Runs tincdt with ARGS, word for word, in a scratch folder of the test's own.
class Conventions : public ::testing::Test {
 protected:
  Conventions()
      : dir_(tincdt::test::scratch_dir("conventions")),
        capture_(tincdt::test::scratch_dir("conventions-capture")) {}

  std::string path(const std::string& name) const { return dir_ + "/" + name; }
  std::set<std::string> files() const { return names_in(dir_); }

  // In the scratch folder, so that a file named "-" would land there.
  Outcome run(const std::vector<std::string>& args) const {
    std::vector<std::string> words = {TINCDT_EXE};
    words.insert(words.end(), args.begin(), args.end());
    const tincdt::test::Spawned r = tincdt::test::spawn_captured(words, dir_, capture_);
    return {r.exit_code, r.out, r.err};
  }

  // A plan of the sample in 100 m tiles with a 20 m buffer (its extent is 160 m x 120 m).
  void make_plan() const {
    const Outcome r =
        run({"plan", kSample, "--tile-size", "100", "--buffer", "20", "-o", path("plan.json")});
    ASSERT_EQ(r.exit_code, 0) << r;
  }

 private:
  std::string dir_;
  std::string capture_;
};

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// A usage error: exit 2, the message, the pointer to --help, nothing on standard output.
void expect_usage_error(const Outcome& r, const std::string& message) {
  EXPECT_EQ(r.exit_code, 2) << r;
  EXPECT_TRUE(contains(r.err, message)) << "expected: " << message << "\n" << r;
  EXPECT_TRUE(contains(r.err, "--help' for more information.")) << r;
  EXPECT_EQ(r.out, "");
}

// ---- tincdt alone -------------------------------------------------------------------------------

TEST_F(Conventions, NoArgumentsPrintsTheUsage) {
  const Outcome r = run({});
  expect_usage_error(r, "tincdt: error: no input and no output");
  EXPECT_EQ(r.err.rfind("tincdt " TINCDT_VERSION ": exact constrained Delaunay TIN", 0), 0u) << r;
  EXPECT_TRUE(contains(r.err, "\nUsage: tincdt [OPTIONS] [INPUT...]")) << r;
  EXPECT_TRUE(contains(r.err, "\n       tincdt plan INPUT...")) << r;
  EXPECT_TRUE(contains(r.err, "\nTry 'tincdt --help' for more information.\n")) << r;
  EXPECT_FALSE(contains(r.err, "--output is required")) << r;
}

// ---- "-" as an output
// ----------------------------------------------------------------------------

TEST_F(Conventions, DashIsNoOutputFile) {
  const std::vector<std::vector<std::string>> commands = {
      {kSample, "-o", "-", "-f", "ply"},
      {kSample, "-o", "-", "-f", "obj"},
      {kSample, "-o", "-"},
      {kSample, "-o", "t.ply", "--dem", "-", "--resolution", "2"},
      {kSample, "-o", "t.ply", "--contour-lines", "-", "--interval", "2"},
  };
  for (const std::vector<std::string>& args : commands) {
    std::string command;
    for (const std::string& word : args) command += " " + word;
    SCOPED_TRACE(command);
    expect_usage_error(run(args), "cannot be standard output ('-')");
    EXPECT_EQ(files(), std::set<std::string>{});
  }
  make_plan();
  expect_usage_error(run({"plan", kSample, "--tile-size", "100", "--buffer", "20", "-o", "-"}),
                     "-o cannot be standard output ('-')");
  expect_usage_error(run({"--plan", "plan.json", "--tile", "0", "-o", "t.ply", "--outline", "-"}),
                     "the tile's outline (--outline) cannot be standard output ('-')");
  expect_usage_error(run({"merge", "t.ply", "-o", "-"}), "-o cannot be standard output ('-')");
  EXPECT_EQ(files(), (std::set<std::string>{"plan.json", "plan.rim.xyz"}));
}

TEST_F(Conventions, StatsDashPrintsTheJsonAlone) {
  const Outcome r = run({kSample, "-o", "t.ply", "--stats", "-", "-v", "--validate"});
  ASSERT_EQ(r.exit_code, 0) << r;
  const tincdt::test::StatsJson stats(r.out);
  ASSERT_TRUE(stats.ok()) << r;
  EXPECT_EQ(r.out.front(), '{');
  EXPECT_EQ(r.out.substr(r.out.size() - 2), "}\n");
  EXPECT_GT(stats.count("triangles"), 0u);
  EXPECT_LT(stats.count("triangles"), 100000u);
  EXPECT_TRUE(stats.has("quality")) << r.out;
  EXPECT_TRUE(contains(r.err, "tincdt: wrote the stats to standard output\n")) << r;
  EXPECT_TRUE(contains(r.err, "tincdt: debug: ")) << r;  // messages stay on stderr
  EXPECT_EQ(files(), (std::set<std::string>{"t.ply", "t.prj"}));
}

// ---- GDAL's spellings ------------------------------------------------------------------------

TEST_F(Conventions, GdalSrsWordsAreTheSrsOptions) {
  const Outcome r = run({kSample, "-o", "t.geojson", "-a_srs", "EPSG:32632", "-t_srs", "EPSG:4326",
                         "--allow-geographic"});
  ASSERT_EQ(r.exit_code, 0) << r;
  const std::string json = slurp(path("t.geojson"));
  // UTM zone 32 metres became degrees: the sample lies near 10.3 E, 46.8 N.
  EXPECT_TRUE(std::regex_search(json, std::regex(R"(\[ ?10\.3[0-9]*, ?46\.8[0-9]*)")))
      << json.substr(0, 400);
  EXPECT_FALSE(std::regex_search(json, std::regex(R"(\[6[0-9]{5}[.,])"))) << json.substr(0, 400);
}

TEST_F(Conventions, GdalCoIsADemCreationOption) {
  const Outcome r =
      run({kSample, "-o", "t.ply", "--dem", "d.tif", "--resolution", "2", "-co", "COMPRESS=LZW"});
  ASSERT_EQ(r.exit_code, 0) << r;
  GDALAllRegister();
  GDALDataset* dem = GDALDataset::FromHandle(GDALOpen(path("d.tif").c_str(), GA_ReadOnly));
  ASSERT_NE(dem, nullptr);
  const char* compression = dem->GetMetadataItem("COMPRESSION", "IMAGE_STRUCTURE");
  EXPECT_STREQ(compression == nullptr ? "" : compression, "LZW");
  GDALClose(dem);
}

TEST_F(Conventions, GdalOfIsTheDemFormat) {
  // Never "-o f": without --dem it is --dem-format's usage error, with it the DEM's driver.
  expect_usage_error(run({kSample, "-o", "t.ply", "-of", "GTiff"}), "need --dem");
  EXPECT_EQ(files(), std::set<std::string>{});
  const Outcome r =
      run({kSample, "-o", "t.ply", "--dem", "d.dem", "--resolution", "4", "-of", "GTiff", "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  GDALAllRegister();
  GDALDataset* dem = GDALDataset::FromHandle(GDALOpen(path("d.dem").c_str(), GA_ReadOnly));
  ASSERT_NE(dem, nullptr);
  EXPECT_STREQ(dem->GetDriver()->GetDescription(), "GTiff");
  GDALClose(dem);
}

TEST_F(Conventions, OnlyTheGdalWordsBeforeTheEndOfOptions) {
  // After "--" every word is an operand: "-a_srs" is an input file, which is missing.
  const Outcome r = run({"-o", "t.ply", "--", "-a_srs"});
  EXPECT_EQ(r.exit_code, 1) << r;
  EXPECT_TRUE(contains(r.err, "-a_srs")) << r;
  EXPECT_EQ(files(), std::set<std::string>{});
}

// ---- misspelt options ------------------------------------------------------------------------

TEST_F(Conventions, MisspeltOptionNamesTheOneMeant) {
  expect_usage_error(run({kSample, "-o", "t.ply", "--keep-clas", "2"}),
                     "tincdt: error: unknown option --keep-clas; did you mean --keep-class?\n");
  expect_usage_error(run({kSample, "-o", "t.ply", "--vaildate"}),
                     "unknown option --vaildate; did you mean --validate?\n");
  expect_usage_error(run({kSample, "--outptu", "t.ply"}),
                     "unknown option --outptu; did you mean --output?\n");
  expect_usage_error(run({kSample, "-o", "t.ply", "--frobnicate"}),
                     "tincdt: error: unknown option --frobnicate\n");
  expect_usage_error(
      run({"plan", kSample, "--tile-szie", "100", "--buffer", "20", "-o", "plan.json"}),
      "unknown option --tile-szie; did you mean --tile-size?\n");
  EXPECT_EQ(files(), std::set<std::string>{});
}

// ---- the help ----------------------------------------------------------------------------------

TEST_F(Conventions, HelpValueNamesReadAsWritten) {
  const Outcome r = run({"--help"});
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_FALSE(contains(r.out, ":NONNEGATIVE")) << r.out;
  EXPECT_FALSE(contains(r.out, " x 4")) << r.out;
  EXPECT_TRUE(contains(r.out, "  --dem-extent XMIN YMIN XMAX YMAX\n")) << r.out;
  EXPECT_TRUE(contains(r.out, "  --tile N ")) << r.out;
  EXPECT_TRUE(contains(r.out, "  --buffer LENGTH ")) << r.out;
  EXPECT_TRUE(contains(
      r.out,
      "-a_srs, -t_srs, -co and -of are read as --a-srs, --t-srs, --dem-co and\n--dem-format"))
      << r.out;
}

TEST_F(Conventions, HelpGivesTheExitStatusOfASignal) {
  const Outcome r = run({"--help"});
  ASSERT_EQ(r.exit_code, 0) << r;
  const std::string exit_status = r.out.substr(r.out.find("Exit status:"));
  for (const char* part : {"SIGINT", "SIGTERM", "130", "143"})
    EXPECT_TRUE(contains(exit_status, part)) << part << "\n" << exit_status;
}

// ---- --validate
// ----------------------------------------------------------------------------------

TEST_F(Conventions, ValidateSaysItsVerdict) {
  const Outcome r = run({kSample, "-o", "t.ply", "--validate"});
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_TRUE(std::regex_search(r.err, std::regex("(^|\n)tincdt: TIN is valid: [0-9,]+ triangles")))
      << r;
  const Outcome quiet = run({kSample, "-o", "t.ply", "--validate", "--overwrite", "-q"});
  ASSERT_EQ(quiet.exit_code, 0) << quiet;
  EXPECT_EQ(quiet.err, "");
}

// ---- numbers in messages, and the tile job's values ---------------------------------------------

// No number of 20 digits or more: %g, not std::to_string of a huge double.
void expect_short_numbers(const Outcome& r) {
  EXPECT_FALSE(std::regex_search(r.err, std::regex("[0-9]{20}"))) << r;
}

TEST_F(Conventions, TileValuesAreRefusedBriefly) {
  make_plan();
  const Outcome tile = run({"--plan", "plan.json", "--tile", "-1", "-o", "t.ply"});
  expect_usage_error(tile, "--tile: '-1' is not a tile index (0, 1, ...)");
  expect_short_numbers(tile);
  const Outcome buffer =
      run({"--plan", "plan.json", "--tile", "0", "--buffer", "-1", "-o", "t.ply"});
  expect_usage_error(buffer, "--buffer: '-1' is not a number >= 0");
  expect_short_numbers(buffer);
  const Outcome huge =
      run({"--plan", "plan.json", "--tile", "0", "--buffer", "1e308", "-o", "t.ply"});
  expect_usage_error(huge,
                     "--buffer: 1e+308 reaches beyond the plan's data: 260 (the extent's "
                     "larger side, 160, plus the tile size) already reads all of it");
  EXPECT_EQ(files(), (std::set<std::string>{"plan.json", "plan.rim.xyz"}));
  // The bound itself is a buffer like any other.
  const Outcome most =
      run({"--plan", "plan.json", "--tile", "0", "--buffer", "260", "-o", "t.ply"});
  ASSERT_EQ(most.exit_code, 0) << most;
  EXPECT_TRUE(contains(most.err, " triangles owned")) << most;
  EXPECT_FALSE(contains(most.err, ": 0 triangles owned")) << most;
}

TEST_F(Conventions, DemNodataMessageHasAShortNumber) {
  const Outcome r =
      run({kSample, "-o", "t.ply", "--dem", "d.tif", "--resolution", "2", "--dem-nodata", "1e308"});
  expect_usage_error(r, "--dem-nodata: 1e+308 cannot be stored in Float32 cells");
  expect_short_numbers(r);
  EXPECT_EQ(files(), std::set<std::string>{});
}

}  // namespace
