// OutputSet: several outputs move into place together or not at all; OutputFile::take_path for
// writers that create their file themselves; the signal-safe removal of temporaries.
#include "io/output_set.hpp"

#include <gtest/gtest.h>
#include <pthread.h>
#include <signal.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "core/error.hpp"
#include "io/output_file.hpp"
#include "support/files.hpp"

namespace tincdt::io {
namespace {

// A fresh folder per test; at(NAME) is a path in it, files() what it holds.
class Outputs : public ::testing::Test {
 protected:
  std::string at(const std::string& name) const { return dir_ + "/" + name; }
  std::set<std::string> files() const { return test::names_in(dir_); }
  std::string read(const std::string& name) const { return test::slurp(at(name)); }
  void put(const std::string& name, const std::string& bytes) const { test::spit(at(name), bytes); }
  // Adds a.txt (new content) to SET.
  void add_a(OutputSet& set) const { set.add(at("a.txt"), "a").write(std::string("new")); }

  const std::string dir_ = test::scratch_dir("output_set");
};

TEST_F(Outputs, CommitMovesEveryFileIntoPlace) {
  put("old.txt", "old");
  OutputSet set(true);
  set.add(at("old.txt"), "a").write(std::string("new a"));
  set.add(at("b.txt"), "b").write(std::string("new b"));
  EXPECT_EQ(files().size(), 3u);  // old.txt and two temporaries
  set.commit();
  EXPECT_TRUE(set.committed());
  EXPECT_EQ(files(), (std::set<std::string>{"old.txt", "b.txt"}));
  EXPECT_EQ(read("old.txt"), "new a");
  EXPECT_EQ(read("b.txt"), "new b");
}

TEST_F(Outputs, DestroyedUncommittedLeavesEverythingAsItWas) {
  put("a.txt", "old");
  {
    OutputSet set(true);
    add_a(set);
    set.add(at("b.txt"), "b").write(std::string("new"));
  }
  EXPECT_EQ(files(), std::set<std::string>{"a.txt"});
  EXPECT_EQ(read("a.txt"), "old");
}

TEST_F(Outputs, CancelledByTheLastCheckOrAPendingSignal) {
  put("a.txt", "old");
  {
    OutputSet set(true);
    add_a(set);
    EXPECT_THROW(set.commit([] { return false; }), Cancelled);
    EXPECT_EQ(files(), std::set<std::string>{"a.txt"});  // temporaries gone at once
  }
  {
    // A SIGTERM raised by the last check is pending while the files would move: no file moves.
    const auto old_handler = std::signal(SIGTERM, [](int) {});
    OutputSet set(true);
    add_a(set);
    EXPECT_THROW(set.commit([] { return ::raise(SIGTERM) == 0; }), Cancelled);
    std::signal(SIGTERM, old_handler);
  }
  EXPECT_EQ(files(), std::set<std::string>{"a.txt"});
  EXPECT_EQ(read("a.txt"), "old");
}

// The second file cannot move (its temporary vanished): the first, already in place, gets its
// old content back, and a new file that had no old content is removed again.
TEST_F(Outputs, AFailedMovePutsTheOthersBack) {
  put("a.txt", "old a");
  OutputSet set(true);
  set.add(at("a.txt"), "a").write(std::string("new a"));
  set.add(at("c.txt"), "c").write(std::string("new c"));
  OutputFile& b = set.add(at("b.txt"), "b");
  b.write(std::string("new b"));
  b.close();
  std::filesystem::remove(b.temp_path());
  EXPECT_THROW(set.commit(), OutputError);
  EXPECT_EQ(files(), std::set<std::string>{"a.txt"});
  EXPECT_EQ(read("a.txt"), "old a");
}

TEST_F(Outputs, ATargetThatAppearedMeanwhileIsNotReplacedWithoutOverwrite) {
  OutputSet set(false);
  set.add(at("a.txt"), "a").write(std::string("new a"));
  set.add(at("b.txt"), "b").write(std::string("new b"));
  put("b.txt", "someone else's");
  EXPECT_THROW(set.commit(), OutputError);
  EXPECT_EQ(files(), std::set<std::string>{"b.txt"});
  EXPECT_EQ(read("b.txt"), "someone else's");
}

TEST_F(Outputs, OnePathIsOneOutput) {
  OutputSet set(false);
  set.add(at("a.txt"), "tin");
  EXPECT_THROW(set.add(at("a.txt"), "stats"), OutputError);
}

// A writer that creates its own file (as GDAL does) at take_path(): the name keeps the target's
// extension, the file moves into place with the others, and is removed on failure with the
// SQLite journal beside it.
TEST_F(Outputs, TakenPathIsTheWritersOwn) {
  {
    OutputSet set(false);
    OutputFile& out = set.add(at("d.gpkg"), "diagnostics");
    const std::string file = out.take_path();
    EXPECT_EQ(std::filesystem::path(file).extension(), ".gpkg");
    EXPECT_FALSE(std::filesystem::exists(file));
    test::spit(file, "a database");
    test::spit(file + "-journal", "a journal");
  }
  EXPECT_TRUE(files().empty());
  OutputSet set(false);
  OutputFile& out = set.add(at("d.gpkg"), "diagnostics");
  test::spit(out.take_path(), "a database");
  EXPECT_THROW(out.write(std::string("x")), OutputError);
  set.commit();
  EXPECT_EQ(files(), std::set<std::string>{"d.gpkg"});
  EXPECT_EQ(read("d.gpkg"), "a database");
  EXPECT_EQ(out.bytes_written(), 10u);
}

// What a signal handler calls before it ends the process: every temporary goes, targets stay.
TEST_F(Outputs, TemporariesCanBeRemovedFromASignalHandler) {
  put("a.txt", "old");
  OutputSet set(true);
  set.add(at("a.txt"), "a").write(std::string("new"));
  test::spit(set.add(at("d.gpkg"), "d").take_path(), "a database");
  ASSERT_EQ(files().size(), 4u);  // a.txt, two temporaries, the database
  EXPECT_TRUE(remove_temporaries_for_exit());
  EXPECT_EQ(files(), std::set<std::string>{"a.txt"});
  EXPECT_EQ(read("a.txt"), "old");
}

}  // namespace
}  // namespace tincdt::io
