// What a progress display hears from a build: each wanted stage announced in order, numbered of
// the stages that run, with a name for a person; and each stage's fraction never going back,
// even where the stage's work reports in phases (the DEM: rasterize, then write; the contour
// lines: trace, then write).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "core/progress.hpp"
#include "pipeline/build.hpp"
#include "pipeline/stage.hpp"
#include "support/files.hpp"

namespace tincdt {
namespace {

namespace fs = std::filesystem;

class Recorder final : public StageWatcher {
 public:
  struct Started {
    std::string name, title, unit;
    int number, count;
  };
  std::vector<Started> started;
  std::map<std::string, std::vector<double>> fractions;

  void stage_started(const StageStart& s) override {
    started.push_back(
        {std::string(s.name), std::string(s.title), std::string(s.unit), s.number, s.count});
  }
  bool report(std::string_view stage, double fraction) override {
    fractions[std::string(stage)].push_back(fraction);
    return true;
  }
};

TEST(StageProgress, StagesAreAnnouncedAndNeverGoBack) {
  const std::string dir = test::scratch_dir("stage_progress");
  pipeline::BuildOptions o;
  o.inputs = {std::string(TINCDT_SOURCE_DIR) + "/data/sample.las"};
  o.output = dir + "/t.ply";
  o.dem.path = dir + "/d.tif";
  o.dem.resolution = 0.1;
  o.contour_lines.path = dir + "/c.gpkg";
  o.contour_lines.interval = 1;
  Recorder recorder;
  const ProgressFn progress = watching(recorder);
  ASSERT_EQ(watcher_of(&progress), &recorder);
  pipeline::build(o, &progress);

  const std::vector<std::string> names = {"read", "delaunay", "write", "dem", "contour_lines"};
  ASSERT_EQ(recorder.started.size(), names.size());
  for (std::size_t i = 0; i < names.size(); ++i) {
    const Recorder::Started& s = recorder.started[i];
    EXPECT_EQ(s.name, names[i]);
    EXPECT_EQ(s.number, static_cast<int>(i + 1));
    EXPECT_EQ(s.count, static_cast<int>(names.size()));
    EXPECT_NE(s.title, s.name) << "a name for a person";
  }
  EXPECT_EQ(recorder.started[1].title, "triangulating");
  EXPECT_EQ(recorder.started[1].unit, "points");
  for (const auto& [stage, seen] : recorder.fractions) {
    SCOPED_TRACE(stage);
    for (std::size_t i = 1; i < seen.size(); ++i) ASSERT_GE(seen[i], seen[i - 1]) << "at " << i;
  }
  // The phases took their shares: the DEM's rasterizing reported up to one half, its writing
  // from there.
  const std::vector<double>& dem = recorder.fractions.at("dem");
  EXPECT_TRUE(std::any_of(dem.begin(), dem.end(), [](double f) { return f > 0 && f <= 0.5; }));
  EXPECT_TRUE(std::any_of(dem.begin(), dem.end(), [](double f) { return f >= 0.5 && f < 1; }));
  // An ordinary callback hears the same fractions; it has no watcher.
  const ProgressFn plain = [](std::string_view, double) { return true; };
  EXPECT_EQ(watcher_of(&plain), nullptr);
}

// Every stage a progress display can announce has a name for a person, not its internal one.
TEST(StageProgress, EveryStageHasATitleForAPerson) {
  for (const pipeline::Stage* stage : pipeline::stages()) {
    SCOPED_TRACE(stage->name);
    EXPECT_FALSE(stage->progress.title.empty());
    EXPECT_EQ(stage->progress.title.find('_'), std::string_view::npos);
  }
}

}  // namespace
}  // namespace tincdt
