// OutputSet: several outputs move into place together or not at all; OutputFile::take_path for
// writers that create their file themselves; the signal-safe removal of temporaries.
#include "io/output_set.hpp"

#include <gtest/gtest.h>
#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

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

// Files whose fsync waits for the set's one flush of the file system go in with the others, and
// one whose temporary is gone by then fails the commit, which changes nothing.
TEST_F(Outputs, FilesFlushedTogetherCommitLikeTheOthers) {
  {
    OutputSet set(false);
    for (const char* name : {"t1.terrain", "t2.terrain"}) {
      OutputFile& f = set.add(at(name), "terrain");
      f.defer_sync();
      f.write(std::string(name));
    }
    set.add(at("layer.json"), "json").write(std::string("{}"));
    set.commit();
  }
  EXPECT_EQ(files(), (std::set<std::string>{"t1.terrain", "t2.terrain", "layer.json"}));
  EXPECT_EQ(read("t2.terrain"), "t2.terrain");

  OutputSet set(true);
  OutputFile& gone = set.add(at("t1.terrain"), "terrain");
  gone.defer_sync();
  gone.write(std::string("new"));
  set.add(at("layer.json"), "json").write(std::string("new"));
  gone.close();
  ASSERT_EQ(::unlink(gone.temp_path().c_str()), 0);
  EXPECT_THROW(set.commit(), OutputError);
  EXPECT_EQ(files(), (std::set<std::string>{"t1.terrain", "t2.terrain", "layer.json"}));
  EXPECT_EQ(read("t1.terrain"), "t1.terrain");
  EXPECT_EQ(read("layer.json"), "{}");
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

// Bytes of a large file (past the size where an OutputFile stops using the page cache), written
// in pieces of odd sizes, so that the switch falls inside an aligned block.
std::string large_content() {
  std::string bytes((std::size_t{80} << 20) + 1234, '\0');
  for (std::size_t i = 0; i < bytes.size(); ++i)
    bytes[i] = static_cast<char>((i * 2654435761u) >> 13);
  return bytes;
}

void write_in_pieces(OutputFile& out, const std::string& bytes) {
  constexpr std::size_t kPieces[] = {
      1, 4095, 4097, 65537, (std::size_t{1} << 20) + 3, (std::size_t{9} << 20) + 5};
  for (std::size_t at = 0, k = 0; at < bytes.size(); ++k) {
    const std::size_t n = std::min(kPieces[k % std::size(kPieces)], bytes.size() - at);
    out.write(bytes.data() + at, n);
    at += n;
  }
}

TEST_F(Outputs, ALargeFileIsWrittenWholeWhereverItGoes) {
  const std::string bytes = large_content();
  std::vector<std::string> folders = {dir_};
  if (std::filesystem::is_directory("/dev/shm"))  // tmpfs, which may refuse O_DIRECT
    folders.push_back(test::fresh_dir("/dev/shm/tincdt_output_set_test").string());
  for (const std::string& folder : folders) {
    const std::string path = folder + "/large.bin";
    OutputFile out(path, false);
    write_in_pieces(out, bytes);
    EXPECT_EQ(out.bytes_written(), bytes.size());
    out.commit();
    EXPECT_EQ(std::filesystem::file_size(path), bytes.size()) << path;
    EXPECT_TRUE(test::slurp(path) == bytes) << path;
    std::filesystem::remove(path);
  }
  std::filesystem::remove_all("/dev/shm/tincdt_output_set_test");
}

// In place of pwrite(2) for the O_DIRECT blocks: the REFUSED-th call fails with ERROR (EINVAL: a
// file system that opens with O_DIRECT but takes no such write; ENOSPC: a full disk, for a while).
class RefusedDirectWrites {
 public:
  RefusedDirectWrites(int refused, int error) : old_(detail::direct_write()) {
    calls_ = 0;
    refused_ = refused;
    error_ = error;
    detail::direct_write() = &write;
  }
  ~RefusedDirectWrites() { detail::direct_write() = old_; }
  RefusedDirectWrites(const RefusedDirectWrites&) = delete;
  RefusedDirectWrites& operator=(const RefusedDirectWrites&) = delete;
  static int calls() { return calls_; }

 private:
  static ssize_t write(int fd, const void* data, std::size_t n, off_t offset) {
    if (++calls_ == refused_) {
      errno = error_;
      return -1;
    }
    return ::pwrite(fd, data, n, offset);
  }
  static inline std::atomic<int> calls_{0};
  static inline int refused_ = 0;
  static inline int error_ = 0;
  detail::PositionalWrite old_;
};

TEST_F(Outputs, ALargeFileWhoseDirectWritesAreRefusedGoesOnThroughTheStream) {
  const std::string bytes = large_content();
  for (const int refused : {1, 2, 3}) {
    const std::string path = at("large" + std::to_string(refused) + ".bin");
    {
      const RefusedDirectWrites refuse(refused, EINVAL);
      OutputFile out(path, false);
      write_in_pieces(out, bytes);
      out.commit();
      EXPECT_EQ(RefusedDirectWrites::calls(), refused);  // none after the first refusal
    }
    EXPECT_EQ(std::filesystem::file_size(path), bytes.size()) << refused;
    EXPECT_TRUE(test::slurp(path) == bytes) << refused;
  }
}

TEST_F(Outputs, ALargeFileWhoseDirectWriteFailsIsNeverCommitted) {
  const std::string bytes = large_content();
  {
    const RefusedDirectWrites refuse(2, ENOSPC);
    OutputFile out(at("large.bin"), false);
    EXPECT_THROW(
        {
          write_in_pieces(out, bytes);
          out.commit();
        },
        OutputError);
    try {
      out.commit();  // again: still refused, never a file with a hole
      ADD_FAILURE() << "committed after a failed write";
    } catch (const OutputError& e) {
      EXPECT_NE(std::string(e.what()).find("earlier write failed"), std::string::npos) << e.what();
    }
  }
  EXPECT_TRUE(files().empty());
}

TEST_F(Outputs, ALargeFileThatCannotBeWrittenSaysSoAndLeavesNothing) {
  const std::string bytes = large_content();
  {
    const test::FileSizeLimit limit(std::size_t{72} << 20);
    OutputFile out(at("large.bin"), false);
    try {
      write_in_pieces(out, bytes);
      out.commit();
      ADD_FAILURE() << "a file beyond the size limit was written";
    } catch (const OutputError& e) {
      EXPECT_NE(std::string(e.what()).find("large.bin"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("write failed"), std::string::npos) << e.what();
    }
  }
  EXPECT_TRUE(files().empty());
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
