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

namespace fs = std::filesystem;
using test::names_in;
using test::slurp;
using test::spit;

std::string scratch() {
  return test::scratch_dir("output_set");
}

TEST(OutputSet, CommitMovesEveryFileIntoPlace) {
  const std::string dir = scratch();
  spit(dir + "/old.txt", "old");
  OutputSet set(true);
  set.add(dir + "/old.txt", "a").write(std::string("new a"));
  set.add(dir + "/b.txt", "b").write(std::string("new b"));
  EXPECT_EQ(names_in(dir).size(), 3u);  // old.txt and two temporaries
  set.commit();
  EXPECT_TRUE(set.committed());
  EXPECT_EQ(names_in(dir), (std::set<std::string>{"old.txt", "b.txt"}));
  EXPECT_EQ(slurp(dir + "/old.txt"), "new a");
  EXPECT_EQ(slurp(dir + "/b.txt"), "new b");
}

TEST(OutputSet, DestroyedUncommittedLeavesEverythingAsItWas) {
  const std::string dir = scratch();
  spit(dir + "/a.txt", "old");
  {
    OutputSet set(true);
    set.add(dir + "/a.txt", "a").write(std::string("new"));
    set.add(dir + "/b.txt", "b").write(std::string("new"));
  }
  EXPECT_EQ(names_in(dir), std::set<std::string>{"a.txt"});
  EXPECT_EQ(slurp(dir + "/a.txt"), "old");
}

TEST(OutputSet, CancelledByTheLastCheckOrAPendingSignal) {
  const std::string dir = scratch();
  spit(dir + "/a.txt", "old");
  {
    OutputSet set(true);
    set.add(dir + "/a.txt", "a").write(std::string("new"));
    EXPECT_THROW(set.commit([] { return false; }), Cancelled);
    EXPECT_EQ(names_in(dir), std::set<std::string>{"a.txt"});  // temporaries gone at once
  }
  {
    // A SIGTERM raised by the last check is pending while the files would move: no file moves.
    const auto old_handler = std::signal(SIGTERM, [](int) {});
    OutputSet set(true);
    set.add(dir + "/a.txt", "a").write(std::string("new"));
    EXPECT_THROW(set.commit([] { return ::raise(SIGTERM) == 0; }), Cancelled);
    std::signal(SIGTERM, old_handler);
  }
  EXPECT_EQ(names_in(dir), std::set<std::string>{"a.txt"});
  EXPECT_EQ(slurp(dir + "/a.txt"), "old");
}

// The second file cannot move (its temporary vanished): the first, already in place, gets its
// old content back, and a new file that had no old content is removed again.
TEST(OutputSet, AFailedMovePutsTheOthersBack) {
  const std::string dir = scratch();
  spit(dir + "/a.txt", "old a");
  OutputSet set(true);
  set.add(dir + "/a.txt", "a").write(std::string("new a"));
  set.add(dir + "/c.txt", "c").write(std::string("new c"));
  OutputFile& b = set.add(dir + "/b.txt", "b");
  b.write(std::string("new b"));
  b.close();
  fs::remove(b.temp_path());
  EXPECT_THROW(set.commit(), OutputError);
  EXPECT_EQ(names_in(dir), std::set<std::string>{"a.txt"});
  EXPECT_EQ(slurp(dir + "/a.txt"), "old a");
}

TEST(OutputSet, ATargetThatAppearedMeanwhileIsNotReplacedWithoutOverwrite) {
  const std::string dir = scratch();
  OutputSet set(false);
  set.add(dir + "/a.txt", "a").write(std::string("new a"));
  set.add(dir + "/b.txt", "b").write(std::string("new b"));
  spit(dir + "/b.txt", "someone else's");
  EXPECT_THROW(set.commit(), OutputError);
  EXPECT_EQ(names_in(dir), std::set<std::string>{"b.txt"});
  EXPECT_EQ(slurp(dir + "/b.txt"), "someone else's");
}

TEST(OutputSet, OnePathIsOneOutput) {
  const std::string dir = scratch();
  OutputSet set(false);
  set.add(dir + "/a.txt", "tin");
  EXPECT_THROW(set.add(dir + "/a.txt", "stats"), OutputError);
}

// A writer that creates its own file (as GDAL does) at take_path(): the name keeps the target's
// extension, the file moves into place with the others, and is removed on failure with the
// SQLite journal beside it.
TEST(OutputSet, TakenPathIsTheWritersOwn) {
  const std::string dir = scratch();
  {
    OutputSet set(false);
    OutputFile& out = set.add(dir + "/d.gpkg", "diagnostics");
    const std::string file = out.take_path();
    EXPECT_EQ(fs::path(file).extension(), ".gpkg");
    EXPECT_FALSE(fs::exists(file));
    spit(file, "a database");
    spit(file + "-journal", "a journal");
  }
  EXPECT_TRUE(names_in(dir).empty());
  OutputSet set(false);
  OutputFile& out = set.add(dir + "/d.gpkg", "diagnostics");
  spit(out.take_path(), "a database");
  EXPECT_THROW(out.write(std::string("x")), OutputError);
  set.commit();
  EXPECT_EQ(names_in(dir), std::set<std::string>{"d.gpkg"});
  EXPECT_EQ(slurp(dir + "/d.gpkg"), "a database");
  EXPECT_EQ(out.bytes_written(), 10u);
}

// What a signal handler calls before it ends the process: every temporary goes, targets stay.
TEST(OutputSet, TemporariesCanBeRemovedFromASignalHandler) {
  const std::string dir = scratch();
  spit(dir + "/a.txt", "old");
  OutputSet set(true);
  set.add(dir + "/a.txt", "a").write(std::string("new"));
  spit(set.add(dir + "/d.gpkg", "d").take_path(), "a database");
  ASSERT_EQ(names_in(dir).size(), 4u);  // a.txt, two temporaries, the database
  EXPECT_TRUE(remove_temporaries_for_exit());
  EXPECT_EQ(names_in(dir), std::set<std::string>{"a.txt"});
  EXPECT_EQ(slurp(dir + "/a.txt"), "old");
}

}  // namespace
}  // namespace tincdt::io
