// `tincdt plan`, `tincdt --plan P --tile N` and `tincdt merge` run the way a user (or a job
// engine) runs them: exit codes, one-line errors naming the plan and the tile, no file left by a
// failed job, and a GNU parallel run of every tile of a plan (skipped when parallel is missing).
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <gdal_priv.h>

#include "support/files.hpp"
#include "support/mesh_files.hpp"
#include "support/spawn.hpp"

extern char** environ;

namespace {

namespace fs = std::filesystem;

struct Outcome {
  int exit_code = -1;
  std::string err;
};

// Runs ARGS (ARGS[0] the program) in DIR, stderr captured.
Outcome run(const fs::path& dir, std::vector<std::string> args) {
  const fs::path capture = dir / ".capture";
  fs::create_directories(capture);
  const tincdt::test::Spawned r = tincdt::test::spawn_captured(std::move(args), dir, capture);
  fs::remove_all(capture);
  return {r.exit_code, r.err};
}

Outcome tincdt_run(const fs::path& dir, std::vector<std::string> args) {
  args.insert(args.begin(), TINCDT_EXE);
  return run(dir, std::move(args));
}

// Stderr without the lines of the stages done before the error ("tincdt: [1/4] ... - done.").
std::string without_progress(const std::string& err) {
  const std::regex done(R"(tincdt: \[\d+/\d+\] .* - done\.)");
  std::string kept;
  std::size_t start = 0;
  while (start < err.size()) {
    const std::size_t end = std::min(err.find('\n', start), err.size() - 1) + 1;
    const std::string line = err.substr(start, end - start);
    if (!std::regex_match(line.substr(0, line.find('\n')), done)) kept += line;
    start = end;
  }
  return kept;
}

// Exactly one line on stderr besides the progress, an error containing TEXT.
void expect_one_error(const Outcome& r, int code, const std::string& text) {
  const std::string err = without_progress(r.err);
  EXPECT_EQ(r.exit_code, code) << r.err;
  EXPECT_EQ(err.rfind("tincdt: error: ", 0), 0u) << r.err;
  EXPECT_EQ(err.find('\n'), err.size() - 1) << "more than one line:\n" << r.err;
  EXPECT_NE(err.find(text), std::string::npos) << r.err;
}

// A small LiDAR-like cloud over 200 m x 150 m as XYZ text.
void write_cloud(const fs::path& path, int n) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> at(0, 1);
  std::string s;
  char line[128];
  for (int i = 0; i < n; ++i) {
    const double x = 300000 + 200 * at(rng), y = 5000000 + 150 * at(rng);
    std::snprintf(line, sizeof line, "%.17g %.17g %.17g\n", x, y,
                  100 + 5 * std::sin(x / 30) + 3 * std::cos(y / 20));
    s += line;
  }
  tincdt::test::spit(path, s);
}

class TilesCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = tincdt::test::scratch_dir("tiles_cli");
    write_cloud(dir_ / "cloud.xyz", 4000);
  }
  // The TIN at MERGED (below the folder) has the vertices and faces of the cloud's single job
  // (with the job options OPTIONS).
  void expect_counts_of_single_job(const std::string& merged,
                                   const std::vector<std::string>& options = {}) const {
    std::vector<std::string> args = {"cloud.xyz", "-o", "whole.ply", "-q", "--overwrite"};
    args.insert(args.end(), options.begin(), options.end());
    const Outcome r = tincdt_run(dir_, args);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string a = tincdt::test::ply_header(dir_ / "whole.ply");
    const std::string b = tincdt::test::ply_header(dir_ / merged);
    for (const char* element : {"vertex", "face"})
      EXPECT_EQ(tincdt::test::ply_element_count(a, element),
                tincdt::test::ply_element_count(b, element))
          << element;
  }
  fs::path dir_;
};

TEST_F(TilesCli, PlanTileMergeAsAUserRunsThem) {
  Outcome r = tincdt_run(
      dir_, {"plan", "cloud.xyz", "--tile-size", "100", "--buffer", "40", "-o", "plan.json", "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string plan = tincdt::test::slurp(dir_ / "plan.json");
  EXPECT_NE(plan.find("\"tile_count\": 4,"), std::string::npos) << plan;  // 2 x 2 tiles
  fs::create_directories(dir_ / "out");
  for (int i = 0; i < 4; ++i) {
    const std::string n = std::to_string(i);
    r = tincdt_run(dir_,
                   {"--plan", "plan.json", "--tile", n, "-o", "out/tile_" + n + ".ply", "-q"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  std::vector<std::string> merge = {"merge"};
  for (int i = 0; i < 4; ++i) merge.push_back("out/tile_" + std::to_string(i) + ".ply");
  std::vector<std::string> check = merge;
  check.push_back("--check");
  EXPECT_EQ(tincdt_run(dir_, check).exit_code, 0);
  merge.insert(merge.end(), {"-o", "merged.ply", "-q"});
  r = tincdt_run(dir_, merge);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expect_counts_of_single_job("merged.ply");
}

// --max-edge on every tile: the merge gives the single job's trimmed TIN, and names a missing
// tile.
TEST_F(TilesCli, TrimmedTilesMergeAndAMissingOneIsNamed) {
  Outcome r = tincdt_run(
      dir_, {"plan", "cloud.xyz", "--tile-size", "100", "--buffer", "20", "-o", "plan.json", "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::vector<std::string> merge = {"merge"};
  for (int i = 0; i < 4; ++i) {
    const std::string n = std::to_string(i);
    r = tincdt_run(dir_, {"--plan", "plan.json", "--tile", n, "--max-edge", "6", "-o",
                          "tile_" + n + ".ply", "-q"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    merge.push_back("tile_" + n + ".ply");
  }
  std::vector<std::string> without_one(merge.begin(), merge.end() - 1);
  without_one.push_back("--check");
  expect_one_error(tincdt_run(dir_, without_one), 1, "tile 3 of its plan's 4 is missing");
  merge.insert(merge.end(), {"-o", "merged.ply"});
  r = tincdt_run(dir_, merge);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find(" outline edges; wrote merged.ply"), std::string::npos) << r.err;
  expect_counts_of_single_job("merged.ply", {"--max-edge", "6"});
  const Outcome whole = tincdt_run(dir_, {"cloud.xyz", "-o", "untrimmed.ply", "-q"});
  ASSERT_EQ(whole.exit_code, 0) << whole.err;
  EXPECT_GT(
      tincdt::test::ply_element_count(tincdt::test::ply_header(dir_ / "untrimmed.ply"), "face"),
      tincdt::test::ply_element_count(tincdt::test::ply_header(dir_ / "merged.ply"), "face"));
}

// A file planned for a tile by its bounds may have no point in the tile's box: expected, so no
// warning (one of two clusters at the east edge, south and north, seen from the middle tiles).
TEST_F(TilesCli, AFileWithNoPointInTheTileBoxIsNoWarning) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> at(0, 10);
  std::string clusters;
  for (int i = 0; i < 50; ++i)
    for (const double y : {5000000.0, 5000140.0}) {
      char line[96];
      std::snprintf(line, sizeof line, "%.17g %.17g 100\n", 300190 + at(rng), y + at(rng));
      clusters += line;
    }
  tincdt::test::spit(dir_ / "clusters.xyz", clusters);
  Outcome r = tincdt_run(dir_, {"plan", "cloud.xyz", "clusters.xyz", "--tile-size", "50",
                                "--buffer", "10", "-o", "plan.json", "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  int tiles = 0;
  for (; tiles < 100; ++tiles) {
    const std::string n = std::to_string(tiles);
    r = tincdt_run(dir_, {"--plan", "plan.json", "--tile", n, "--a-srs", "EPSG:32631", "-o",
                          "tile.ply", "--overwrite"});
    if (r.exit_code == 1 && r.err.find("no tile " + n) != std::string::npos) break;
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err.find("warning"), std::string::npos) << "tile " << n << ":\n" << r.err;
  }
  EXPECT_EQ(tiles, 12);  // 4 x 3
}

TEST_F(TilesCli, BadPlansGiveOneLineAndExitOne) {
  ASSERT_EQ(tincdt_run(dir_, {"plan", "cloud.xyz", "--tile-size", "100", "--buffer", "2", "-o",
                              "plan.json", "-q"})
                .exit_code,
            0);
  // A tile index the plan does not have.
  expect_one_error(tincdt_run(dir_, {"--plan", "plan.json", "--tile", "4", "-o", "t.ply"}), 1,
                   "plan.json: no tile 4: the plan has tiles 0 to 3");
  // Too small a buffer, and told not to grow it: the tile and the buffer it needs.
  expect_one_error(
      tincdt_run(dir_, {"--plan", "plan.json", "--tile", "1", "--buffer-fixed", "-o", "t.ply"}), 1,
      "plan.json: tile 1: buffer 2 is too small");
  // A plan from other inputs: the cloud changed since.
  tincdt::test::spit(dir_ / "cloud.xyz",
                     tincdt::test::slurp(dir_ / "cloud.xyz") + "300050 5000050 1\n");
  expect_one_error(tincdt_run(dir_, {"--plan", "plan.json", "--tile", "0", "-o", "t.ply"}), 1,
                   "cloud.xyz has changed since the plan was made");
  EXPECT_FALSE(fs::exists(dir_ / "t.ply"));
  // Options a tile cannot honour are usage errors.
  const Outcome r = tincdt_run(
      dir_, {"--plan", "plan.json", "--tile", "0", "--max-vertices", "50", "-o", "t.ply"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--max-vertices cannot be used with --plan"), std::string::npos) << r.err;
  EXPECT_EQ(tincdt_run(dir_, {"--plan", "plan.json", "-o", "t.ply"}).exit_code, 2);
  EXPECT_EQ(tincdt_run(dir_, {"merge", "a.ply"}).exit_code, 2);  // neither -o nor --check
}

// plan, a tile job and merge never write over their own inputs, --overwrite or not: a usage
// error naming both files, before any work, and every file as it was.
TEST_F(TilesCli, NoCommandWritesOverItsInputs) {
  const auto refused = [&](std::vector<std::string> args, const std::string& victim) {
    const std::string before = tincdt::test::slurp(dir_ / victim);
    args.insert(args.end(), {"--overwrite", "-q"});
    const Outcome r = tincdt_run(dir_, args);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("would overwrite an input, " + victim), std::string::npos) << r.err;
    EXPECT_EQ(tincdt::test::slurp(dir_ / victim), before) << victim;
  };
  const std::vector<std::string> plan = {"plan", "cloud.xyz", "--tile-size",
                                         "100",  "--buffer",  "40"};
  auto with = [](std::vector<std::string> a, std::initializer_list<std::string> more) {
    a.insert(a.end(), more);
    return a;
  };
  refused(with(plan, {"-o", "cloud.xyz"}), "cloud.xyz");
  // The rim file of plan "cloud.json" is cloud.rim.xyz: here an input.
  fs::copy_file(dir_ / "cloud.xyz", dir_ / "cloud.rim.xyz");
  refused(with(plan, {"cloud.rim.xyz", "-o", "cloud.json"}), "cloud.rim.xyz");
  EXPECT_FALSE(fs::exists(dir_ / "cloud.json"));

  ASSERT_EQ(tincdt_run(dir_, with(plan, {"-o", "plan.json", "-q"})).exit_code, 0);
  refused({"--plan", "plan.json", "--tile", "0", "-o", "plan.json", "-f", "ply"}, "plan.json");
  for (const std::string t : {"0", "1"})
    ASSERT_EQ(tincdt_run(dir_, {"--plan", "plan.json", "--tile", t, "-o", "t" + t + ".ply", "-q"})
                  .exit_code,
              0);
  refused({"merge", "t0.ply", "t1.ply", "-o", "t1.ply"}, "t1.ply");
  refused({"merge", "t0.ply", "t1.ply", "--outline", "-o", "t0.ply"}, "t0.ply");
}

// Each tile job draws its own tile, framed, so that the pictures of a plan join into a mosaic.
TEST_F(TilesCli, TilePreviewsCoverTheirTiles) {
  ASSERT_EQ(tincdt_run(dir_, {"plan", "cloud.xyz", "--tile-size", "100", "--buffer", "40", "-o",
                              "plan.json", "-q"})
                .exit_code,
            0);
  // Tile 2 is [300000, 300100] x [5000000, 5000100]: the data's south-west corner.
  const Outcome r = tincdt_run(dir_, {"--plan", "plan.json", "--tile", "2", "-o", "t2.ply",
                                      "--preview", "t2.png", "--preview-size", "200", "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(tincdt::test::slurp(dir_ / "plan.json")
                .find("\"index\": 2, \"col\": 3000, \"row\": 50000, \"box\": [300000, 5000000, "
                      "300100, 5000100]"),
            std::string::npos);
  // 200 x 200 pixels (the tile is a square), and no gap: the neighbours' final triangles fill
  // the tile's picture where the tile does not own them. The tile's west and south sides are the
  // data's, whose hull the random points reach only within a few metres.
  GDALAllRegister();
  GDALDatasetUniquePtr png(GDALDataset::Open((dir_ / "t2.png").c_str(), GDAL_OF_RASTER));
  ASSERT_TRUE(png);
  ASSERT_EQ(png->GetRasterXSize(), 200);
  ASSERT_EQ(png->GetRasterYSize(), 200);
  std::vector<std::uint8_t> alpha(200 * 200);
  ASSERT_EQ(png->GetRasterBand(4)->RasterIO(GF_Read, 0, 0, 200, 200, alpha.data(), 200, 200,
                                            GDT_Byte, 0, 0, nullptr),
            CE_None);
  int gaps = 0;
  for (int row = 0; row < 190; ++row)
    for (int col = 10; col < 200; ++col) gaps += alpha[std::size_t(row) * 200 + col] == 0;
  EXPECT_EQ(gaps, 0);
}

// The engine recipe examples/tiles/parallel.sh, as CI runs it: every tile of a plan through GNU
// parallel, then merged, against the one-job TIN.
TEST_F(TilesCli, GnuParallelRecipeBuildsTheWholeTin) {
  if (run(dir_, {"sh", "-c", "command -v parallel"}).exit_code != 0)
    GTEST_SKIP() << "GNU parallel is not installed (cmake/setup.sh installs it)";
  const fs::path script = fs::path(TINCDT_SOURCE_DIR) / "examples/tiles/parallel.sh";
  ASSERT_EQ(tincdt_run(dir_, {"plan", "cloud.xyz", "--tile-size", "50", "--buffer", "40", "-o",
                              "plan.json", "-q"})
                .exit_code,
            0);
  setenv("TINCDT", TINCDT_EXE, 1);
  setenv("JOBS", "2", 1);
  Outcome r = run(dir_, {"bash", script.string(), "plan.json", "out"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "out/merged.ply")) << r.err;
  expect_counts_of_single_job("out/merged.ply");
}

}  // namespace
